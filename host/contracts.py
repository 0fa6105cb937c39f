"""What a source, a backend and an effect are: the hot spots of the framework (thesis ch. 3.2).

Plugins subclass these and hand the classes to `register(...)` in their hook implementations.
Every class has a `name` (what profiles say) and an `Options` pydantic model (what profiles may
set); `availability()` says, without raising, whether it can run here and if not how to fix it.
Optional capabilities that host commands use are declared here too, with their defaults (a
backend's `dictionary` and `recognizer`, `for_recording` on sources and backends): commands never
probe plugins for undeclared attributes. See docs/architecture.md, Contracts.
"""
from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, ClassVar, Literal, Protocol

from pydantic import BaseModel, ConfigDict

from host.model import DepthFrame, Frame, Gesture, Hand, Intrinsics, Vec3
from host.render import calibration


class NoOptions(BaseModel):
    """Options of a plugin that takes none: anything set in the profile is an error."""

    model_config = ConfigDict(extra="forbid")


class PluginUnavailable(RuntimeError):
    """A plugin cannot run here; the message says what is missing and how to get it."""


class Plugin:
    """Common to sources, backends and effects: a name, validated options, availability."""

    name: ClassVar[str] = ""
    Options: ClassVar[type[BaseModel]] = NoOptions

    def __init__(self, options: BaseModel | None = None) -> None:
        self.options = options if options is not None else self.Options()

    @classmethod
    def availability(cls) -> str | None:
        """None when this plugin can run here; otherwise why not and how to fix it."""
        return None


@dataclass(frozen=True)
class DeviceInfo:
    """A camera a source can open, as `issv list` names it; `problem` says why it cannot be opened here."""

    model: str
    serial: str = ""
    firmware: str = ""
    modes: tuple[str, ...] = ()
    problem: str | None = None


class Source(Plugin):
    """Where depth comes from. `read()` returns the next frame, or None at the end of the stream.

    A source that is not `live` (a clip, the synthetic performer) is paced by the host from its
    frames' timestamps; a live one (a camera) blocks in `read()` until the device delivers.
    """

    fps: float = 30.0
    live: ClassVar[bool] = False
    #: what `read()` gives: "depth" (DepthFrame, millimetres) or "colour" (an RGB camera's frames)
    frames: ClassVar[str] = "depth"
    intrinsics: Intrinsics

    @classmethod
    def for_recording(cls, path: Path, seek: float = 0.0) -> "Source | None":
        """Capability: a source of an issv recording's depth images from `seek` seconds on, looping
        off (`issv compare` feeds every backend from it), or None when this source cannot."""
        return None

    @classmethod
    def devices(cls) -> list[DeviceInfo] | None:
        """Cameras connected now (an empty list: none); None for sources that read files."""
        return None

    def health(self) -> str | None:
        """One line for the HUD from a live source: its device's own rate, dropped frames, state."""
        return None

    def open(self) -> None:
        """Acquire the device or file."""

    def read(self) -> DepthFrame | None:
        raise NotImplementedError

    def close(self) -> None:
        """Release the device or file."""


class Recognizer(Protocol):
    """A gesture recogniser that runs on any stream of hand positions (the open engine's)."""

    def update(self, t: float, hands: Sequence[Hand], body: Mapping[str, Vec3] | None = None,
               mirrored: bool = True) -> list[Gesture]:
        """Gesture events at time `t` (seconds) from these hands and body points (mm)."""

    def finish(self) -> list[Gesture]:
        """The stream ended: gestures still being confirmed, now complete."""


#: What `Backend.update()` answers: the next frame; None once the source ended; False while nothing came yet.
Update = Frame | None | Literal[False]


