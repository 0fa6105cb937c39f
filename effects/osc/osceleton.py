"""The OSCeleton preset (`scheme = "osceleton"`): what Sensebloom's OSCeleton sends, from our users.

Taken from OSCeleton's source (src/OSCeleton.cpp): `/new_user i` when NiTE sees a user,
`/new_skel i` when its skeleton is calibrated, `/joint s i f f f` for every joint whose confidence
is at least 0.5, in OSCeleton's order and names, `/user/<id> f f f` (the centre of mass) for a user
without a skeleton, `/lost_user i` when the user is gone. Positions are normalised as OSCeleton
does: x = (1280 - X) / 2560, y = (960 - Y) / 1920, z = Z * 7.8125 / 10000, with OpenNI's X, which
grows towards the performer's left in OSCeleton's default mirror mode (so l_hand has the smaller
x), and the centre of mass's y = (1280 - Y) / 2560 (the source's own, different, formula).

Frames without users (hand-only backends) are sent as before: each user's hands as l_hand and
r_hand, the user new with its first hand and lost with its last.
"""
from __future__ import annotations

from effects.osc.coords import Projector
from effects.osc.presets import performer_view, sided
from effects.osc.schema import Scheme
from host import Frame, Hand, Side, User, Vec3
from host.osc import Message

OSCELETON_TEXT = """\
OSCeleton preset (scheme = "osceleton"; default destination 127.0.0.1:7110)

  /new_user   i            user         a user appears
  /new_skel   i            user         the user's joints follow (its first frame with joints)
  /joint      s i f f f    joint, user, x, y, z        per joint, per user, per frame
  /user/<id>  f f f        x, y, z      centre of mass of a user without joints yet
  /lost_user  i            user         the user has left (not when a hand drops)

joint  head neck l_shoulder l_elbow l_hand r_shoulder r_elbow r_hand torso l_hip
       l_knee l_foot r_hip r_knee r_foot: OSCeleton's names and order, those of its
       joints issv has and the backend reports with confidence >= 0.5 (OSCeleton's
       collar, wrist, fingertip, waist and ankle are never sent: NiTE had none)
x      (1280 - X) / 2560 with OpenNI's X: 0 at 1.28 m to the performer's left, 1 at
       1.28 m to the right (OSCeleton's default mirror mode: l_hand has the smaller x)
y      (960 - Y) / 1920:  0..1 over 0.96..-0.96 m, growing downwards
z      Z * 7.8125 / 10000: 0..7.8 over 0..10 m
/user/<id> uses OSCeleton's y = (1280 - Y) / 2560 for the centre of mass.
Users come from backends that report them (osc-in, the open engine); frames with hands only
(other backends) send each user's hands as l_hand / r_hand (a hand of unknown side takes the
free side), /new_user and /new_skel with its first hand, /lost_user after its last.
One bundle per frame. OSCeleton had no gestures: add templates (messages) to send them.
"""

#: OSCeleton's joint names in the order its sendOSC() sends them, for the joints issv has.
JOINTS: tuple[tuple[str, str], ...] = tuple(
    (issv, issv.replace("left_", "l_").replace("right_", "r_")) for issv in (
        "head", "neck", "left_shoulder", "left_elbow", "left_hand", "right_shoulder", "right_elbow",
        "right_hand", "torso", "left_hip", "left_knee", "left_foot", "right_hip", "right_knee", "right_foot"))
HANDS = {Side.LEFT: "l_hand", Side.RIGHT: "r_hand"}
MIN_CONFIDENCE = 0.5  # OSCeleton's genOscMsg() drops a joint below this


def normalised(position: Vec3) -> tuple[float, float, float]:
    """OSCeleton's jointPos(): millimetres (x towards the performer's right) to its 0..1 range.
    OpenNI's X is the opposite of ours, hence 1280 - X = 1280 + x."""
    x, y, z = position
    return ((1280 + x) / 2560, (960 - y) / 1920, z * 7.8125 / 10000)


class OSCeletonScheme(Scheme):
    def __init__(self, prefix: str = "") -> None:
        self.prefix = prefix
        self._users: set[int] = set()  # announced with /new_user, not yet lost
        self._skeletons: set[int] = set()  # announced with /new_skel

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        if frame.users:
            present = {u.id: u for u in frame.users if u.in_view}
            body = [m for u in sorted(present.values(), key=lambda u: u.id) for m in self._user(u, frame)]
        else:
            present = {h.user_id: None for h in hands}
            body = [self._joint(HANDS[side], hand.user_id, performer_view(hand.position, frame))
                    for hand, side in sided(hands)]
        p = self.prefix
        messages = [Message(f"{p}/new_user", (("i", u),)) for u in sorted(set(present) - self._users)]
        self._users |= set(present)
        if not frame.users:
            messages += [Message(f"{p}/new_skel", (("i", u),)) for u in sorted(set(present) - self._skeletons)]
            self._skeletons |= set(present)
        messages += body
        for user in sorted(self._users - set(present)):
            messages.append(Message(f"{p}/lost_user", (("i", user),)))
            self._users.discard(user)
            self._skeletons.discard(user)
        return messages

    def _user(self, user: User, frame: Frame) -> list[Message]:
        """One user's messages: /new_skel with its first joints, then the joints (or the centre
        of mass while it has none)."""
        joints = [(name, user.joints[issv]) for issv, name in JOINTS
                  if issv in user.joints and user.joints[issv].confidence >= MIN_CONFIDENCE]
        if not joints:
            if user.center_of_mass is None:
                return []
            x, y, z = performer_view(user.center_of_mass, frame)
            return [Message(f"{self.prefix}/user/{user.id}",
                            (("f", (1280 + x) / 2560), ("f", (1280 - y) / 2560), ("f", z * 7.8125 / 10000)))]
        messages = []
        if user.id not in self._skeletons:
            self._skeletons.add(user.id)
            messages.append(Message(f"{self.prefix}/new_skel", (("i", user.id),)))
        return messages + [self._joint(name, user.id, performer_view(j.position, frame)) for name, j in joints]

    def _joint(self, name: str, user: int, position: Vec3) -> Message:
        x, y, z = normalised(position)
        return Message(f"{self.prefix}/joint", (("s", name), ("i", user), ("f", x), ("f", y), ("f", z)))
