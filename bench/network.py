"""The thesis' Table 16 (ROS overhead) side by side: ZeroMQ and ROS, unshaped and at 100 Mbit/s.

A publisher process sends 640x480 Kinect-like depth at 30 Hz with two hands and one gesture event
per frame; a subscriber process (the `network` backend) counts and times what arrives. Unshaped:
both on loopback. 100 Mbit/s: two network namespaces joined by a veth pair shaped with `tc ... tbf
rate 100mbit` on both ends (needs root; skipped with the reason otherwise). Also measured: the
lossless depth codecs (which one `issv serve` uses by default, and why).

The machine's load average is reported with each row: on a shared machine, p99 latencies and
newest-wins depth drops measure CPU starvation as much as the network.

Targets (issue 9): 0 % depth loss at 30 Hz 640x480 over 100 Mbit/s (thesis, ROS: 35 %); gestures
and hands 0 % lost and <= 2 ms p99 on loopback; depth latency <= 1.3 x the time the link needs to
carry one compressed frame. That time counts what the link carries: the message plus the Ethernet,
IP and TCP headers of each segment (measured: 11.94 MB/s of TCP payload through the shaped pair,
against 11.96 predicted and 12.5 for payload alone).

    python -m bench.network [--json] [--seconds S] [--only zmq|ros]
    python -m bench.network publish|subscribe ...   (the two roles; tests use them too)
    python -m bench.network labels [--json]         (the user label image's cost alone)

Also measured: the user label image that rides in each depth message (its `labels` table: bytes
and encode/decode ms at 640x480 on the synthetic duet, zstd as sent against run-length, and what
it adds to a whole depth message).
"""
from __future__ import annotations

import argparse
import glob
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import uuid
from pathlib import Path

import numpy as np

from bench.common import add_data_argument, data_set, report, stop
from host import DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Side

ROOT = Path(__file__).resolve().parents[1]
RATE_BPS = 100e6  # tc's "100mbit": 100,000,000 bit/s of whole Ethernet frames
MSS, FRAME_HEADERS = 1448, 66  # TCP payload per segment at MTU 1500 (with timestamps); Ethernet + IP + TCP


