"""`osc-in`: users, hands and gestures from the skeleton trackers artists already run.

OSCeleton, Synapse, NI mate, KinectV2-OSC, MediaPipe-to-OSC bridges or the artist's own addresses
(schemes.py) arrive over UDP (receiver.py); each frame the backend drains the complete samples,
runs each user's recogniser on them (users.py) and reports users, both hands of each and the
gestures. Frames carry a depth image of no readings with a Kinect v1's geometry (640x480, 57 x 43
degrees, OSCeleton's sensor), so effects place hands on the stage as on `openiss`. The clock
(`Frame.time`, gesture times) is the time of day of the senders' bundle time tags, or of arrival
for untagged messages (receiver.py): a replay stamped with a session's own times is recognised
on exactly those times.
"""
from __future__ import annotations

import sys
import time
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from backends.engine.recognizer import GestureRecognizer
from backends.engine.rules import GestureRules
from backends.oscin.receiver import Announcement, Receiver
from backends.oscin.schemes import (CustomScheme, InputTemplate, KinectV2Scheme, MediaPipeScheme, NiMateScheme,
                                    OSCeletonScheme, Scheme, SynapseScheme)
from backends.engine.geometry import KINECT_V1
from backends.users import BlankDepth, Users
from host import Backend, Frame, Gesture, Update
from host.errors import UserError

SchemeName = Literal["osceleton", "synapse", "ni-mate", "kinectv2", "mediapipe", "custom"]
#: where each bridge sends by default (OSCeleton 7110, Synapse 12345, NI mate 7000, KinectV2-OSC 12345)
DEFAULT_PORT = {"osceleton": 7110, "synapse": 12345, "ni-mate": 7000, "kinectv2": 12345, "mediapipe": 9000,
                "custom": 9000}


class OscInOptions(BaseModel):
    """What a profile may set for `osc-in` (README.md, OSC in)."""

    model_config = ConfigDict(extra="forbid")
    scheme: SchemeName = Field("osceleton", description="the bridge: osceleton (also its -k and -q formats), "
                               "synapse, ni-mate (basic or OSCeleton-style), kinectv2 (KinectV2-OSC), mediapipe "
                               "(flat pose landmark lists) or custom (the templates in messages)")
    port: int | None = Field(None, ge=0, lt=65536, description="UDP port to listen on; default the bridge's own "
                             "(OSCeleton 7110, Synapse and KinectV2-OSC 12345, NI mate 7000, others 9000); "
                             "0 any free one")
    host: str = Field("0.0.0.0", description="the address to listen on (0.0.0.0: every interface)")
    lost_timeout_s: float = Field(1.0, gt=0, description="a user whose messages stop this long is LOST")
    fps: float = Field(30.0, gt=0, le=240, description="frames per second while users are in view (at most "
                       "twice this when messages come faster)")
    end_after_idle_s: float = Field(0.0, ge=0, description="> 0: the stream ends after this long without a "
                                    "message (ten times as long before the first); users still in view are LOST in "
                                    "its last frame, their strokes judged as at the end of a clip")
    reach_mm: float = Field(350.0, gt=0, description="a hand farther than this from the torso (sideways, forwards "
                            "or upwards) is extended; nearer, it rests")
    multiplier: tuple[float, float, float] = Field((1.0, 1.0, 1.0), description="osceleton: the -mx -my -mz "
                                                   "OSCeleton ran with, undone")
    offset: tuple[float, float, float] = Field((0.0, 0.0, 0.0), description="osceleton: the -ox -oy -oz "
                                               "OSCeleton ran with, undone")
    kitchen_depth_mm: float = Field(2000.0, gt=0, description="osceleton -k (Animata) sends no z: joints are "
                                    "placed this far away")
    synapse_host: str = Field("127.0.0.1", description="synapse: where Synapse runs, to send it the keep-alive "
                              "/<joint>_trackjointpos it needs every few seconds")
    synapse_port: int = Field(12346, gt=0, lt=65536, description="synapse: the port Synapse takes them on")
    mediapipe_address: str = Field("/pose", description="mediapipe: the landmark list's address (or "
                                   "ADDRESS/<person>, counted from 0)")
    mediapipe_depth_mm: float = Field(2500.0, gt=0, description="mediapipe: how far from the camera the hips are "
                                      "(its world landmarks are hip-centred)")
    mirrored: bool | None = Field(None, description="whether +x is the performer's right; default the scheme's "
                                  "(false for mediapipe, true for the others)")
    scale: float = Field(1.0, description="custom: multiply positions by this to get millimetres (1000 for metres)")
    messages: list[InputTemplate] = Field([], description="custom: the templates, [[backend.messages]] with on "
                                          "(joint, new_user, lost_user), address and args using {user} {joint} {x} {y} "
                                          "{z} {confidence}")
    gestures: GestureRules = Field(default_factory=GestureRules, description="gesture thresholds (mm, s), as for "
                                   "openiss")

    @model_validator(mode="after")
    def _check(self):
        if self.scheme == "custom" and not self.messages:
            raise ValueError('scheme "custom" reads only the templates: add [[backend.messages]] tables')
        if any(m == 0 for m in self.multiplier):
            raise ValueError("multiplier must not be 0 on any axis (OSCeleton's -mx/-my/-mz as it ran)")
        return self


