"""An ISF file read: its header, and the GLSL 330 fragment and vertex shaders made from it and
from its companion `.vs` (same name, next to it) when there is one."""
from __future__ import annotations

from pathlib import Path

import moderngl

from effects.isf.glsl import explain, fragment_source, vertex_source
from effects.isf.header import Input, IsfError, parse_header

LAX_VERSION = 420


class IsfShader:
    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        text = _read(self.path)
        self.header = parse_header(self.path, text)
        self.inputs: dict[str, str] = {i.name: i.type for i in self.header.inputs}
        self.defaults = {i.name: i.default for i in self.header.inputs if i.default is not None}
        self.fragment = fragment_source(self.path, text, self.header)
        vs = self.path.with_suffix(".vs")
        self.vertex_path = vs if vs.is_file() else None
        self.vertex = vertex_source(_read(vs) if self.vertex_path else None, self.header)
        for name, image in self.header.imported.items():
            if not image.is_file():
                raise IsfError(f"{self.path}: IMPORTED image {name!r} not found at {image}; put it next to the shader")

    @property
    def kind(self) -> str:
        return self.header.kind

    def input(self, name: str) -> Input:
        return next(i for i in self.header.inputs if i.name == name)

    def program(self, ctx: moderngl.Context) -> moderngl.Program:
        """GLSL 330; where that fails and the driver has 4.2 (Mesa, desktop GPUs), 4.2 again: it
        converts int to uint and return values implicitly, as the lax compilers shaders were
        written on did. An error names the 330 compile's first lines."""
        try:
            return ctx.program(vertex_shader=self.vertex, fragment_shader=self.fragment)
        except moderngl.Error as error:
            first = str(error)
        if ctx.version_code >= LAX_VERSION:
            try:
                return ctx.program(vertex_shader=lax(self.vertex), fragment_shader=lax(self.fragment))
            except moderngl.Error:
                pass
        in_vertex = "vertex_shader\n" in first and self.vertex_path is not None
        raise IsfError(explain(self.vertex_path if in_vertex else self.path, first))


def lax(source: str) -> str:
    return source.replace("#version 330\n", f"#version {LAX_VERSION}\n", 1)


def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8-sig", errors="replace")  # -sig: a BOM some editors write
    except OSError as error:
        raise IsfError(f"{path}: cannot read the ISF shader: {error}") from None