class Backend(Plugin):
    """A gesture provider: the OIGestureTracker contract (thesis Fig. 31) in Python form.

    The host calls `init()`, the start methods, then `update()` on its sensor thread until it
    returns None (the source ended), then `finish()` and `stop()`. A backend fed by a live input
    that may be silent (a network publisher not started yet) returns False when nothing came
    within a fraction of a second, so that the host can keep its time limits and stop requests;
    code that reads a backend itself takes its frames through `frames_of`. Backends that compute
    from depth read their `source`; others (network, replay) make frames of their own and take
    `source=None`.
    """

    needs_source: ClassVar[bool] = True
    #: Capability: the gestures it can report, canonical name -> its native name or type
    #: (`issv compare` reports it); None: not declared.
    dictionary: ClassVar[Mapping[str, Any] | None] = None
    #: Capability: a backend whose gestures come from a recogniser that runs on any stream of hand
    #: positions overrides this with `@classmethod recognizer(cls, options=None) -> Recognizer`
    #: (`options`: its validated Options, None for the defaults); `issv gestures` runs it on
    #: hand-trajectory files. None: it has none.
    recognizer: ClassVar[Callable[..., Recognizer] | None] = None
    #: the frames it tracks, as a Source's `frames` says ("depth" or "colour"); a profile pairing
    #: it with a source of the other kind is refused. Unused when `needs_source` is False.
    takes: ClassVar[str] = "depth"

    def __init__(self, source: Source | None = None, options: BaseModel | None = None) -> None:
        super().__init__(options)
        self.source = source
        self.detecting_gestures = False
        self.tracking_hands = False

    @classmethod
    def for_recording(cls, path: Path) -> "Backend | None":
        """Capability: for a backend that makes its frames from an issv recording itself (not from
        a source): one that plays `path` as fast as possible (`issv compare`); None otherwise."""
        return None

    def init(self) -> None:
        if self.source is not None:
            self.source.open()

    def start_gesture_detection(self) -> None:
        self.detecting_gestures = True

    def stop_gesture_detection(self) -> None:
        self.detecting_gestures = False

    def start_hand_tracking(self) -> None:
        self.tracking_hands = True

    def stop_hand_tracking(self) -> None:
        self.tracking_hands = False

    def update(self) -> Update:
        raise NotImplementedError

    def finish(self) -> tuple[Gesture, ...]:
        """After `update()` returned None: gestures the backend was still confirming when the
        source ended, now complete (a swipe in a clip's last quarter second). Default: none."""
        return ()

    def stop(self) -> None:
        self.stop_gesture_detection()
        self.stop_hand_tracking()
        if self.source is not None:
            self.source.close()

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        """convertHandCoordinatesToDepth: mm -> (u, v, z) in the source's depth image."""
        if self.source is None:
            raise PluginUnavailable(f"backend {self.name!r} has no depth source to project into")
        return self.source.intrinsics.world_to_depth(*position)

    def __enter__(self) -> "Backend":
        self.init()
        self.start_hand_tracking()
        self.start_gesture_detection()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


def frames_of(backend: Backend) -> Iterator[Frame]:
    """A backend's frames until its source ends, past its "nothing yet" (False) answers: for code
    that reads a backend outside the frame loop and has no limits to check between frames."""
    while (frame := backend.update()) is not None:
        if frame is not False:
            yield frame


@dataclass
class Stage:
    """What an effect gets in `setup`: the output it draws for and the host's state.

    `ctx` is the moderngl context (None when the show renders nothing); `size` is the output size
    in pixels; `metrics` is the live Metrics object (read-only for effects); `calibration` the
    profile's camera-to-stage homography (None: the depth image is stretched over the output).
    """

    size: tuple[int, int]
    fps: float
    backend: str
    ctx: Any = None
    metrics: Any = None
    extra: dict[str, Any] = field(default_factory=dict)
    calibration: Any = None

    def to_stage(self, position: Vec3, depth: DepthFrame) -> tuple[float, float]:
        """Where a camera point (mm) seen in `depth` lands on the output, in pixels from the top-left."""
        return calibration.project(position, depth, self.size, self.calibration)

    def depth_to_stage(self, depth: DepthFrame) -> Any:
        """The 3x3 homography from `depth`'s pixels to output pixels (to draw depth images in place)."""
        return calibration.depth_to_stage_matrix((depth.width, depth.height), self.size, self.calibration)


class Effect(Plugin):
    """A visual or sound effect. Override only the hooks you need.

    Gesture events arrive through `on_gesture` exactly once each, in order; `on_frame` gets the
    newest frame (hands may skip frames, gestures never do). Render effects set `renders = True`
    and draw their layer in `render`; those that place every vertex through `target.to_clip`
    set `keystone_aware = True` and the keystone costs no extra pass.
    """

    renders: ClassVar[bool] = False
    keystone_aware: ClassVar[bool] = False

    def setup(self, stage: Stage) -> None:
        self.stage = stage

    def on_gesture(self, gesture: Gesture) -> None:
        pass

    def on_frame(self, frame: Frame) -> None:
        pass

    def render(self, target: Any) -> None:
        pass

    def close(self) -> None:
        pass