def make_scheme(o: OscInOptions) -> Scheme:
    if o.scheme == "osceleton":
        return OSCeletonScheme(o.multiplier, o.offset, o.kitchen_depth_mm)
    if o.scheme == "synapse":
        return SynapseScheme()
    if o.scheme == "ni-mate":
        return NiMateScheme()
    if o.scheme == "kinectv2":
        return KinectV2Scheme()
    if o.scheme == "mediapipe":
        return MediaPipeScheme(o.mediapipe_address, o.mediapipe_depth_mm)
    return CustomScheme(o.messages, o.scale)


def warn_stderr(text: str) -> None:
    print(f"issv: osc-in: {text}", file=sys.stderr, flush=True)


class OscInBackend(Backend):
    """Skeletons over OSC -> users, hands (both, all the time) and gestures per user."""

    name = "osc-in"
    Options = OscInOptions
    needs_source = False
    #: what kind of input it takes (`issv check` compares it with the source's)
    input_kind = "skeleton (OSC)"

    def __init__(self, source=None, options: OscInOptions | None = None, warn=warn_stderr) -> None:
        super().__init__(source, options)
        self.warn = warn

    @classmethod
    def recognizer(cls, options: OscInOptions | None = None) -> GestureRecognizer:
        """The recogniser each user gets (`issv gestures --backend osc-in`)."""
        options = options if options is not None else cls.Options()
        return GestureRecognizer(options.gestures)

    def init(self) -> None:
        o = self.options
        self.scheme = make_scheme(o)
        mirrored = self.scheme.mirrored if o.mirrored is None else o.mirrored
        self.mirrored = mirrored
        self.users = Users(lambda: self.recognizer(o), o.lost_timeout_s, mirrored, o.reach_mm)
        port = DEFAULT_PORT[o.scheme] if o.port is None else o.port
        keepalive = (o.synapse_host, o.synapse_port) if o.scheme == "synapse" else None
        try:
            self.receiver = Receiver(self.scheme, o.host, port, self.warn, keepalive)
        except OSError as error:
            raise UserError(f"backend 'osc-in': {error}") from None
        self.receiver.start()
        self.port = self.receiver.port
        self._seq = 0
        self.blank = BlankDepth()
        self._last_frame = 0.0
        self._ended = False
        self._started = time.monotonic()
        self._rate_mark, self._rate = (self._started, 0), 0.0
        #: seconds each frame took to rebuild users and hands, and in the recognisers (the bench reads them)
        self.rebuild_s: list[float] = []
        self.recognise_s: list[float] = []
        self._last_t = (0.0, time.monotonic())  # (source time of the newest sample, its arrival)

    def update(self) -> Update:
        """The next frame; False when nothing came within a frame's time and nobody is in view (no
        bridge sending yet: the host checks its limits and asks again); None once ended idle."""
        o, rx = self.options, self.receiver
        if self._ended:
            return None
        rx.arrived.wait(1.0 / o.fps)
        rx.arrived.clear()
        wait = self._last_frame + 1.0 / (2 * o.fps) - time.monotonic()  # never faster than 2 x fps
        if wait > 0:
            time.sleep(wait)
        if self._idle():
            self._ended = True
            if not rx.queue and not len(self.users):
                return None
            # else a last frame: what arrived, and the users still in view LOST
        elif not rx.queue and not len(self.users):
            return False
        start = time.perf_counter()
        now = time.monotonic()
        gestures: list[Gesture] = []
        t = self._now_t()
        arrival = None  # of the newest message in this frame
        while rx.queue:
            item = rx.queue.popleft()
            t = item.t
            self._last_t = (t, item.arrival)
            arrival = item.arrival
            if isinstance(item, Announcement):
                if item.event.kind == "new":
                    self.users.announce(item.event.user, item.arrival)
                else:
                    gestures += self.users.leave(item.event.user, t)
            else:
                gestures += self.users.sample(item.user, item.joints, t, item.arrival)
        gestures += self.users.finish(t) if self._ended else self.users.expire(now, t)
        users, hands = self.users.report()
        self.recognise_s.append(self.users.recognising)
        self.rebuild_s.append(time.perf_counter() - start - self.users.recognising)
        self.users.recognising = 0.0
        self._seq += 1
        self._last_frame = time.monotonic()
        # captured when its newest message arrived; a frame with none (a user's state kept or
        # timed out while the bridge is quiet) is made now, not "captured" seconds ago, but keeps
        # the newest sample's time: it brings no new sample, and the host's learned recognisers
        # (host/learned_users.py) would take its hands, stamped later, for a pause never made
        capture = time.time() - (now - arrival) if arrival is not None else time.time()
        sampled = self._last_t[0]  # t itself when this frame drained a sample
        depth = self.blank(*KINECT_V1, self._seq, sampled, capture, self.mirrored)
        return Frame(self._seq, capture, depth, hands if self.tracking_hands else (),
                     tuple(gestures) if self.detecting_gestures else (), self.name, users=users, time=sampled)

    def _now_t(self) -> float:
        """The source time now: the newest sample's, plus the time since it arrived."""
        t, arrival = self._last_t
        return t + (time.monotonic() - arrival) if self.receiver.last_arrival is not None else 0.0

    def _idle(self) -> bool:
        """With end_after_idle_s: nothing arrived for that long (before the first message, for ten
        times that long: a bridge may take a while to start)."""
        limit, last = self.options.end_after_idle_s, self.receiver.last_arrival
        if not limit or self.receiver.queue:
            return False
        if last is None:
            return time.monotonic() - self._started > 10 * limit
        return time.monotonic() - last > limit

    def input_label(self) -> str:
        """What the HUD and the status line say: the scheme, the port, users and message rate."""
        rx, now = getattr(self, "receiver", None), time.monotonic()
        if rx is None:
            return f"osc {self.options.scheme} (not listening yet)"
        last_t, last_n = self._rate_mark
        if now - last_t >= 1.0:
            self._rate = (rx.messages - last_n) / (now - last_t)
            self._rate_mark = (now, rx.messages)
        return f"osc {self.options.scheme} :{self.port}, {len(self.users)} users, {self._rate:.0f} msg/s"

    def stop(self) -> None:
        super().stop()
        receiver = getattr(self, "receiver", None)
        if receiver is not None:
            receiver.close()
            if receiver.bad:
                counts = ", ".join(f"{n} {kind}" for kind, n in receiver.bad.most_common())
                self.warn(f"{receiver.messages} messages, ignored: {counts}")
