"""ROS 1 interop (transport = "ros"): the thesis' topics and messages (Listings 4.5-4.7) via rospy.

rospy comes from Debian (python3-rospy, python3-sensor-msgs, python3-geometry-msgs); scripts/setup.sh
drops a .pth file naming /usr/lib/python3/dist-packages into our Python's site-packages so these
import here. The thesis' messages lived in a catkin package; we generate the same kind of message
classes at runtime from .msg text with genpy (as rosbag does for bags of unknown types), so nothing
needs building and a C++ node with these .msg files in a package `openiss` interoperates (same
type names, same MD5 sums). Each message keeps the thesis' fields verbatim and adds a std_msgs/Header
(seq: per-topic sequence number, set by rospy; stamp: capture time; frame_id: issv's publisher
session) and what issv's Gesture, Hand and DepthFrame carry beyond the thesis.

Topics under the namespace (default /openiss): gestures (openiss/Gesture, one per event), hands
(openiss/Hands, one per frame: the hands and the users, openiss/User with their openiss/Joint), depth (openiss/DepthFrame), depth_image (sensor_msgs/Image 16UC1,
millimetres, REP 118) with camera_info (sensor_msgs/CameraInfo), user_labels (sensor_msgs/Image
mono8 at the depth image's size: 0 nobody, else the user's id; stamped and framed like the depth
image it belongs to, sent with it when the backend knows the users' pixels and a node listens), and
status (std_msgs/String: the JSON heartbeat and goodbye of wire.py). Depth here is raw, as in the
thesis: that is what ROS carries.
"""
from __future__ import annotations

import os
import queue
import threading
import time
from functools import cache

import numpy as np

from backends.network import wire
from backends.network.command import how_to_serve
from backends.network.publisher import HEARTBEAT_S, DepthGate, DepthOptions
from backends.network.subscriber import Accounting, Notice, stderr_notice
from host import (DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Joint,
                  PluginUnavailable, Side, User)

DEBIAN_DIST = "/usr/lib/python3/dist-packages"
GESTURE_TYPES, GESTURE_STATES = list(GestureType), list(GestureState)
HAND_STATES, SIDES = list(HandState), list(Side)
EXTENDED = {True: 1, False: 0, None: -1}  # Hand.extended as the int8 of openiss/Hand

MSGS = {
    "Gesture": """# Thesis Listing 4.5 (gesture_type, gesture_position) plus issv's Gesture fields
Header header
uint16 gesture_type
geometry_msgs/Point gesture_position
uint8 gesture_state
uint16 hand_id
uint8 hand_side
float64 confidence
float64 source_time
uint32 frame_seq
uint16 user_id
""",
    "Hand": """# Thesis Listing 4.6 (hand_id, hand_state, hand_position) plus issv's Hand fields
uint16 hand_id
bool hand_state
geometry_msgs/Point hand_position
uint8 hand_status
uint8 hand_side
uint16 user_id
float64 confidence
int8 extended
""",
    "Hands": """# The tracked hands and users of one frame
Header header
Hand[] hands
uint32 frame_seq
float64 source_time
bool depth
string backend
User[] users
""",
    "User": """# A tracked person (NiTE's and Nuitrack's user): user_status as hand_status, joints in mm
uint16 user_id
uint8 user_status
Joint[] joints
bool has_center_of_mass
geometry_msgs/Point center_of_mass
""",
    "Joint": """# One body joint: head, neck, torso, left_shoulder ... (issv's JOINTS), mm, confidence 0..1
string name
geometry_msgs/Point position
float64 confidence
""",
    "DepthFrame": """# Thesis Listing 4.7 (depth_data .. frame_timestamp) plus intrinsics and mirroring
Header header
uint16[] depth_data
uint16 frame_width
uint16 frame_height
uint16 frame_id
time frame_timestamp
float64[4] intrinsics
bool mirrored
uint32 frame_seq
""",
}


class _Array(np.ndarray):
    """genpy's numpy serialiser calls ndarray.tostring(), which numpy 2 removed: give it back."""

    def tostring(self) -> bytes:
        return self.tobytes()


def _array(values, dtype) -> _Array:
    return np.ascontiguousarray(values, dtype=dtype).view(_Array)


