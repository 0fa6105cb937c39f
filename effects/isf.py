"""`isf`: runs an ISF shader (the VJ world's Interactive Shader Format: a JSON header comment,
then GLSL) over the whole stage, its inputs bound to hands, gestures and the depth image.

Supported: one pass (no PASSES targets, no persistent buffers); INPUTS of type float, long,
bool, event, color, point2D and image. ISF's GLSL dialect (gl_FragColor, texture2D,
IMG_NORM_PIXEL, IMG_PIXEL, isf_FragNormCoord, RENDERSIZE, TIME, ...) is translated to GLSL 330
with `#line` kept, so a compile error names the ISF file and its own line.

Bindings (`bind = { input = "source" }` in the profile), by input type:
- point2D: `hand.left`, `hand.right`, `hand.1`, `hand.2` (tracked hands by id), `gesture` (where
  the last gesture completed); ISF pixels, origin bottom-left. Unseen: off-stage (-1e4, -1e4).
- float: `hands` (how many are tracked), `gesture.age` / `gesture.NAME.age` (seconds since the
  last (NAME) gesture completed; 1e4 before any).
- bool, event: `gesture` / `gesture.NAME`: true on the first render after one completed.
- image: `depth` (metres in .r, 0 = no reading), `mask` (the user mask, 1 = performer).
"""
from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import moderngl
from pydantic import BaseModel, ConfigDict, Field, model_validator

from effects.gl import Offscreen, StageQuad
from host import CANONICAL_GESTURES, DepthFrame, Effect, Frame, Gesture, GestureState, Side, Stage
from host.errors import UserError
from host.options import ProfilePath

SHADERS = Path(__file__).resolve().parent / "shaders"
FAR = -1.0e4  # where an unseen hand is: far off-stage, so distance-based shaders show nothing
NEVER = 1.0e4  # seconds since a gesture that has not happened
GLSL_TYPES = {"float": "float", "long": "int", "bool": "bool", "event": "bool", "color": "vec4",
              "point2D": "vec2", "image": "sampler2D"}

PRELUDE = """#version 330
uniform vec2 RENDERSIZE;
uniform float TIME;
uniform float TIMEDELTA;
uniform int FRAMEINDEX;
uniform int PASSINDEX;
uniform vec4 DATE;
in vec2 isf_FragNormCoord;
out vec4 isf_FragColor;
#define IMG_NORM_PIXEL(img, coord) texture(img, coord)
#define IMG_PIXEL(img, coord) texture(img, (coord) / vec2(textureSize(img, 0)))
#define IMG_THIS_NORM_PIXEL(img) texture(img, isf_FragNormCoord)
#define IMG_THIS_PIXEL(img) texture(img, isf_FragNormCoord)
#define IMG_SIZE(img) vec2(textureSize(img, 0))
"""
# The ISF main runs first; ours makes its straight alpha premultiplied, as the stage expects.
EPILOGUE = "\nvoid main() { isf_main(); isf_FragColor = vec4(isf_FragColor.rgb * isf_FragColor.a, isf_FragColor.a); }\n"
DIALECT = [(re.compile(r"\bgl_FragColor\b"), "isf_FragColor"), (re.compile(r"\btexture2D\b"), "texture"),
           (re.compile(r"\bvarying\b"), "in"), (re.compile(r"\bvoid\s+main\s*\("), "void isf_main(")]
COMPILER_LINE = re.compile(r"^\s*\d+:(\d+)\(\d+\):\s*(.*)$|^\s*ERROR:\s*\d+:(\d+):\s*(.*)$")


class IsfOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    shader: str | None = Field(None, description="a shipped shader: " + ", ".join(
        sorted(p.stem for p in SHADERS.glob("*.fs"))))
    file: ProfilePath | None = Field(None, description="an ISF .fs file of your own")
    bind: dict[str, str] = Field(default_factory=dict, description="ISF input name -> hands/gestures/depth")
    values: dict[str, float | bool | list[float]] = Field(default_factory=dict, description="fixed input values")
    scale: float = Field(1.0, gt=0, le=1, description="render resolution, fraction of the output: a heavy, "
                         "soft shader looks the same at 0.5 for a quarter of the work (plus one stretch pass)")

    @model_validator(mode="after")
    def _one_shader(self) -> "IsfOptions":
        if (self.shader is None) == (self.file is None):
            raise ValueError("give exactly one of `shader` (a shipped one) or `file` (an ISF .fs path)")
        if self.shader is not None and not (SHADERS / f"{self.shader}.fs").is_file():
            known = ", ".join(sorted(p.stem for p in SHADERS.glob("*.fs")))
            raise ValueError(f"no shipped ISF shader {self.shader!r}; expected one of {known}")
        try:  # the header and the bindings are checked with the profile (`issv check`)
            check_bindings(IsfShader(self.path), self.bind, self.values)
        except IsfError as error:
            raise ValueError(str(error)) from None
        return self

    @property
    def path(self) -> Path:
        return Path(self.file) if self.file is not None else SHADERS / f"{self.shader}.fs"


