"""The default OSC address scheme (`scheme = "issv"`), documented in SCHEMA_TEXT.

SCHEMA_TEXT is what `issv osc-schema` prints and what README.md quotes; the tests check that
the messages sent, the shipped patches and the README agree with it.
"""
from __future__ import annotations

from host import Frame, Gesture, Hand

from effects.osc.coords import Projector
from host.osc import Message

DEFAULT_PREFIX = "/issv"

SCHEMA_TEXT = """\
issv OSC address scheme (scheme = "issv", the default; prefix /issv)

Per sensor frame, one bundle (time tag: immediately) holding, in this order:
  /issv/frame    i f i            seq, t, hands
  /issv/hand     i s s f f f f    id, side, state, x, y, z, confidence   (one per hand)
One message per gesture event, sent alone, as soon as the event arrives:
  /issv/gesture  s s s i f f f f  name, state, side, hand, x, y, z, confidence

seq         sensor frame number (1, 2, ...); t: source time in seconds
hands       how many /issv/hand messages with a tracked hand follow in this bundle
id          hand id, stable while the hand is tracked
side        left | right | unknown (the performer's own left and right)
state       new | tracking | lost | touching_fov, or absent: the hand was in the
            previous bundle and is gone now (sent once, at its last position)
name        wave | click | hand_raise | swipe_left | swipe_right | swipe_up | swipe_down
            (swipes are named from the performer's point of view), or the name of a
            learned gesture (`issv learn`; option learned = false leaves them out)
state       of a gesture: complete, or in_progress (only with in_progress = true)
hand        the id of the hand that made the gesture (0 if unknown)
confidence  0..1
x y z       in the effect's coordinate space (option space):
  mm          camera millimetres: x right, y up, z away from the camera (default)
  normalized  x, y: place in the depth image, 0..1 from the left / top; z: 0..1 over
              depth_range (default 500..4500 mm)
  stage       x, y: output pixels from the top-left, through the profile's
              output.calibration (without one, the depth image stretched over the
              output); z: millimetres

Only the types i, f and s are used, so Pure Data's oscparse reads every message.
The option prefix replaces /issv (prefix = "" sends /frame, /hand, /gesture).
"""


class Scheme:
    """Turns hands and gestures into messages. One instance per effect, so a scheme may remember
    what it sent before (new and lost users, for example)."""

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        """The messages of one frame's bundle. `gone`: hands of the previous bundle missing now."""
        return []

    def gesture(self, gesture: Gesture, to: Projector) -> list[Message]:
        """The messages for one gesture event, each sent as its own datagram."""
        return []

    def close(self) -> None:
        """Release what the scheme holds (a socket it listens on)."""


class IssvScheme(Scheme):
    """The default scheme: every field of our hands and gestures, only i, f and s types."""

    def __init__(self, prefix: str = DEFAULT_PREFIX) -> None:
        self.prefix = prefix

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        messages = [Message(f"{self.prefix}/frame", (("i", frame.seq), ("f", frame.timestamp), ("i", len(hands))))]
        messages += [self._hand(h, h.state.value, h.confidence, to) for h in hands]
        messages += [self._hand(h, "absent", 0.0, to) for h in gone]
        return messages

    def _hand(self, hand: Hand, state: str, confidence: float, to: Projector) -> Message:
        x, y, z = to(hand.position)
        return Message(f"{self.prefix}/hand", (("i", hand.id), ("s", hand.side.value), ("s", state),
                                               ("f", x), ("f", y), ("f", z), ("f", confidence)))

    def gesture(self, gesture: Gesture, to: Projector) -> list[Message]:
        x, y, z = to(gesture.position)
        return [Message(f"{self.prefix}/gesture", (
            ("s", gesture.name), ("s", gesture.state.value), ("s", gesture.side.value), ("i", gesture.hand_id),
            ("f", x), ("f", y), ("f", z), ("f", gesture.confidence)))]