def rospy_missing() -> str | None:
    try:
        import rospy  # noqa: F401
        import sensor_msgs.msg  # noqa: F401
        import genpy.dynamic  # noqa: F401
    except ImportError as error:
        return (f"rospy cannot be imported ({error}): install ros-core python3-rospy python3-sensor-msgs "
                f"python3-geometry-msgs and make {DEBIAN_DIST} importable (bash scripts/setup.sh does both)")
    return None


def _require() -> None:
    reason = rospy_missing()
    if reason is not None:
        raise PluginUnavailable(reason)


@cache
def messages() -> dict[str, type]:
    """openiss/* message classes generated from MSGS (plus numpy serialisation for DepthFrame)."""
    import genpy.dynamic
    import roslib.message
    from rospy.numpy_msg import numpy_msg
    deps = {t: roslib.message.get_message_class(t)._full_text for t in ("std_msgs/Header", "geometry_msgs/Point")}
    sep = "\n" + "=" * 80 + "\nMSG: "
    out: dict[str, type] = {}
    for name in ("Gesture", "Hands", "DepthFrame"):
        cat = MSGS[name] + "".join(f"{sep}{t}\n{text}" for t, text in deps.items())
        if name == "Hands":
            cat += "".join(f"{sep}openiss/{part}\n{MSGS[part]}" for part in ("Hand", "User", "Joint"))
        classes = genpy.dynamic.generate_dynamic(f"openiss/{name}", cat)
        out[name] = classes[f"openiss/{name}"]
        if name == "Hands":
            out.update({part: classes[f"openiss/{part}"] for part in ("Hand", "User", "Joint")})
    out["DepthFrame"] = numpy_msg(out["DepthFrame"])
    return out


_node_lock = threading.Lock()


def node(master: str | None) -> None:
    """One rospy node per process (rospy's rule), shared by publishers and subscribers."""
    import rosgraph
    import rospy
    with _node_lock:
        if rospy.core.is_initialized():
            return
        if master and master.startswith("http://"):
            os.environ["ROS_MASTER_URI"] = master
        os.environ.setdefault("ROS_MASTER_URI", "http://127.0.0.1:11311")
        try:  # rospy would wait for a missing master forever; say so instead
            rosgraph.Master("/issv").getPid()
        except Exception as error:
            raise PluginUnavailable(f"no ROS master answers at {os.environ['ROS_MASTER_URI']} ({error}): "
                                    "start `roscore` there, or name another with ROS_MASTER_URI") from None
        rospy.init_node("issv", anonymous=True, disable_signals=True)


def _stamp(t: float):
    import rospy
    return rospy.Time.from_sec(max(0.0, t))


def _xyz(point) -> tuple[float, float, float]:
    return (point.x, point.y, point.z)


def _session(frame_id: str) -> int:
    if not frame_id.startswith("issv-"):
        raise wire.WireError("bad-field", f"header.frame_id {frame_id[:40]!r} is not an issv session")
    return int(frame_id[5:21], 16)