class IsfError(UserError):
    """An ISF file that cannot run: the message names the file (and line when there is one)."""


class IsfShader:
    """An ISF file parsed: its inputs and the GLSL 330 fragment shader made from it."""

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise IsfError(f"{path}: cannot read the ISF shader: {error}") from None
        match = re.match(r"\s*/\*", text)
        end = text.find("*/")
        if not match or end < 0:
            raise IsfError(f"{path}:1: an ISF shader starts with its JSON header in a /* ... */ comment")
        header_start = match.end()
        try:
            self.header = json.loads(text[header_start:end])
        except json.JSONDecodeError as error:
            line = text.count("\n", 0, header_start) + error.lineno
            raise IsfError(f"{path}:{line}: the ISF header is not valid JSON: {error.msg}") from None
        if not isinstance(self.header, dict):
            raise IsfError(f"{path}:1: the ISF header must be a JSON object")
        passes = self.header.get("PASSES") or [{}]
        if len(passes) > 1 or any(k in passes[0] for k in ("TARGET", "PERSISTENT")):
            raise IsfError(f"{path}: only single-pass ISF shaders are supported (PASSES has {len(passes)} "
                           "entries or a TARGET)")
        self.inputs = self._inputs(self.header.get("INPUTS", []))
        body_line = text.count("\n", 0, end + 2) + 1  # the body starts on the line the header ends
        body = text[end + 2:]
        for pattern, repl in DIALECT:
            body = pattern.sub(repl, body)
        if "isf_main(" not in body:
            raise IsfError(f"{path}: the shader has no `void main()`")
        uniforms = "".join(f"uniform {GLSL_TYPES[t]} {n};\n" for n, t in self.inputs.items())
        # `#line` makes the compiler count lines as the ISF file does.
        self.fragment = f"{PRELUDE}{uniforms}#line {body_line}\n{body}{EPILOGUE}"

    def _inputs(self, inputs: Any) -> dict[str, str]:
        out: dict[str, str] = {}
        self.defaults: dict[str, Any] = {}
        for entry in inputs if isinstance(inputs, list) else []:
            name, kind = entry.get("NAME"), entry.get("TYPE")
            if not isinstance(name, str) or kind not in GLSL_TYPES:
                raise IsfError(f"{self.path}: ISF input {entry!r}: expected a NAME and a TYPE among "
                               f"{', '.join(GLSL_TYPES)}")
            out[name] = kind
            if "DEFAULT" in entry:
                self.defaults[name] = entry["DEFAULT"]
        return out

    def compile(self, ctx: moderngl.Context) -> StageQuad:
        try:
            return StageQuad(ctx, self.fragment, uv_name="isf_FragNormCoord")
        except moderngl.Error as error:
            raise IsfError(self._explain(str(error))) from None

    def _explain(self, log: str) -> str:
        """The driver's log as `FILE:LINE: message` lines (the first one first)."""
        found = []
        for raw in log.splitlines():
            m = COMPILER_LINE.match(raw)
            if m:
                line, msg = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
                found.append(f"{self.path}:{line}: {msg.strip()}")
        if not found:
            return f"{self.path}: the shader does not compile: {log.strip()}"
        return "; ".join(found[:3])


