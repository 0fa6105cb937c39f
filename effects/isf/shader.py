"""An ISF file read: its header, and the GLSL 330 fragment and vertex shaders made from it and
from its companion `.vs` (same name, next to it) when there is one."""
from __future__ import annotations

from pathlib import Path

import moderngl

from effects.isf.glsl import PASSINDEX_UNIFORM, explain, fragment_source, vertex_source
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

    @property
    def branches_on_pass(self) -> bool:
        """Several passes told apart by PASSINDEX: each pass is then a program of its own."""
        return len(self.header.passes) > 1 and "PASSINDEX" in self.fragment + self.vertex

    def program(self, ctx: moderngl.Context, pass_index: int | None = None) -> moderngl.Program:
        """GLSL 330; where that fails and the driver has 4.2 (Mesa, desktop GPUs), 4.2 again: it
        converts int to uint and return values implicitly, as the lax compilers shaders were
        written on did. An error names the 330 compile's first lines.

        With `pass_index`, PASSINDEX is that constant rather than a uniform, so the compiler
        drops the other passes' branches: a CPU rasteriser (llvmpipe) runs both sides of a
        branch, so one program for all passes pays every pass's texture reads in each."""
        vertex, fragment = (self.vertex, self.fragment) if pass_index is None else \
            (specialise(self.vertex, pass_index), specialise(self.fragment, pass_index))
        try:
            return ctx.program(vertex_shader=vertex, fragment_shader=fragment)
        except moderngl.Error as error:
            first = str(error)
        if ctx.version_code >= LAX_VERSION:
            try:
                return ctx.program(vertex_shader=lax(vertex), fragment_shader=lax(fragment))
            except moderngl.Error:
                pass
        in_vertex = "vertex_shader\n" in first and self.vertex_path is not None
        raise IsfError(explain(self.vertex_path if in_vertex else self.path, first))


def specialise(source: str, pass_index: int) -> str:
    return source.replace(PASSINDEX_UNIFORM, f"#define PASSINDEX {pass_index}\n", 1)


def lax(source: str) -> str:
    return source.replace("#version 330\n", f"#version {LAX_VERSION}\n", 1)


def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8-sig", errors="replace")  # -sig: a BOM some editors write
    except OSError as error:
        raise IsfError(f"{path}: cannot read the ISF shader: {error}") from None