class RosPublisher:
    """`issv serve --transport ros`: the Publisher interface (publish, stats, close) over rospy."""

    def __init__(self, master: str | None, namespace: str, depth: DepthOptions, backend: str) -> None:
        _require()
        import rospy
        import sensor_msgs.msg
        import std_msgs.msg
        node(master)
        self.m = messages()
        self.depth_options, self.backend = depth, backend
        self.session = int.from_bytes(os.urandom(8), "little") >> 1
        ns = namespace.rstrip("/")
        self.pubs = {
            "gestures": rospy.Publisher(f"{ns}/gestures", self.m["Gesture"], queue_size=1000),
            "hands": rospy.Publisher(f"{ns}/hands", self.m["Hands"], queue_size=1000),
            "depth": rospy.Publisher(f"{ns}/depth", self.m["DepthFrame"], queue_size=1),
            "image": rospy.Publisher(f"{ns}/depth_image", sensor_msgs.msg.Image, queue_size=1),
            "info": rospy.Publisher(f"{ns}/camera_info", sensor_msgs.msg.CameraInfo, queue_size=1),
            "labels": rospy.Publisher(f"{ns}/user_labels", sensor_msgs.msg.Image, queue_size=1),
            "status": rospy.Publisher(f"{ns}/status", std_msgs.msg.String, queue_size=100),
        }
        self.where = f"{os.environ['ROS_MASTER_URI']} {ns}/*"
        self._last_status = 0.0
        self._depth_gate = DepthGate(depth)
        self._final: dict | None = None
        self._last_seq = 0

    def _header(self, capture_time: float):
        import std_msgs.msg
        return std_msgs.msg.Header(stamp=_stamp(capture_time), frame_id=f"issv-{self.session:016x}")

    def _send_gestures(self, gestures: tuple[Gesture, ...], capture_time: float, frame_seq: int) -> None:
        import geometry_msgs.msg as gm
        for g in gestures:
            self.pubs["gestures"].publish(self.m["Gesture"](
                header=self._header(capture_time), gesture_type=GESTURE_TYPES.index(g.type),
                gesture_position=gm.Point(*g.position), gesture_state=GESTURE_STATES.index(g.state),
                hand_id=g.hand_id, hand_side=SIDES.index(g.side), confidence=g.confidence,
                source_time=g.timestamp, frame_seq=frame_seq, user_id=g.user_id))

    def publish_end(self, gestures: tuple[Gesture, ...]) -> None:
        """Gestures the end of the source completed: sent after the last frame, before the end."""
        self._send_gestures(gestures, time.time(), self._last_seq + 1)

    def publish(self, frame: Frame) -> None:
        import geometry_msgs.msg as gm
        m = self.m
        self._send_gestures(frame.gestures, frame.capture_time, frame.seq)
        self._last_seq = frame.seq
        depth = self._depth(frame)
        hands = [m["Hand"](hand_id=h.id, hand_state=h.state in (HandState.NEW, HandState.TRACKING),
                           hand_position=gm.Point(*h.position), hand_status=HAND_STATES.index(h.state),
                           hand_side=SIDES.index(h.side), user_id=h.user_id, confidence=h.confidence,
                           extended=EXTENDED[h.extended])
                 for h in frame.hands]
        users = [m["User"](user_id=u.id, user_status=HAND_STATES.index(u.state),
                           joints=[m["Joint"](name=name, position=gm.Point(*j.position), confidence=j.confidence)
                                   for name, j in u.joints.items()],
                           has_center_of_mass=u.center_of_mass is not None,
                           center_of_mass=gm.Point(*(u.center_of_mass or (0.0, 0.0, 0.0))))
                 for u in frame.users]
        self.pubs["hands"].publish(m["Hands"](header=self._header(frame.capture_time), hands=hands,
                                              frame_seq=frame.seq, source_time=frame.timestamp,
                                              depth=depth is not None, backend=frame.backend or self.backend,
                                              users=users))
        if depth is not None:  # labels first: a subscriber holds a frame for them only until the next one
            self._publish_labels(frame)
            self._publish_depth(frame, depth)
        if time.monotonic() - self._last_status >= HEARTBEAT_S:
            self._status(wire.HEARTBEAT)

    def _depth(self, frame: Frame) -> DepthFrame | None:
        return self.depth_options.shape(frame.depth) if self._depth_gate.admit(frame) else None

    def _publish_depth(self, frame: Frame, d: DepthFrame) -> None:
        import sensor_msgs.msg
        i = d.intrinsics
        header = self._header(frame.capture_time)
        if self.pubs["depth"].get_num_connections():
            self.pubs["depth"].publish(self.m["DepthFrame"](
                header=header, depth_data=_array(d.data.reshape(-1), np.uint16), frame_width=d.width,
                frame_height=d.height, frame_id=d.frame_id % 65536, frame_timestamp=_stamp(d.timestamp),
                intrinsics=_array(i.as_list(), np.float64), mirrored=d.mirrored, frame_seq=frame.seq))
        if self.pubs["image"].get_num_connections():
            self.pubs["info"].publish(sensor_msgs.msg.CameraInfo(
                header=header, width=d.width, height=d.height, K=[i.fx, 0, i.cx, 0, i.fy, i.cy, 0, 0, 1]))
            self.pubs["image"].publish(sensor_msgs.msg.Image(
                header=header, height=d.height, width=d.width, encoding="16UC1", is_bigendian=0,
                step=d.width * 2, data=d.data.tobytes()))

    def _publish_labels(self, frame: Frame) -> None:
        """The frame's user labels (made here, only when a node listens), sent just before its depth image."""
        import sensor_msgs.msg
        labels = self.depth_options.labels_of(frame)
        if labels is None or not self.pubs["labels"].get_num_connections() or (image := labels()) is None:
            return
        height, width = image.shape
        self.pubs["labels"].publish(sensor_msgs.msg.Image(
            header=self._header(frame.capture_time), height=height, width=width, encoding="mono8", is_bigendian=0,
            step=width, data=np.ascontiguousarray(image, np.uint8).tobytes()))

    def wait_for_subscriber(self, timeout: float) -> bool:
        """Block until some node subscribes to hands, gestures and a depth topic."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            n = self.pubs
            if (n["hands"].get_num_connections() and n["gestures"].get_num_connections()
                    and (n["depth"].get_num_connections() or n["image"].get_num_connections())):
                return True
            time.sleep(0.05)
        return False

    def _sent(self) -> dict[str, int]:
        """rospy's own per-topic counts (the header.seq it sets): messages that had a subscriber."""
        sent = {name: self.pubs[name].impl.seq for name in wire.STREAMS.values()}
        sent["depth"] = max(sent["depth"], self.pubs["image"].impl.seq)
        return sent

    def _status(self, kind: int) -> None:
        import std_msgs.msg
        body = wire.encode_status(kind, self.session, 0, self._sent(), self.backend, 0, time.time())
        self.pubs["status"].publish(std_msgs.msg.String(data=body.hex()))
        self._last_status = time.monotonic()

    def stats(self) -> dict:
        if self._final is not None:
            return self._final
        return {"bind": self.where, "subscribers": self.pubs["hands"].get_num_connections(), "sent": self._sent(),
                "depth_skipped": 0, "depth_bytes": None, "compression": None}

    def close(self) -> None:
        if self._final is not None:
            return
        self._status(wire.BYE)
        self._final = self.stats()
        time.sleep(0.2)  # rospy writes on its own threads: let the goodbye leave
        for pub in self.pubs.values():
            pub.unregister()