class Isf(Effect):
    name = "isf"
    Options = IsfOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.shader = IsfShader(self.options.path)  # again: live reload may have changed the file
        check_bindings(self.shader, self.options.bind, self.options.values)
        ctx = stage.ctx
        self.quad = self.shader.compile(ctx)
        self.prog = self.quad.prog
        self.offscreen = Offscreen(ctx, stage.size, self.options.scale) if self.options.scale < 1 else None
        self.blank = ctx.texture((1, 1), 1, dtype="f4")
        self.hands: dict[str, tuple[float, float]] = {}
        self.count = 0
        self.depth: DepthFrame | None = None
        self.last: dict[str, tuple[float, tuple[float, float] | None]] = {}  # name -> (time, where)
        self.fired: set[str] = set()
        self.frames = 0
        for name, value in {**self.shader.defaults, **self.options.values}.items():
            self._set(name, value)

    def _set(self, name: str, value: Any) -> None:
        uniform, kind = self.prog.get(name, None), self.shader.inputs.get(name)
        if uniform is None or kind == "image":
            return  # unused by the shader (the compiler dropped it), or an image bound at render
        if kind in ("bool", "event"):
            value = bool(value)
        elif kind == "long":
            value = int(value)
        elif kind in ("color", "point2D"):
            value = tuple(float(v) for v in value)
        uniform.value = value

    def on_frame(self, frame: Frame) -> None:
        if frame.depth is None:
            return
        self.depth = frame.depth
        live = sorted((h for h in frame.hands if h.in_view
                       and h.position[2] > 0), key=lambda h: h.id)
        self.count = len(live)
        self.hands = {}
        for i, hand in enumerate(live):
            where = self.stage.to_stage(hand.position, frame.depth)
            self.hands[f"hand.{i + 1}"] = where
            if hand.side is not Side.UNKNOWN:
                self.hands[f"hand.{hand.side.value}"] = where

    def on_gesture(self, gesture: Gesture) -> None:
        if gesture.state is not GestureState.COMPLETE:
            return
        where = self.stage.to_stage(gesture.position, self.depth) if self.depth and gesture.position[2] > 0 else None
        for key in ("gesture", f"gesture.{gesture.name}"):
            self.last[key] = (-1.0, where)  # stamped with the render time at the next render
            self.fired.add(key)

    def _value(self, kind: str, source: str, now: float) -> Any:
        h = self.stage.size[1]
        if kind == "point2D":
            if source == "gesture":
                where = self.last.get("gesture", (0, None))[1]
            else:
                where = self.hands.get(source)
            return (FAR, FAR) if where is None else (where[0], h - where[1])
        if source == "hands":
            return float(self.count)
        if kind in ("bool", "event"):
            return source in self.fired
        key = source.removesuffix(".age")
        return now - self.last[key][0] if key in self.last else NEVER

    def render(self, target) -> None:
        for key, (t, where) in self.last.items():
            if t < 0:
                self.last[key] = (target.time, where)
        prog = self.prog
        for name, value in (("RENDERSIZE", tuple(float(v) for v in target.size)), ("TIME", target.time),
                            ("TIMEDELTA", target.dt), ("FRAMEINDEX", self.frames)):
            if prog.get(name, None) is not None:
                prog[name].value = value
        unit = 0
        for name, kind in self.shader.inputs.items():
            source = self.options.bind.get(name)
            if kind == "image":
                texture = {"depth": target.depth_texture, "mask": target.mask_texture}.get(source, lambda: None)()
                (texture or self.blank).use(unit)
                if prog.get(name, None) is not None:
                    prog[name].value = unit
                unit += 1
            elif source is not None:
                self._set(name, self._value(kind, source, target.time))
        self.fired.clear()
        self.frames += 1
        if self.offscreen is None:
            self.quad.draw(target)
            return
        self.offscreen.begin()
        self.quad.draw(self.offscreen)
        target.use()
        self.offscreen.draw(target)

    def close(self) -> None:
        for name in ("quad", "blank", "offscreen"):
            if getattr(self, name, None) is not None:
                getattr(self, name).release()


def check_bindings(shader: IsfShader, bind: dict[str, str], values: dict[str, Any]) -> None:
    """Every bound or set input exists, and each binding suits its input's type."""
    inputs, path = shader.inputs, shader.path
    for name in {**bind, **values}:
        if name not in inputs:
            raise IsfError(f"{path}: has no input {name!r} to bind or set (inputs: {', '.join(inputs) or 'none'})")
    for name, source in bind.items():
        if not _valid_source(inputs[name], source):
            raise IsfError(f"{path}: input {name!r} ({inputs[name]}) cannot be bound to {source!r}; "
                           "see the isf effect's bindings in the README")


def _valid_source(kind: str, source: str) -> bool:
    gestures = {"gesture"} | {f"gesture.{g}" for g in CANONICAL_GESTURES}
    if kind == "point2D":
        return source in {"hand.left", "hand.right", "hand.1", "hand.2", "gesture"}
    if kind in ("float", "long"):
        return source == "hands" or source.removesuffix(".age") in gestures and source.endswith(".age")
    if kind in ("bool", "event"):
        return source in gestures
    if kind == "image":
        return source in ("depth", "mask")
    return False
