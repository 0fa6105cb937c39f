"""osc-in: rebuilding users at 30 Hz, messages lost on loopback, and its gestures against `issv gestures`.

Two parts, each through real UDP from another process:

1. load: a sender process plays two OSCeleton users of 15 joints at 30 Hz (one bundle per user per
   frame, as OSCeleton sends them) for `--seconds`; the figures are the time osc-in takes per frame
   to rebuild users and both hands of each (target <= 1 ms), the time their recognisers take on
   top (reported apart: the same recogniser every backend runs), and the messages that never
   arrived (target 0).
2. parity: MSRC-12 skeleton streams (ISSV_DATA/msrc12-dev, G1 lift arms and G3 push right: the
   ones with gestures in our dictionary) are sent as OSCeleton (hands, torso, head), each bundle
   stamped with the frame's own time in the file as a time of day, `--speed` times faster than
   real time. osc-in's clock is its time tags' time of day to the nanosecond and it gives
   positions to 0.01 mm, so it sees the file's own times and 0.1 mm positions back exactly
   through 32-bit floats: its gestures must be the event lines `issv gestures --backend osc-in
   --mirrored` prints for the file (hands renumbered: osc-in's 11 and 12 are user 1's), and equal
   the same recogniser run in-process on the file in every field, to the last bit. Each stream
   goes twice: as OSCeleton (32-bit normalised floats, what the bridge sends) and as 64-bit
   millimetres through the custom scheme.
   Skipped without ISSV_DATA.

`python -m bench.osc_in [--seconds 10] [--streams 40] [--speed 20] [--json]`
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

from backends.oscin.backend import OscInBackend, OscInOptions
from backends.oscin.decode import midnight, stamp, time_tag
from bench.common import parse_args, percentiles, report
from host import frames_of
from host.osc import Message, encode_bundle

TARGET_MS = 1.0
JOINTS = ("head", "neck", "torso", "l_shoulder", "l_elbow", "l_hand", "r_shoulder", "r_elbow", "r_hand",
          "l_hip", "l_knee", "l_foot", "r_hip", "r_knee", "r_foot")
ROOT = Path(__file__).resolve().parents[1]


def osceleton_joint(name: str, user: int, x: float, y: float, z: float) -> Message:
    """A `/joint s i f f f` as OSCeleton (and the osc effect's preset) maps millimetres."""
    return Message("/joint", (("s", name), ("i", user), ("f", (x + 1280) / 2560), ("f", (960 - y) / 1920),
                              ("f", z / 1280)))


def _skeleton(user: int, t: float) -> list[Message]:
    """A standing user swinging both forearms: 15 joints, in mm."""
    x0 = -500.0 if user == 1 else 500.0
    out = []
    for k, name in enumerate(JOINTS):
        swing = 150 * math.sin(2 * math.pi * 0.7 * t + k) if name.endswith(("hand", "elbow")) else 0.0
        out.append(osceleton_joint(name, user, x0 + (k % 5 - 2) * 120 + swing, 600 - 110 * k, 2200 + 10 * k))
    return out


def send_load(port: int, seconds: float, fps: float = 30.0) -> None:
    """The sender process: /new_user + /new_skel per user, then two users x 15 joints per frame."""
    import socket
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    for user in (1, 2):
        for address in ("/new_user", "/new_skel"):
            sock.sendto(encode_bundle([Message(address, (("i", user),))], False), ("127.0.0.1", port))
    start, sent = time.perf_counter(), 4
    for i in range(int(seconds * fps)):
        due = start + i / fps
        time.sleep(max(0.0, due - time.perf_counter()))
        for user in (1, 2):
            messages = _skeleton(user, i / fps)
            sock.sendto(encode_bundle(messages, False), ("127.0.0.1", port))
            sent += len(messages)
    print(sent, flush=True)


def _backend(**options) -> OscInBackend:
    return OscInBackend(None, OscInOptions.model_validate({"port": 0, **options}), warn=lambda text: None)


def _env() -> dict:
    return {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}


def load(seconds: float) -> dict:
    with _backend(end_after_idle_s=0.5, lost_timeout_s=0.3) as backend:
        sender = subprocess.Popen([sys.executable, "-m", "bench.osc_in", "--send", str(backend.port), str(seconds)],
                                  stdout=subprocess.PIPE, text=True, env=_env(), cwd=ROOT)
        frames = list(frames_of(backend))
        sent = int(sender.communicate(timeout=seconds + 30)[0].split()[-1])
    rebuild_ms = [s * 1000 for s in backend.rebuild_s]
    recognise_ms = [s * 1000 for s in backend.recognise_s]
    busy = [f for f in frames if len(f.users) == 2]
    return {"seconds": seconds, "frames": len(frames), "frames_with_two_users": len(busy),
            "hands_per_frame": max((len(f.hands) for f in frames), default=0),
            "rebuild_ms": percentiles(rebuild_ms, (50, 99, 100)),
            "recognise_ms": percentiles(recognise_ms, (50, 99, 100)), "messages_sent": sent,
            "messages_received": backend.receiver.messages, "messages_lost": sent - backend.receiver.messages,
            "target_met": percentiles(rebuild_ms, (99,))["p99"] <= TARGET_MS and sent == backend.receiver.messages,
            "load_avg_1m": round(os.getloadavg()[0], 2)}


#: the parity run's wires: OSCeleton's 32-bit normalised floats, and millimetres as 64-bit doubles
#: through the custom scheme (what the transport alone does to the gestures)
DOUBLES = {"scheme": "custom", "messages": [{"address": "/skel/{user}/{joint}", "args": ["{x}", "{y}", "{z}"]}]}


def _double_joint(name: str, user: int, x: float, y: float, z: float) -> Message:
    return Message(f"/skel/{user}/{name}", (("d", x), ("d", y), ("d", z)))


def _stream_messages(path: Path, wire: str) -> list[tuple[float, list[Message]]]:
    from host.commands.gestures import read_trajectories
    names = {"left": "l_hand", "right": "r_hand"}
    joint = osceleton_joint if wire == "osceleton" else _double_joint
    out = []
    for frame in read_trajectories(path):
        messages = [joint(names[h.side.value], 1, *h.position) for h in frame.hands]
        messages += [joint(name, 1, *p) for name, p in frame.body.items()]
        out.append((frame.t, messages))
    return out


def _as_in_file(g):
    """An osc-in gesture as `issv gestures` names it: hands 11 and 12 (user 1) are the file's 1 and 2."""
    return replace(g, hand_id=g.hand_id % 10 if g.hand_id else 0)


def _issv_gestures(path: Path) -> list[str]:
    """The event lines of `issv gestures --backend osc-in --mirrored FILE` (the command's own code)."""
    from host.commands import gestures
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        gestures.main(argparse.Namespace(file=path, backend="osc-in", mirrored=True, learned=[]))
    return out.getvalue().splitlines()


def parity_one(path: Path, speed: float, wire: str = "osceleton") -> dict:
    """One stream sent on `wire` (osceleton, doubles) with its own times as time tags: osc-in's
    gestures against `issv gestures` (its event lines) and against its recogniser run in-process
    on the file (every field of every event, to the last bit)."""
    from host.commands.gestures import read_trajectories, recognizer_for
    recognizer = recognizer_for("osc-in")
    frames = list(read_trajectories(path))
    exact = [g for f in frames for g in recognizer.update(f.t, f.hands, f.body, True)] + recognizer.finish()
    lines = _issv_gestures(path)
    stream = _stream_messages(path, wire)
    options = DOUBLES if wire == "doubles" else {}
    with _backend(end_after_idle_s=2.0, lost_timeout_s=30.0, mirrored=True, **options) as backend:
        import socket
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sender = _Sender(sock, backend.port, stream, speed)
        sender.start()
        got = [_as_in_file(g) for f in frames_of(backend) for g in f.gestures]
        sender.join()
        sock.close()
    return {"stream": path.name, "issv_gestures": len(lines), "osc_in": len(got),
            "same_lines": [json.dumps(g.to_json()) for g in got] == lines, "bit_exact": got == exact,
            "datagrams_lost": len(stream) - backend.receiver.datagrams}


class _Sender:
    """Sends a stream's bundles on a thread, `speed` times faster than real time, each stamped
    with its own time in the file as a time of day (osc-in's clock then reads the file's times)."""

    def __init__(self, sock, port: int, stream, speed: float) -> None:
        import threading
        self.sock, self.port, self.stream, self.speed = sock, port, stream, speed
        self.thread = threading.Thread(target=self.run, daemon=True)

    def start(self) -> None:
        self.thread.start()

    def join(self) -> None:
        self.thread.join()

    def run(self) -> None:
        origin, start, t0 = midnight(time_tag(time.time())), time.perf_counter(), self.stream[0][0]
        for t, messages in self.stream:
            time.sleep(max(0.0, start + (t - t0) / self.speed - time.perf_counter()))
            self.sock.sendto(encode_bundle(messages, False, stamp(origin, t)), ("127.0.0.1", self.port))


def parity(streams: int, speed: float) -> dict | None:
    data = os.environ.get("ISSV_DATA")
    folder = Path(data) / "msrc12-dev" if data else None
    if folder is None or not folder.is_dir() or streams <= 0:
        return None
    paths = sorted(folder.glob("p*_g01_*.csv")) + sorted(folder.glob("p*_g03_*.csv"))
    paths = paths[::max(1, len(paths) // streams)][:streams]
    out = {"streams": len(paths), "speed": speed}
    for wire in ("osceleton", "doubles"):
        rows = [parity_one(path, speed, wire) for path in paths]
        out[wire] = {"same_lines": sum(r["same_lines"] for r in rows), "bit_exact": sum(r["bit_exact"] for r in rows),
                     "gestures": sum(r["issv_gestures"] for r in rows),
                     "datagrams_lost": sum(r["datagrams_lost"] for r in rows), "rows": rows}
        out[wire]["target_met"] = out[wire]["same_lines"] == out[wire]["bit_exact"] == len(paths)
    return out


def main() -> None:
    if len(sys.argv) == 4 and sys.argv[1] == "--send":
        send_load(int(sys.argv[2]), float(sys.argv[3]))
        return
    args = parse_args(__doc__.splitlines()[0], lambda p: (
        p.add_argument("--seconds", type=float, default=10.0, help="length of the load run (default 10)"),
        p.add_argument("--streams", type=int, default=40, help="MSRC-12 streams for the parity run (default 40)"),
        p.add_argument("--speed", type=float, default=20.0, help="how much faster than real time they are sent")))
    f = {"load": load(args.seconds), "parity": parity(args.streams, args.speed)}
    lo = f["load"]
    rows = [["rebuild users + hands per frame (ms)", lo["rebuild_ms"]["p50"], lo["rebuild_ms"]["p99"],
             lo["rebuild_ms"]["p100"]],
            ["their gesture recognisers per frame (ms)", lo["recognise_ms"]["p50"], lo["recognise_ms"]["p99"],
             lo["recognise_ms"]["p100"]],
            [f"2 users x 15 joints at 30 Hz for {lo['seconds']:.0f} s: {lo['frames']} frames "
             f"({lo['frames_with_two_users']} with both users, {lo['hands_per_frame']} hands)", "", "", ""],
            [f"messages sent {lo['messages_sent']}, received {lo['messages_received']}, lost {lo['messages_lost']}; "
             f"target p99 <= {TARGET_MS} ms and 0 lost: {'met' if lo['target_met'] else 'MISSED'}; "
             f"load average {lo['load_avg_1m']}", "", "", ""]]
    pa = f["parity"]
    if pa is None:
        rows.append(["parity: skipped (--streams 0, or ISSV_DATA not set to the shared data folder)", "", "", ""])
    else:
        for wire, label in (("osceleton", "OSCeleton's 32-bit floats"), ("doubles", "custom scheme, 64-bit mm")):
            w = pa[wire]
            rows.append([f"parity, {label}, sent at {pa['speed']:.0f}x with time tags: {w['same_lines']} of "
                         f"{pa['streams']} MSRC-12 streams print the same {w['gestures']} event lines as issv gestures "
                         f"--backend osc-in --mirrored; {w['bit_exact']} of {pa['streams']} bit-exact (target: all, "
                         f"{'met' if w['target_met'] else 'MISSED'}); datagrams lost {w['datagrams_lost']}", "", "", ""])
            rows += [[f"  {r['stream']}: {r['issv_gestures']} vs {r['osc_in']} events, {r['datagrams_lost']} "
                      f"datagrams lost", "", "", ""] for r in w["rows"] if not (r["same_lines"] and r["bit_exact"])]
    report("osc-in", f, rows, ["", "p50", "p99", "max"], args.json)


if __name__ == "__main__":
    main()