def carry_ms(message_bytes: float) -> float:
    """Time the shaped link needs to carry one message: its bytes plus the Ethernet, IP and TCP
    headers of every segment (tbf counts whole frames: 1514 bytes per 1448 of payload)."""
    segments = -(-message_bytes // MSS)
    return (message_bytes + segments * FRAME_HEADERS) * 8 / RATE_BPS * 1000


# -- a Kinect-like depth stream ----------------------------------------------------------------
def _raw_to_mm(raw):
    """libfreenect's disparity -> metres formula (x1000): Kinect v1 depth is quantised like this."""
    return 1000.0 / (3.3309495161 - 0.0030711016 * raw)


def _mm_to_raw(z):
    return (3.3309495161 - 1000.0 / z) / 0.0030711016


def kinect_like(n: int, size: tuple[int, int] = (640, 480), seed: int = 0,
                clips: Path | None = None) -> list[np.ndarray]:
    """`n` depth images of a room (back wall 4.2 m, floor, side wall, 40 boxes) with a real
    performer from a UTD-MHAD clip in front, seen through Kinect v1's 11-bit disparity with one
    unit of noise, 1 % dropouts and shadow bands at depth edges (no performer when `clips`, the
    UTD-MHAD clips folder, is None). A model, not a recording: the codec table also reports the
    real (background-removed, 320x240) clips."""
    w, h = size
    rng = np.random.default_rng(seed)
    v, u = np.mgrid[0:h, 0:w].astype(np.float64)
    f = (w / 2) / np.tan(np.radians(28.5))
    z = np.full((h, w), 4200.0)
    z = np.minimum(z, np.where(v > h / 2 + 1, 1000.0 * f / np.maximum(v - h / 2, 1e-3), np.inf))
    z = np.minimum(z, np.where(u < w / 2 - 1, 1800.0 * f / np.maximum(w / 2 - u, 1e-3), np.inf))
    for _ in range(40):
        x0, y0 = rng.integers(0, w - 40), rng.integers(0, h - 40)
        z[y0:y0 + rng.integers(10, 120), x0:x0 + rng.integers(10, 160)] = rng.uniform(1500, 4000)
    performer = np.load(sorted(glob.glob(str(clips / "*wave*.npz")))[0])["depth"] if clips is not None else None
    out = []
    for i in range(n):
        zz = z
        if performer is not None:
            p = performer[i % len(performer)].astype(np.float64)
            p = np.kron(p, np.ones((h // p.shape[0], w // p.shape[1])))
            zz = np.where(p > 0, np.minimum(p, z), z)
        raw = np.round(_mm_to_raw(zz) + rng.normal(0, 1.0, zz.shape))
        mm = np.round(_raw_to_mm(raw))
        mm[(mm < 500) | (mm > 6000) | (rng.random(mm.shape) < 0.01)] = 0
        edge = np.abs(np.diff(zz, axis=1, prepend=zz[:, :1])) > 200
        mm[np.roll(edge, -3, axis=1) | np.roll(edge, -5, axis=1)] = 0
        out.append(mm.astype(np.uint16))
    return out


def stream(seconds: float, fps: float = 30.0, size: tuple[int, int] = (640, 480), clips: Path | None = None):
    """Frames paced at `fps` (capture time = now), each with two hands and one gesture event."""
    images = kinect_like(30, size, clips=clips)
    intr = Intrinsics.from_fov(size[0], size[1], 57, 43)
    types = list(GestureType)
    start = time.perf_counter()
    for i in range(int(seconds * fps)):
        delay = start + i / fps - time.perf_counter()
        if delay > 0:
            time.sleep(delay)
        now = time.time()
        depth = DepthFrame(images[i % len(images)], intr, frame_id=i, timestamp=i / fps, capture_time=now)
        a = i / fps
        hands = (Hand(1, HandState.TRACKING, (-300 + 100 * np.sin(a), 0.0, 2000.0), Side.LEFT),
                 Hand(2, HandState.TRACKING, (300.0, 100 * np.cos(a), 2000.0), Side.RIGHT))
        state = GestureState.COMPLETE if i % 2 else GestureState.IN_PROGRESS
        gesture = Gesture(types[(i // 2) % len(types)], state, hands[1].position, 2, Side.RIGHT, 0.9, a)
        yield Frame(i + 1, now, depth, hands, (gesture,), "bench")


# -- two network namespaces joined by a shaped veth pair -----------------------------------------
class LinkPair:
    """Namespaces A and B on 10.X.Y.1 and .2, a veth pair between them, tbf on both ends."""

    def __init__(self, rate: str = "100mbit") -> None:
        tag = uuid.uuid4().hex[:6]
        self.ns_a, self.ns_b = f"issv-a-{tag}", f"issv-b-{tag}"
        self.dev_a, self.dev_b = f"iva{tag}", f"ivb{tag}"
        octet = int(tag[:2], 16) % 200 + 20
        self.ip_a, self.ip_b = f"10.{octet}.77.1", f"10.{octet}.77.2"
        self.rate = rate

    @staticmethod
    def unavailable() -> str | None:
        """None if namespaces, veth and tbf can be created here; else why not."""
        if shutil.which("ip") is None or shutil.which("tc") is None:
            return "`ip` or `tc` (iproute2) is not installed"
        if os.geteuid() != 0:
            return "creating network namespaces needs root"
        probe = LinkPair()
        try:
            probe.__enter__()
        except (subprocess.CalledProcessError, OSError) as error:
            return f"cannot create a namespace pair here: {getattr(error, 'stderr', '') or error}".strip()
        finally:
            probe.__exit__()
        return None

    def _ip(self, *args: str) -> None:
        subprocess.run(["ip", *args], check=True, capture_output=True, text=True)

    def __enter__(self) -> "LinkPair":
        try:
            self._ip("netns", "add", self.ns_a)
            self._ip("netns", "add", self.ns_b)
            self._ip("link", "add", self.dev_a, "type", "veth", "peer", "name", self.dev_b)
            for ns, dev, ip in ((self.ns_a, self.dev_a, self.ip_a), (self.ns_b, self.dev_b, self.ip_b)):
                self._ip("link", "set", dev, "netns", ns)
                self._ip("-n", ns, "addr", "add", f"{ip}/24", "dev", dev)
                self._ip("-n", ns, "link", "set", dev, "up")
                self._ip("-n", ns, "link", "set", "lo", "up")
                if self.rate:
                    subprocess.run(["tc", "-n", ns, "qdisc", "add", "dev", dev, "root", "tbf", "rate", self.rate,
                                    "burst", "32kbit", "latency", "400ms"], check=True, capture_output=True)
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        for ns in (self.ns_a, self.ns_b):  # deleting a namespace deletes its end of the veth pair
            subprocess.run(["ip", "netns", "del", ns], capture_output=True)

    def prefix(self, side: str) -> list[str]:
        return ["ip", "netns", "exec", self.ns_a if side == "a" else self.ns_b]


# -- the two roles ------------------------------------------------------------------------------
def publish_main(args: argparse.Namespace) -> int:
    from backends.network.publisher import DepthOptions
    depth = DepthOptions(codec=args.codec) if args.codec else DepthOptions()
    if args.transport == "ros":
        from backends.network.ros import RosPublisher
        pub = RosPublisher(args.bind, "/openiss", depth, "bench")
    else:
        from backends.network.publisher import Publisher
        pub = Publisher(args.bind, depth, "bench")
    if not pub.wait_for_subscriber(args.wait):
        print("bench publisher: no subscriber came", file=sys.stderr)
    time.sleep(0.5)  # the depth subscription travels on its own connection
    frames = 0
    for frame in stream(args.seconds, size=tuple(args.size), clips=utd_clips(args, quiet=True)):
        pub.publish(frame)
        frames += 1
    time.sleep(0.5)  # let the last depth images leave before saying goodbye
    pub.close()
    print(json.dumps({"frames": frames, **pub.stats()}), flush=True)
    return 0


def subscribe_main(args: argparse.Namespace) -> int:
    from backends.network.backend import NetworkBackend, NetworkOptions
    options = NetworkOptions(connect=args.connect, transport=args.transport, end_with_publisher=True,
                             ros_depth=args.ros_depth)
    backend = NetworkBackend(None, options)
    frames = gestures = 0
    dumped: list[DepthFrame] = []
    labels: list[np.ndarray | None] = []  # the user labels that came with each dumped depth image
    deadline = time.monotonic() + args.timeout
    with backend:
        print("subscribed", file=sys.stderr, flush=True)
        while time.monotonic() < deadline:
            frame = backend.update()
            if frame is None:
                break
            if frame is False:  # nothing yet: the deadline is checked
                continue
            frames += 1
            gestures += len(frame.gestures)
            if args.dump and frame.depth is not None and (not dumped or dumped[-1] is not frame.depth):
                dumped.append(frame.depth)
                labels.append(frame.user_labels)
        stats = backend.stats()
    if args.dump:
        shape = dumped[0].data.shape if dumped else (0, 0)
        np.savez(args.dump, frame_ids=np.array([d.frame_id for d in dumped], dtype=np.int64),
                 timestamps=np.array([d.timestamp for d in dumped], dtype=np.float64),
                 depth=np.array([d.data for d in dumped], dtype=np.uint16).reshape(-1, *shape),
                 has_labels=np.array([x is not None for x in labels], dtype=bool),
                 labels=np.array([np.zeros(shape, np.uint8) if x is None else x for x in labels],
                                 dtype=np.uint8).reshape(-1, *shape))
    print(json.dumps({"frames": frames, "gestures": gestures, **stats}), flush=True)
    return 0


# -- the table ---------------------------------------------------------------------------------
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_line(proc: subprocess.Popen, text: str, timeout: float, stream: str = "stderr") -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        line = getattr(proc, stream).readline()
        if text in line:
            return
        if not line and proc.poll() is not None:
            break
    raise RuntimeError(f"a bench process did not say {text!r}")


def run_case(transport: str, shaped: bool, seconds: float, data: Path | None = None) -> dict:
    """One row: publisher and subscriber processes over loopback or the shaped veth pair."""
    link = LinkPair() if shaped else None
    procs: list[subprocess.Popen] = []
    env = {"ROS_HOME": "/tmp/issv-bench-ros", **os.environ, "PYTHONPATH": str(ROOT)}
    try:
        pre_a = pre_b = []
        host_a = "127.0.0.1"
        env_a, env_b = dict(env), dict(env)
        if link is not None:
            link.__enter__()
            pre_a, pre_b, host_a = link.prefix("a"), link.prefix("b"), link.ip_a
            env_a["ROS_IP"], env_b["ROS_IP"] = link.ip_a, link.ip_b
        port = _free_port()
        if transport == "ros":
            env_a["ROS_IP"] = env_a.get("ROS_IP", "127.0.0.1")
            env_b["ROS_IP"] = env_b.get("ROS_IP", "127.0.0.1")
            master = f"http://{host_a}:{port}"
            for e in (env_a, env_b):
                e["ROS_MASTER_URI"] = master
            core = subprocess.Popen([*pre_a, "roscore", "-p", str(port)], env=env_a, stdout=subprocess.PIPE,
                                    stderr=subprocess.DEVNULL, text=True, start_new_session=True)
            procs.append(core)
            _wait_line(core, "started core service", 30, "stdout")
            addr = master
        else:
            addr = f"tcp://{host_a}:{port}"
        py = [sys.executable, "-m", "bench.network", *(["--data", str(data)] if data is not None else [])]
        sub = subprocess.Popen([*pre_b, *py, "subscribe", "--connect", addr, "--transport", transport,
                                "--timeout", str(seconds + 30)], env=env_b, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=ROOT, start_new_session=True)
        procs.append(sub)
        _wait_line(sub, "subscribed", 30)
        pub = subprocess.Popen([*pre_a, *py, "publish", "--bind", addr, "--transport", transport,
                                "--seconds", str(seconds)], env=env_a, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=ROOT, start_new_session=True)
        procs.append(pub)
        sent = json.loads(pub.communicate(timeout=seconds + 60)[0].strip().splitlines()[-1])
        got = json.loads(sub.communicate(timeout=30)[0].strip().splitlines()[-1])
    finally:
        for p in reversed(procs):
            stop(p)
        if link is not None:
            link.__exit__()
    return _row(transport, shaped, sent, got)


def _row(transport: str, shaped: bool, sent: dict, got: dict) -> dict:
    s = got["streams"]
    offered = {"depth": sent["frames"], "hands": sent["sent"]["hands"], "gestures": sent["sent"]["gestures"]}
    loss = {k: round(100.0 * (1 - s[k]["received"] / offered[k]), 2) if offered[k] else None for k in offered}
    frame_bytes = (sent["depth_bytes"] / sent["sent"]["depth"]) if sent.get("depth_bytes") else 640 * 480 * 2
    carry = carry_ms(frame_bytes) if shaped else None
    return {"transport": transport, "link": "100 Mbit/s" if shaped else "loopback", "offered": offered,
            "loss_pct": loss, "depth_skipped_by_publisher": sent.get("depth_skipped", 0),
            "load_average": round(os.getloadavg()[0], 2), "latency_ms": {k: s[k]["latency_ms"] for k in s},
            "depth_frame_kB": round(frame_bytes / 1000, 1), "carry_ms": carry and round(carry, 2),
            "depth_latency_over_carry": (round(s["depth"]["latency_ms"]["p50"] / carry, 2)
                                     if carry and s["depth"]["received"] else None),
            "malformed": got["malformed"]}


def codecs_table(clips_dir: Path | None) -> list[dict]:
    from backends.network import wire
    from sources.clip import Clip
    sets = {"kinect-like 640x480": kinect_like(10, clips=clips_dir)}
    clips = sorted(clips_dir.glob("*.npz"))[:20] if clips_dir is not None else []
    if clips:
        sets["UTD-MHAD clips 320x240"] = [Clip(p).depth[len(Clip(p)) // 2] for p in clips]
    rows = []
    for label, images in sets.items():
        for codec in wire.CODECS.values():
            enc, dec, size = [], [], 0
            for img in images:
                t0 = time.perf_counter()
                blob = codec.encode(img)
                t1 = time.perf_counter()
                back = codec.decode(blob, img.shape)
                dec.append(time.perf_counter() - t1)
                enc.append(t1 - t0)
                size += len(blob)
                assert np.array_equal(back, img), codec.name
            rows.append({"images": label, "codec": codec.name, "ratio": round(sum(i.nbytes for i in images) / size, 2),
                         "encode_ms": round(float(np.median(enc)) * 1000, 2),
                         "decode_ms": round(float(np.median(dec)) * 1000, 2)})
    return rows


def duet_labels(n: int = 24, step: int = 15) -> list[tuple[DepthFrame, np.ndarray]]:
    """Depth and user labels of the synthetic duet at 640x480, every `step`th frame (crossings included)."""
    from backends.truth import TruthBackend
    from sources.synthetic import SyntheticOptions, SyntheticSource
    out = []
    with TruthBackend(SyntheticSource(SyntheticOptions(scene="duet", seed=1))) as backend:
        for i in range(n * step):
            frame = backend.update()
            if i % step == 0:
                out.append((frame.depth, frame.user_labels))
    return out


def _runs(labels: np.ndarray) -> bytes:
    """Run-length labels (the alternative measured): u32 run starts where the value changes, values."""
    flat = labels.ravel()
    starts = np.flatnonzero(np.diff(flat, prepend=np.int16(-1)))
    return np.uint32(len(starts)).tobytes() + starts.astype("<u4").tobytes() + flat[starts].tobytes()


def _unruns(blob: bytes, shape: tuple[int, int]) -> np.ndarray:
    n = int(np.frombuffer(blob, "<u4", 1)[0])
    starts = np.frombuffer(blob, "<u4", n, 4)
    values = np.frombuffer(blob, np.uint8, n, 4 + 4 * n)
    return np.repeat(values, np.diff(np.append(starts, shape[0] * shape[1]))).reshape(shape)


def labels_table() -> list[dict]:
    """The user label image's cost on the wire at 640x480: its block (zstd, as sent and recorded)
    against run-length, and what it adds to a whole depth message (encode + decode)."""
    from backends.network import wire
    pairs = duet_labels()
    ways = {"zstd-1 (wire, recording)": (wire.encode_labels,
                                         lambda b, shape: wire._decode_labels(memoryview(b), 0, shape)[0]),
            "run-length (numpy)": (_runs, _unruns)}
    rows = []
    for name, (encode, decode) in ways.items():
        enc, dec, sizes = [], [], []
        for _, labels in pairs:
            t0 = time.perf_counter()
            blob = encode(labels)
            t1 = time.perf_counter()
            back = decode(blob, labels.shape)
            dec.append(time.perf_counter() - t1)
            enc.append(t1 - t0)
            sizes.append(len(blob))
            assert np.array_equal(back, labels), name
        rows.append({"what": name, "bytes_p50": int(np.median(sizes)), "bytes_max": max(sizes),
                     "ratio": round(pairs[0][1].nbytes / float(np.median(sizes)), 1),
                     "encode_ms": round(float(np.median(enc)) * 1000, 3),
                     "decode_ms": round(float(np.median(dec)) * 1000, 3)})
    for codec in ("banded-zstd", "raw"):  # a whole depth message, with and without its labels
        for with_labels in (False, True):
            enc, dec, sizes = [], [], []
            for depth, labels in pairs:
                t0 = time.perf_counter()
                msg = wire.encode_depth(1, 1, 0.0, 1, depth, codec, labels=labels if with_labels else None)
                t1 = time.perf_counter()
                wire.decode(msg)
                dec.append(time.perf_counter() - t1)
                enc.append(t1 - t0)
                sizes.append(len(msg))
            rows.append({"what": f"depth message {codec}{' + labels' if with_labels else ''}",
                         "bytes_p50": int(np.median(sizes)), "bytes_max": max(sizes), "ratio": None,
                         "encode_ms": round(float(np.median(enc)) * 1000, 3),
                         "decode_ms": round(float(np.median(dec)) * 1000, 3)})
    return rows


def utd_clips(args: argparse.Namespace, quiet: bool = False) -> Path | None:
    """The UTD-MHAD clips in --data (a real performer in the kinect-like images, the real codec rows)."""
    if quiet and (args.data is None or not (args.data / "utd-mhad-dev").is_dir()):
        return None
    utd = data_set(args, "utd-mhad-dev", "the real performer in the kinect-like images and the real codec rows")
    return utd / "clips" if utd is not None else None


def table_main(args: argparse.Namespace) -> int:
    from backends.network.ros import rospy_missing
    notes = []
    transports = [t for t in ("zmq", "ros") if args.only in (None, t)]
    if "ros" in transports and (why := rospy_missing()):
        transports.remove("ros")
        notes.append(f"ROS skipped: {why}")
    links = [False]
    why = LinkPair.unavailable()
    if why is None:
        links.append(True)
    else:
        notes.append(f"100 Mbit/s skipped: {why}")
    clips = utd_clips(args)
    rows = [run_case(t, shaped, args.seconds, args.data) for t in transports for shaped in links]
    codecs = codecs_table(clips)
    labels = labels_table()
    figures = {"cases": rows, "codecs": codecs, "labels": labels, "load_average": os.getloadavg()[0], "notes": notes, "seconds": args.seconds,
               "thesis_table16": {"100 Mbps": {"depth": 35, "gesture": 0, "hands": 0},
                                  "1 Gbps": {"depth": 0, "gesture": 0, "hands": 0}}}
    columns = ["", "link", "loss %", "depth ms", "gest ms", "hand ms", "kB", "x carry", "load"]

    def lat(r: dict, k: str) -> str:
        t = r["latency_ms"][k]
        return "-" if t["p50"] is None else f"{t['p50']:.1f}/{t['p99']:.1f}"

    def loss(r: dict) -> str:
        pct = r["loss_pct"]
        return "/".join("-" if pct[k] is None else f"{pct[k]:g}" for k in ("depth", "gestures", "hands"))

    table = [[r["transport"], "100M" if r["link"] != "loopback" else "lo", loss(r), lat(r, "depth"),
              lat(r, "gestures"), lat(r, "hands"), f"{r['depth_frame_kB']:.0f}",
              f"{r['depth_latency_over_carry']:.2f}" if r["depth_latency_over_carry"] is not None else "-",
              f"{r['load_average']:.1f}"] for r in rows]
    table += [["thesis", "100M", "35/0/0", "-", "-", "-", "614", "-", "-"],
              ["thesis", "1G", "0/0/0", "16 mean", "-", "-", "614", "-", "-"]]
    report("Table 16 side by side, 30 Hz 640x480 (loss % depth/gesture/hands, ms p50/p99)", figures, table,
           columns, args.json)
    if not args.json:
        report("lossless depth codecs", {}, [list(r.values()) for r in codecs], list(codecs[0]), False)
        report(f"user labels, synthetic duet 640x480 (raw {640 * 480} bytes; load {os.getloadavg()[0]:.1f})", {},
               [["-" if v is None else v for v in r.values()] for r in labels], list(labels[0]), False)
        for note in notes:
            print(note)
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="role")
    p = sub.add_parser("publish")
    p.add_argument("--bind", required=True)
    p.add_argument("--transport", choices=("zmq", "ros"), default="zmq")
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--size", type=int, nargs=2, default=(640, 480))
    p.add_argument("--codec")
    p.add_argument("--wait", type=float, default=20.0)
    s = sub.add_parser("subscribe")
    s.add_argument("--connect", required=True)
    s.add_argument("--transport", choices=("zmq", "ros"), default="zmq")
    s.add_argument("--ros-depth", choices=("frame", "image"), default="frame")
    sub.add_parser("labels", help="only the user labels table (seconds, not minutes)")
    s.add_argument("--timeout", type=float, default=60.0)
    s.add_argument("--dump", metavar="FILE.npz",
                   help="save the depth images received (frame_ids, timestamps, depth, has_labels, labels)")
    parser.add_argument("--json", action="store_true", help="print one JSON object of the figures")
    add_data_argument(parser)
    parser.add_argument("--seconds", type=float, default=20.0,
                        help="length of each case (default 20: 600 frames, so a p99 rests on 6 samples)")
    parser.add_argument("--only", choices=("zmq", "ros"), help="one transport only")
    args = parser.parse_args(argv)
    if args.role == "publish":
        return publish_main(args)
    if args.role == "subscribe":
        return subscribe_main(args)
    if args.role == "labels":
        rows = labels_table()
        report(f"user labels, synthetic duet 640x480 (raw {640 * 480} bytes; load {os.getloadavg()[0]:.1f})",
               {"labels": rows, "load_average": os.getloadavg()[0]},
               [["-" if v is None else v for v in r.values()] for r in rows], list(rows[0]), args.json)
        return 0
    return table_main(args)


if __name__ == "__main__":
    sys.exit(main())