class RosSubscriber:
    """The subscriber interface of ZmqSubscriber (poll, accounting, close) over rospy topics."""

    def __init__(self, master: str, namespace: str, depth: bool = True, depth_topic: str = "frame",
                 notice: Notice = stderr_notice) -> None:
        _require()
        import rospy
        import sensor_msgs.msg
        import std_msgs.msg
        node(master if master.startswith("http://") else os.environ.get("ROS_MASTER_URI"))
        m = messages()
        ns = namespace.rstrip("/")
        master = os.environ["ROS_MASTER_URI"]
        self.accounting = Accounting(f"{master} {ns}/*", notice, how_to_serve(master, namespace))
        self._inbox: queue.SimpleQueue = queue.SimpleQueue()
        self._intrinsics: Intrinsics | None = None
        big = 1 << 24  # rospy's default 64 KiB read buffer makes large messages late
        self.subs = [
            rospy.Subscriber(f"{ns}/gestures", m["Gesture"], self._guard(self._gesture), queue_size=None),
            rospy.Subscriber(f"{ns}/hands", m["Hands"], self._guard(self._hands), queue_size=None),
            rospy.Subscriber(f"{ns}/status", std_msgs.msg.String, self._guard(self._status), queue_size=None),
        ]
        if depth and depth_topic == "frame":
            self.subs.append(rospy.Subscriber(f"{ns}/depth", m["DepthFrame"], self._guard(self._depth_frame),
                                              queue_size=1, buff_size=big))
        elif depth:
            self.subs.append(rospy.Subscriber(f"{ns}/camera_info", sensor_msgs.msg.CameraInfo,
                                              self._guard(self._info), queue_size=1))
            self.subs.append(rospy.Subscriber(f"{ns}/depth_image", sensor_msgs.msg.Image,
                                              self._guard(self._image), queue_size=1, buff_size=big))
        if depth:
            self.subs.append(rospy.Subscriber(f"{ns}/user_labels", sensor_msgs.msg.Image,
                                              self._guard(self._labels), queue_size=2, buff_size=big))

    def _guard(self, convert):
        """Runs on rospy's threads: convert, or pass the problem on to be counted (never raise there)."""
        def callback(msg) -> None:
            try:
                out = convert(msg)
            except wire.WireError as error:
                out = error
            except Exception as error:
                out = wire.WireError("bad-field", f"{type(error).__name__}: {error}")
            if out is not None:
                self._inbox.put((out, time.time()))
        return callback

    @staticmethod
    def _header(h, kind: int) -> wire.Header:
        return wire.Header(kind, _session(h.frame_id), h.seq, h.stamp.to_sec())

    def _gesture(self, g) -> wire.GestureMsg:
        p = g.gesture_position
        gesture = Gesture(GESTURE_TYPES[g.gesture_type], GESTURE_STATES[g.gesture_state], (p.x, p.y, p.z),
                          g.hand_id, SIDES[g.hand_side], g.confidence, g.source_time, g.user_id)
        return wire.GestureMsg(self._header(g.header, wire.GESTURE), g.frame_seq, gesture)

    def _hands(self, msg) -> wire.HandsMsg:
        hands = tuple(Hand(h.hand_id, HAND_STATES[h.hand_status], _xyz(h.hand_position), SIDES[h.hand_side],
                           h.user_id, h.confidence, {1: True, 0: False}.get(h.extended)) for h in msg.hands)
        users = tuple(User(u.user_id, HAND_STATES[u.user_status],
                           {j.name: Joint(_xyz(j.position), j.confidence) for j in u.joints},
                           _xyz(u.center_of_mass) if u.has_center_of_mass else None) for u in msg.users)
        return wire.HandsMsg(self._header(msg.header, wire.HANDS), msg.frame_seq, msg.source_time,
                             msg.backend[:64], hands, msg.depth, users)

    def _depth_frame(self, d) -> wire.DepthMsg:
        data = np.asarray(d.depth_data, dtype=np.uint16)
        if data.size != d.frame_width * d.frame_height or data.size == 0:
            raise wire.WireError("bad-depth", f"{data.size} values for {d.frame_width}x{d.frame_height}")
        frame = DepthFrame(data.reshape(d.frame_height, d.frame_width), Intrinsics(*map(float, d.intrinsics)),
                           frame_id=d.frame_id, timestamp=d.frame_timestamp.to_sec(),
                           capture_time=d.header.stamp.to_sec(), mirrored=d.mirrored)
        return wire.DepthMsg(self._header(d.header, wire.DEPTH), d.frame_seq, frame)

    def _info(self, info) -> None:
        k = info.K
        self._intrinsics = Intrinsics(k[0], k[4], k[2], k[5])

    def _image(self, img) -> wire.DepthMsg | None:
        if img.encoding not in ("16UC1", "mono16") or img.step != img.width * 2 or img.is_bigendian:
            raise wire.WireError("bad-depth", f"image {img.encoding} step {img.step}: expected 16UC1 millimetres")
        if self._intrinsics is None:
            return None  # camera_info has not arrived yet
        data = np.frombuffer(img.data, np.uint16).reshape(img.height, img.width)
        frame = DepthFrame(data, self._intrinsics, timestamp=img.header.stamp.to_sec(),
                           capture_time=img.header.stamp.to_sec())
        return wire.DepthMsg(self._header(img.header, wire.DEPTH), img.header.seq, frame)

    def _labels(self, img) -> wire.LabelsMsg:
        if img.encoding != "mono8" or img.step != img.width or len(img.data) != img.width * img.height:
            raise wire.WireError("bad-labels", f"image {img.encoding} step {img.step}: expected mono8 user labels")
        labels = np.frombuffer(img.data, np.uint8).reshape(img.height, img.width)
        return wire.LabelsMsg(self._header(img.header, wire.DEPTH), labels)

    def _status(self, s) -> wire.StatusMsg:
        msg = wire.decode(bytes.fromhex(s.data))
        if not isinstance(msg, wire.StatusMsg):
            raise wire.WireError("bad-field", "a status topic message that is not a heartbeat")
        return msg

    def poll(self, timeout_ms: float) -> list[wire.Message]:
        out: list[wire.Message] = []
        try:
            items = [self._inbox.get(timeout=max(0.0, timeout_ms) / 1000)]
        except queue.Empty:
            items = []
        while True:
            try:
                items.append(self._inbox.get_nowait())
            except queue.Empty:
                break
        for item, arrived in items:
            if isinstance(item, wire.WireError):
                self.accounting.bad(item)
            elif isinstance(item, wire.LabelsMsg):  # counted with the depth image they belong to
                out.append(item)
            elif self.accounting.accept(item, arrived):
                out.append(item)
        self.accounting.check_silence()
        return out

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()
