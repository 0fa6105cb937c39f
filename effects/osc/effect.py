"""`osc`: hands and gestures to Max, Pure Data, or anything that speaks OSC over UDP.

The two paths stay apart (docs/architecture.md): hands go out once per frame as one bundle (rate-limited
if asked, newest frame wins); every gesture event goes out on its own the moment the show loop
hands it over, never rate-limited. Nothing here waits on the network (destinations.py).
"""
from __future__ import annotations

import time
from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, field_validator, model_validator

from host import CANONICAL_GESTURES, Effect, Frame, Gesture, GestureType, Hand, Stage

from effects.osc.coords import Projector, Space
from effects.osc.destinations import Address, Destination, Warn, warn_stderr
from effects.osc.keepalive import KeepAlive
from effects.osc.osceleton import OSCELETON_TEXT, OSCeletonScheme
from effects.osc.presets import TEMPLATE_TEXT, Template, TemplateScheme
from effects.osc.synapse import SYNAPSE_TEXT, SynapseScheme
from effects.osc.schema import DEFAULT_PREFIX, SCHEMA_TEXT, IssvScheme, Scheme
from host.osc import Message, encode, encode_bundle

SCHEMES = {"issv": IssvScheme, "osceleton": OSCeletonScheme}
DEFAULT_DESTINATION = {"issv": "127.0.0.1:9000", "osceleton": "127.0.0.1:7110", "synapse": "127.0.0.1:12345",
                       "custom": "127.0.0.1:9000"}
SCHEME_TEXT = {"issv": SCHEMA_TEXT, "osceleton": OSCELETON_TEXT, "synapse": SYNAPSE_TEXT, "custom": TEMPLATE_TEXT}
RESOLVE_WAIT = 1.0  # seconds setup waits for host names; slower ones join when resolved


def _host_port(text: str) -> str:
    Address.parse(text)  # raises with what is wrong
    return text


HostPort = Annotated[str, AfterValidator(_host_port)]


class OscOptions(BaseModel):
    """What a profile may set for the `osc` effect (README.md, OSC)."""

    model_config = ConfigDict(extra="forbid")
    destinations: list[HostPort] | None = None  # "host:port"; default: the scheme's usual port
    scheme: Literal["issv", "osceleton", "synapse", "custom"] = "issv"
    prefix: str | None = None  # prepended to the scheme's addresses; default /issv for issv, none for presets
    space: Space = "mm"
    depth_range: tuple[float, float] = (500.0, 4500.0)  # millimetres mapped to 0..1 in space "normalized"
    hands: list[Literal["left", "right", "unknown"]] = ["left", "right", "unknown"]
    gestures: list[Literal[CANONICAL_GESTURES]] = list(CANONICAL_GESTURES)
    learned: bool = True  # also send learned gestures (`issv learn`), under the names they were taught
    in_progress: bool = False  # also send gestures under way, not only completed ones
    rate: float = Field(0.0, ge=0)  # at most this many hand bundles per second; 0: every frame
    pd_safe: bool = True  # only i, f, s types (Pd 0.53's oscparse rejects T, F, N, h, d)
    messages: list[Template] = []
    keepalive: str = Field("0.0.0.0:12346", description="scheme synapse only: HOST:PORT where clients' "
                           "/<joint>_trackjointpos keep-alives arrive (Synapse's 12346); \"off\": send every "
                           "joint's positions in every space, unasked")

    @field_validator("destinations", mode="before")
    @classmethod
    def _one_or_many(cls, value):
        return [value] if isinstance(value, str) else value

    @field_validator("destinations")
    @classmethod
    def _not_empty(cls, value):
        if value is not None and not value:
            raise ValueError("give at least one HOST:PORT")
        return value

    @field_validator("prefix")
    @classmethod
    def _prefix(cls, value):
        if value and (not value.startswith("/") or value.endswith("/") or any(c in value for c in " #*?,[]{}")):
            raise ValueError("expected an OSC address part such as /issv (starts with /, does not end "
                             "with /, no spaces or # * ? , [ ] { })")
        return value

    @model_validator(mode="after")
    def _check(self):
        if self.scheme == "custom" and not self.messages:
            raise ValueError('scheme "custom" sends only the templates: add [[effects.messages]] tables')
        if "keepalive" in self.model_fields_set and self.scheme != "synapse":
            raise ValueError('keepalive is Synapse\'s keep-alive port: it needs scheme = "synapse"')
        if self.keepalive != "off":
            try:
                Address.parse(self.keepalive)
            except ValueError as error:
                raise ValueError(f'keepalive: {error}, or "off"') from None
        near, far = self.depth_range
        if not 0 <= near < far:
            raise ValueError("depth_range must be [near, far] millimetres with 0 <= near < far")
        return self


