"""`isf`: runs an ISF 2.0 shader (the VJ world's Interactive Shader Format) on the stage, its
inputs bound to hands, gestures, time, sound, the depth image or the show drawn so far.

Bindings (`bind = { input = "source" }` in the profile), by input type:
- point2D: `hand.left`, `hand.right`, `hand.1`, `hand.2` (tracked hands by id), `gesture` (where
  the last gesture completed); ISF pixels, origin bottom-left (unseen: off-stage, -1e4), or, for
  a point with MIN/MAX, a point in that range (e.g. 0..1; unseen: it stays where it was).
- float/long: `hands` (how many are tracked), `gesture.age` / `gesture.NAME.age` (seconds since
  the last (NAME) gesture completed; 1e4 before any), `hand.left.x` ... `hand.2.y` (where the hand
  is across the stage, 0..1 from the left/bottom, mapped onto the input's MIN..MAX), `time.N`
  (a triangle wave MIN -> MAX -> MIN over N seconds), `gesture.toggle` / `gesture.NAME.toggle`
  (each such gesture turns MIN into MAX or back, in one second), `audio.level`.
- bool, event: `gesture` / `gesture.NAME`: true on the first render after one completed.
- image: `below` (everything composited below this layer: the default for inputImage and
  startImage, so a filter applies to the show so far), `depth` (metres in .r), `mask` (the user
  mask), `layers.N` / `layers.N-M` (effects N..M of the profile, drawn apart and not on the stage:
  a transition's endImage).
- audio, audioFFT: `audio` (the show's sound, the default).
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from effects.isf.header import IMAGE_TYPES, IsfError
from effects.isf.passes import Buffer, IsfRenderer, Output, clip_on
from effects.isf.shader import IsfShader
from effects.isf.sound import SoundTextures
from host import CANONICAL_GESTURES, DepthFrame, Effect, Frame, Gesture, GestureState, Side, Stage
from host.options import ProfilePath

SHADERS = Path(__file__).resolve().parent.parent / "shaders"
FAR = -1.0e4  # where an unseen hand is: far off-stage, so distance-based shaders show nothing
NEVER = 1.0e4  # seconds since a gesture that has not happened
HANDS = ("hand.left", "hand.right", "hand.1", "hand.2")
LAYERS = re.compile(r"^layers\.(\d+)(?:-(\d+))?$")
DEFAULT_IMAGE = {"inputImage": "below", "startImage": "below"}
TOGGLE_SECONDS = 1.0


def shipped() -> list[str]:
    """The shaders issv ships, by name (`vidvox/...`: from the Vidvox collection, MIT licence)."""
    return sorted(str(p.relative_to(SHADERS).with_suffix("")) for p in SHADERS.rglob("*.fs"))


class IsfOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    shader: str | None = Field(None, description="a shipped shader: " + ", ".join(shipped()))
    file: ProfilePath | None = Field(None, description="an ISF .fs file of your own")
    bind: dict[str, str] = Field(default_factory=dict, description="ISF input name -> hands/gestures/depth/below")
    values: dict[str, float | bool | list[float]] = Field(default_factory=dict, description="fixed input values")
    scale: float = Field(1.0, gt=0, le=1, description="render resolution, fraction of the output: a heavy, "
                         "soft shader looks the same at 0.5 for a quarter of the work (plus one stretch pass)")

    @model_validator(mode="after")
    def _one_shader(self) -> "IsfOptions":
        if (self.shader is None) == (self.file is None):
            raise ValueError("give exactly one of `shader` (a shipped one) or `file` (an ISF .fs path)")
        if self.shader is not None and not (SHADERS / f"{self.shader}.fs").is_file():
            known = ", ".join(shipped())
            raise ValueError(f"no shipped ISF shader {self.shader!r}; expected one of {known}")
        try:  # the header and the bindings are checked with the profile (`issv check`)
            check_bindings(IsfShader(self.path), self.bind, self.values)
        except IsfError as error:
            raise ValueError(str(error)) from None
        return self

    @property
    def path(self) -> Path:
        return Path(self.file) if self.file is not None else SHADERS / f"{self.shader}.fs"


class Isf(Effect):
    name = "isf"
    Options = IsfOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.shader = IsfShader(self.options.path)  # again: live reload may have changed the file
        check_bindings(self.shader, self.options.bind, self.options.values)
        self.sources = image_sources(self.shader, self.options.bind)
        # The show below and layer groups are read as drawn: the keystone is then one warp pass.
        self.keystone_aware = not any(stage_sized(s) for s in self.sources.values())
        ctx = stage.ctx
        self.runner = IsfRenderer(ctx, self.shader)
        # Only a shader that compiled hides the layers it reads from the stage.
        self.captures = tuple(layer_range(s) for s in self.sources.values() if LAYERS.match(s))
        self.sound = SoundTextures(ctx, lambda: stage.extra.get("audio"))
        self.offscreen = None
        if self.options.scale < 1:
            w, h = stage.size
            scale = self.options.scale
            self.offscreen = Buffer(ctx, (max(1, round(w * scale)), max(1, round(h * scale))), False)
        self.values: dict[str, Any] = {**self.shader.defaults, **self.options.values}
        self.hands: dict[str, tuple[float, float]] = {}
        self.count = 0
        self.depth: DepthFrame | None = None
        self.last: dict[str, tuple[float, tuple[float, float] | None]] = {}  # name -> (time, where)
        self.toggles: dict[str, tuple[float, bool]] = {}  # name -> (time, on)
        self.fired: set[str] = set()

    def on_frame(self, frame: Frame) -> None:
        if frame.depth is None:
            return
        self.depth = frame.depth
        live = sorted((h for h in frame.hands if h.in_view and h.position[2] > 0), key=lambda h: h.id)
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
            on = self.toggles.get(key, (0.0, False))[1]
            self.toggles[key] = (-1.0, not on)

    def _point(self, name: str, source: str) -> tuple[float, float]:
        """A point2D input: the hand's or the last gesture's place, in MIN..MAX when the shader gives
        them, else in the render's pixels (far away while nothing is there)."""
        w, h = self.stage.size
        where = self.last.get("gesture", (0, None))[1] if source == "gesture" else self.hands.get(source)
        item = self.shader.input(name)
        if isinstance(item.maximum, list) and len(item.maximum) == 2:  # a point in MIN..MAX, e.g. 0..1
            lo = item.minimum if isinstance(item.minimum, list) and len(item.minimum) == 2 else (0.0, 0.0)
            if where is None:
                return self.values.get(name, item.default)  # an unseen hand leaves it where it was
            return tuple(a + (b - a) * t for a, b, t in zip(lo, item.maximum, (where[0] / w, 1.0 - where[1] / h)))
        k = self.options.scale  # ISF pixels are the render's, smaller at a lower scale
        return (FAR, FAR) if where is None else (where[0] * k, (h - where[1]) * k)

    def _value(self, name: str, kind: str, source: str, now: float) -> Any:
        if kind == "point2D":
            return self._point(name, source)
        if kind in ("bool", "event"):
            return source in self.fired
        if source == "hands":
            return float(self.count)
        if source == "audio.level":
            return self.sound.level()
        if source.endswith(".age"):
            key = source.removesuffix(".age")
            return now - self.last[key][0] if key in self.last else NEVER
        item = self.shader.input(name)
        lo = float(item.minimum) if isinstance(item.minimum, (int, float)) else 0.0
        hi = float(item.maximum) if isinstance(item.maximum, (int, float)) else 1.0
        if source.endswith((".x", ".y")):
            where = self.hands.get(source[:-2])
            if where is None:
                return self.values.get(name, lo)  # an unseen hand leaves the value where it was
            w, h = self.stage.size
            t = where[0] / w if source.endswith(".x") else 1.0 - where[1] / h
        elif source.startswith("time."):
            period = float(source[5:])
            t = 1.0 - abs((now / period) % 2.0 - 1.0)
        else:  # gesture[.NAME].toggle: MIN until the first such gesture
            start, on = self.toggles.get(source.removesuffix(".toggle"), (now - TOGGLE_SECONDS, False))
            ramp = (now - start) / TOGGLE_SECONDS
            t = ramp if on else 1.0 - ramp
        t = min(1.0, max(0.0, t))
        return lo + (hi - lo) * t if kind == "float" else int(round(lo + (hi - lo) * t))

    def render(self, target) -> None:
        now = target.time
        for table in (self.last, self.toggles):
            for key, (t, extra) in table.items():
                if t < 0:
                    table[key] = (now, extra)
        for name, source in self.options.bind.items():
            kind = self.shader.inputs[name]
            if kind not in IMAGE_TYPES:
                self.values[name] = self._value(name, kind, source, now)
        images = {name: self._image(target, name, source) for name, source in self.sources.items()}
        self.fired.clear()
        if self.offscreen is None:
            output = Output(target.use, target.size, clip_on(target.to_clip, target.size))
            self.runner.draw(self.values, images, output, now, target.dt)
            return
        small = self.offscreen  # a heavy shader at `scale`, then stretched onto the stage
        # The show below is seen at the shader's size: IMG_PIXEL(inputImage, gl_FragCoord.xy) reads
        # the whole stage, not its lower-left corner (linear sampling does the shrinking).
        sizes = {name: small.size for name in images if stage_sized(self.sources[name])}
        small.draw_into().clear(0.0, 0.0, 0.0, 0.0)
        self.runner.draw(self.values, images, Output(small.bind, small.size), now, target.dt, sizes)
        small.swap()
        target.use()
        self.runner.show(small.current, Output(target.use, target.size, clip_on(target.to_clip, target.size)),
                         premultiplied=True)

    def _image(self, target, name: str, source: str):
        kind = self.shader.inputs[name]
        if kind in ("audio", "audioFFT"):
            return self.sound.texture(kind, self.shader.input(name).samples)
        if source == "below":
            return target.below()
        if source == "depth":
            return target.depth_texture()
        if source == "mask":
            return target.mask_texture()
        match = LAYERS.match(source)
        return target.layers(*layer_range(source)) if match else None

    def close(self) -> None:
        for name in ("runner", "sound", "offscreen"):
            if getattr(self, name, None) is not None:
                getattr(self, name).release()


