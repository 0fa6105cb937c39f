"""The Synapse preset (`scheme = "synapse"`): what Ryan Challinor's Synapse for Kinect sends.

Taken from Synapse's source (testApp.cpp, JointHitDetector.cpp): one skeleton, the first tracked
user's; `/tracking_skeleton 1` when a skeleton starts being tracked and `0` when none is; for each
of its joint detectors, in its order, `/<joint>_pos_world` (millimetres), `/<joint>_pos_body`
(the joint minus its reference joint: the torso, or the right hip for the head) and
`/<joint>_pos_screen` (pixel column and row in its 640x480 depth image, depth in mm), each only
while a client has asked for it with `/<joint>_trackjointpos` in the last 3.1 s (keepalive.py);
`closesthand` is whichever hand is nearer the camera. Gesture words go to `/<joint>`.
"""
from __future__ import annotations

import time

from effects.osc.coords import Projector
from effects.osc.destinations import warn_stderr
from effects.osc.keepalive import KeepAlive
from effects.osc.presets import performer_view, sided
from effects.osc.schema import Scheme
from host import Frame, Gesture, Hand, Intrinsics, Side, Vec3
from host.osc import Message

SYNAPSE_TEXT = """\
Synapse preset (scheme = "synapse"; default destination 127.0.0.1:12345,
keep-alive requests taken on 0.0.0.0:12346)

  /tracking_skeleton     i        1 when a skeleton starts being tracked, 0 when none is
  /<joint>_pos_world     f f f    x, y, z millimetres (camera: x right, y up, z away)
  /<joint>_pos_body      f f f    the joint minus its reference joint, millimetres
  /<joint>_pos_screen    f f f    u, v pixels in a 640x480 depth image, z millimetres
  /<joint>               s        a gesture word, when a gesture completes

joint  righthand lefthand rightelbow leftelbow rightknee leftknee rightfoot leftfoot
       head torso neck leftshoulder rightshoulder lefthip righthip closesthand
       (Synapse's order; those the backend reports; closesthand: the hand nearer
       the camera)
body   relative to the torso, except head: relative to the right hip (Synapse's
       choice); torso_pos_body is 0 0 0
keep-alive  a client sends /<joint>_trackjointpos i (1 body, 2 world, 3 screen) to
       port 12346; that joint's positions in that space are sent for 3.1 s after
       the last request, as Synapse does. keepalive = "HOST:PORT" listens elsewhere;
       keepalive = "off" sends every joint in every space, unasked.
words  left, right, up, down (swipes, from the performer's point of view),
       forward (click / push), and, beyond Synapse's own words, wave, hand_raise
       and learned gestures (by the name they were taught); only the skeleton's
       user's gestures are sent
One skeleton: the lowest user id among the users with joints (the backends that report
users: osc-in, the open engine); with hands only (other backends) righthand, lefthand and
closesthand from the lowest user's hands (a hand of unknown side takes the free side),
tracked while it has a hand, and no _pos_body (there is no torso). One bundle per frame.
"""

#: Synapse's JointHitDetectors in its order: (its name, our joint, the reference for _pos_body).
DETECTORS: tuple[tuple[str, str, str], ...] = (
    ("righthand", "right_hand", "torso"), ("lefthand", "left_hand", "torso"),
    ("rightelbow", "right_elbow", "torso"), ("leftelbow", "left_elbow", "torso"),
    ("rightknee", "right_knee", "torso"), ("leftknee", "left_knee", "torso"),
    ("rightfoot", "right_foot", "torso"), ("leftfoot", "left_foot", "torso"),
    ("head", "head", "right_hip"), ("torso", "torso", "torso"), ("neck", "neck", "torso"),
    ("leftshoulder", "left_shoulder", "torso"), ("rightshoulder", "right_shoulder", "torso"),
    ("lefthip", "left_hip", "torso"), ("righthip", "right_hip", "torso"),
    ("closesthand", "closest_hand", "torso"),
)
HAND_JOINTS = {Side.RIGHT: "right_hand", Side.LEFT: "left_hand"}
WORDS = {"swipe_left": "left", "swipe_right": "right", "swipe_up": "up", "swipe_down": "down",
         "click": "forward", "wave": "wave", "hand_raise": "hand_raise"}