class OscEffect(Effect):
    name = "osc"
    Options = OscOptions

    @classmethod
    def describe(cls, scheme: str = "issv") -> str:
        """The documentation of an address scheme (what `issv osc-schema` prints)."""
        return SCHEME_TEXT[scheme]

    def __init__(self, options: OscOptions | None = None, warn: Warn = warn_stderr) -> None:
        super().__init__(options)
        self.warn = warn

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        o = self.options
        prefix = o.prefix if o.prefix is not None else (DEFAULT_PREFIX if o.scheme == "issv" else "")
        self.schemes: list[Scheme] = [SCHEMES[o.scheme](prefix)] if o.scheme in SCHEMES else []
        if o.scheme == "synapse":
            listen = None if o.keepalive == "off" else Address.parse(o.keepalive)
            self.schemes.append(SynapseScheme(prefix, KeepAlive(listen, self.warn, prefix)))
        if o.messages:
            self.schemes.append(TemplateScheme(o.messages, prefix))
        self.projector = Projector(o.space, stage, o.depth_range)
        texts = o.destinations or [DEFAULT_DESTINATION[o.scheme]]
        self.destinations = [Destination(Address.parse(t), self.warn) for t in dict.fromkeys(texts)]
        for destination in self.destinations:
            destination.start()
        deadline = time.monotonic() + RESOLVE_WAIT
        for destination in self.destinations:
            destination.resolved.wait(max(0.0, deadline - time.monotonic()))
        self._previous: dict[int, Hand] = {}
        self._pending: list[Gesture] = []
        self._next_bundle = 0.0

    # -- gestures: every event, at once -----------------------------------------------------------
    def on_gesture(self, gesture: Gesture) -> None:
        o = self.options
        wanted = o.learned if gesture.type is GestureType.LEARNED else gesture.name in o.gestures
        if (not wanted or gesture.side.value not in o.hands
                or (gesture.state.value != "complete" and not o.in_progress)):
            return
        if not self.projector.ready:  # only before the first frame: its geometry comes right after
            self._pending.append(gesture)
            return
        for scheme in self.schemes:
            for message in scheme.gesture(gesture, self.projector):
                self._send(encode(message, o.pd_safe))

    # -- hands: one bundle per frame, newest wins ------------------------------------------------
    def on_frame(self, frame: Frame) -> None:
        self.projector.see(frame.depth)
        if not self.projector.ready:
            self.projector.assume_kinect()
            self.warn(f"space {self.options.space!r} needs depth images and backend {frame.backend!r} "
                      f"sends frames without one: positions are projected as a 640x480 Kinect v1")
        pending, self._pending = self._pending, []
        for gesture in pending:
            self.on_gesture(gesture)
        if self.options.rate and not self._due():
            return
        hands = [h for h in frame.hands if h.side.value in self.options.hands]
        current = {h.id: h for h in hands}
        gone = [h for hand_id, h in self._previous.items() if hand_id not in current]
        self._previous = current
        messages: list[Message] = []
        for scheme in self.schemes:
            messages += scheme.frame(frame, hands, gone, self.projector)
        if messages:
            self._send(encode_bundle(messages, self.options.pd_safe))

    def _due(self) -> bool:
        """Rate limit: on average `rate` bundles a second, however fast frames come."""
        now, period = time.perf_counter(), 1.0 / self.options.rate
        if now < self._next_bundle:
            return False
        on_time = now - self._next_bundle < period
        self._next_bundle = self._next_bundle + period if on_time else now + period
        return True

    def _send(self, data: bytes) -> None:
        for destination in self.destinations:
            destination.send(data)

    def close(self) -> None:
        for destination in getattr(self, "destinations", ()):
            destination.close()
        for scheme in getattr(self, "schemes", ()):
            scheme.close()