def stage_sized(source: str) -> bool:
    """The show below or a layer group: an image the size of the stage."""
    return source == "below" or bool(LAYERS.match(source))


def layer_range(source: str) -> tuple[int, int]:
    match = LAYERS.match(source)
    first = int(match.group(1))
    return first, int(match.group(2) or first)


def image_sources(shader: IsfShader, bind: dict[str, str]) -> dict[str, str]:
    """Each image-like input's source: bound, else `below` for inputImage/startImage, audio for sound."""
    out = {}
    for name, kind in shader.inputs.items():
        if kind in ("audio", "audioFFT"):
            out[name] = "audio"
        elif kind == "image":
            out[name] = bind.get(name) or DEFAULT_IMAGE.get(name) or "none"
    return out


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
        return source in {*HANDS, "gesture"}
    if kind in ("float", "long"):
        return (source in {"hands", "audio.level"} or any(source == f"{g}.age" or source == f"{g}.toggle"
                                                           for g in gestures)
                or any(source == f"{h}.{axis}" for h in HANDS for axis in "xy")
                or bool(re.fullmatch(r"time\.\d+(\.\d+)?", source)) and float(source[5:]) > 0)
    if kind in ("bool", "event"):
        return source in gestures
    if kind == "image":
        return source in ("depth", "mask", "below") or bool(LAYERS.match(source))
    if kind in ("audio", "audioFFT"):
        return source == "audio"
    return False