SCREEN = (640, 480)
KINECT = Intrinsics.from_fov(*SCREEN, 57, 43)  # Synapse's camera, for frames without a depth image


def closest_hand(joints: dict[str, Vec3]) -> Vec3 | None:
    """Synapse's closesthand: the right hand unless the left is nearer the camera."""
    right, left = joints.get("right_hand"), joints.get("left_hand")
    if right is None or left is None:
        return right or left
    return right if right[2] < left[2] else left


class SynapseScheme(Scheme):
    def __init__(self, prefix: str = "", keepalive: KeepAlive | None = None) -> None:
        self.prefix = prefix
        self.keepalive = keepalive or KeepAlive(None, warn_stderr)
        self._tracking = False
        self._user: int | None = None  # the skeleton's user, whose gestures are sent
        self._joint_of: dict[int, str] = {}  # hand id -> joint, in the last frame

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        now = time.monotonic()
        self.keepalive.poll(now)
        joints = self._skeleton(frame, hands)
        messages = []
        if bool(joints) != self._tracking:
            self._tracking = bool(joints)
            messages.append(Message(f"{self.prefix}/tracking_skeleton", (("i", int(self._tracking)),)))
        if joints:
            joints["closest_hand"] = closest_hand(joints)
            screen = KINECT if to.depth is None else to.depth.intrinsics.scaled(
                SCREEN[0] / to.depth.width, SCREEN[1] / to.depth.height)
            for name, joint, ref in DETECTORS:
                messages += self._detector(name, joints.get(joint), joints.get(ref), screen, now)
        return messages

    def _skeleton(self, frame: Frame, hands: list[Hand]) -> dict[str, Vec3]:
        """The tracked skeleton's joints as Synapse's mirror view has them (empty: none tracked)."""
        if frame.users:
            users = [u for u in frame.users if u.in_view and u.joints]
            user = min(users, key=lambda u: u.id, default=None)
            self._user = None if user is None else user.id
            self._joint_of = {}
            if user is None:
                return {}
            return {name: performer_view(j.position, frame) for name, j in user.joints.items()}
        if hands:
            self._user = min(h.user_id for h in hands)
            hands = [h for h in hands if h.user_id == self._user]
        pairs = sided(hands)
        self._joint_of = {hand.id: HAND_JOINTS[side] for hand, side in pairs}
        return {HAND_JOINTS[side]: performer_view(hand.position, frame) for hand, side in pairs}

    def _detector(self, name: str, joint: Vec3 | None, ref: Vec3 | None, screen: Intrinsics,
                  now: float) -> list[Message]:
        """One JointHitDetector::Poll: world, body, screen, each if asked for lately."""
        if joint is None:
            return []
        wanted, at = self.keepalive.wanted, f"{self.prefix}/{name}"
        out = []
        if wanted(name, "world", now):
            out.append(Message(f"{at}_pos_world", tuple(("f", c) for c in joint)))
        if ref is not None and wanted(name, "body", now):
            out.append(Message(f"{at}_pos_body", tuple(("f", c - r) for c, r in zip(joint, ref))))
        if wanted(name, "screen", now):
            u, v, _ = screen.world_to_depth(joint[0], joint[1], max(joint[2], 1.0))
            out.append(Message(f"{at}_pos_screen", (("f", u), ("f", v), ("f", joint[2]))))
        return out

    def gesture(self, gesture: Gesture, to: Projector) -> list[Message]:
        if gesture.state.value != "complete":
            return []  # Synapse reports hits, not motions under way
        if self._user is not None and gesture.user_id != self._user:
            return []  # one skeleton: another performer's gestures are not Synapse's to send
        joint = HAND_JOINTS.get(gesture.side) or self._joint_of.get(gesture.hand_id, "right_hand")
        return [Message(f"{self.prefix}/{joint.replace('_', '')}", (("s", WORDS.get(gesture.name, gesture.name)),))]

    def close(self) -> None:
        self.keepalive.close()
