"""Capture -> OSC sent, and capture -> Pure Data, at 30 Hz with two hands.

The show is the shipped one (profiles/osc.toml: synthetic performer, the `osc` effect with the
default scheme, the profile's output rate), on the real frame loop, sending to a real headless
Pure Data running patches/issv-receiver.pd, which echoes every frame back to this process.
`capture_time` is time.time() when the source delivered the frame (host.Frame), so:

- capture -> sent: until the effect's bundle left the socket (time.time() after sending);
- capture -> Pd echo: until Pd's echo of that frame came back: an upper bound of capture ->
  Pd receiving (it adds Pd's reply over loopback);
- Pd round trip: sent -> echo back;
- and, to show where the time goes: capture -> the backend's update() returned (tracking), and
  from there -> sent (the host's hand-off and the effect).

Target (issue 6): p99 <= 5 ms from capture to Pd receiving.
"""
from __future__ import annotations

import os
import shutil
import socket
import subprocess
import threading
import time
from pathlib import Path

from pythonosc.osc_message import OscMessage

from bench.common import parse_args, percentiles, report
from effects.osc import OscEffect
from host import Stage
from host.assemble import make_backend
from host.loop import EffectSlot, Limits, Show
from host.plugins import default_registry
from host.profile import parse

ROOT = Path(__file__).resolve().parents[1]
PROFILE = ROOT / "profiles" / "osc.toml"
PATCH = ROOT / "patches" / "issv-receiver.pd"
TARGET_P99_MS = 5.0


class TimedOsc(OscEffect):
    """The `osc` effect, noting when each frame's bundle was sent (and that frame's capture time)."""

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.sent: dict[int, tuple[float, float]] = {}  # seq -> (capture_time, sent at)

    def on_frame(self, frame) -> None:
        super().on_frame(frame)
        self.sent[frame.seq] = (frame.capture_time, time.time())


class UdpInbox:
    """A UDP socket on an ephemeral loopback port; a thread hands every datagram to `handle`
    with time.time() at its arrival. Shared with the OSC tests' receiver."""

    def __init__(self) -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        # A burst (Pd echoes every message of a bundle as its own datagram) can outrun this thread
        # while the show holds the GIL; the default 208 KiB buffer then drops datagrams silently.
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.settimeout(0.05)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    @property
    def port(self) -> int:
        return self.sock.getsockname()[1]

    def handle(self, data: bytes, at: float) -> None:
        raise NotImplementedError

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                data = self.sock.recv(65536)
            except (TimeoutError, socket.timeout):
                continue
            except OSError:
                return
            self.handle(data, time.time())

    def close(self) -> None:
        self._stop.set()
        self._thread.join(1)
        self.sock.close()


class Echoes(UdpInbox):
    """Receives Pure Data's echoes; notes when each /echo/frame arrived."""

    def __init__(self) -> None:
        self.frames: dict[int, float] = {}
        self.gestures = 0
        self.ready = threading.Event()
        super().__init__()  # last: the receiving thread starts here

    def handle(self, data: bytes, at: float) -> None:
        message = OscMessage(data)
        if message.address == "/echo/frame":
            self.frames[int(message.params[0])] = at
        elif message.address == "/echo/gesture":
            self.gestures += 1
        elif message.address == "/echo/ready":
            self.ready.set()


def time_updates(backend) -> dict[int, float]:
    """Notes when the backend's update() returned each frame (seq -> time.time())."""
    done: dict[int, float] = {}
    update = backend.update

    def timed():
        frame = update()
        if frame is not None:
            done[frame.seq] = time.time()
        return frame

    backend.update = timed
    return done


def free_port() -> int:
    """An ephemeral UDP port nobody holds right now (tests run in parallel)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def pd_command(listen_port: int, echo_port: int, patch: Path = PATCH) -> list[str]:
    """Headless Pure Data running the receiver patch: OSC in on `listen_port`, echoes out to
    127.0.0.1:`echo_port`."""
    return ["pd", "-nogui", "-noaudio", "-stderr", "-sleepgrain", "0.1", "-open", str(patch),
            "-send", f"issv-listen {listen_port}", "-send", f"issv-echo 127.0.0.1 {echo_port}"]


def start_pd(echo_port: int, listen_port: int) -> subprocess.Popen:
    if shutil.which("pd") is None:
        raise SystemExit("bench.osc: Pure Data is not installed (apt-get install puredata-core)")
    return subprocess.Popen(pd_command(listen_port, echo_port), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def load_profile(backend: str | None):
    """profiles/osc.toml on `backend`, by default the profile's (`truth` until `openiss` is installed)."""
    name = backend or ("openiss" if default_registry().get("backends", "openiss") is not None else "truth")
    return parse(PROFILE.read_text().replace('name = "openiss"', f'name = "{name}"'), str(PROFILE), PROFILE.parent)


def run(seconds: float, fps: float | None, backend: str | None) -> dict:
    profile = load_profile(backend)
    osc = next(r for r in profile.effects if r.ref.name == "osc")
    echoes = Echoes()
    port = free_port()
    pd = start_pd(echoes.port, port)
    try:
        if not echoes.ready.wait(10):
            raise SystemExit("bench.osc: Pure Data did not start the patch")
        effect = TimedOsc(osc.options.model_copy(update={"destinations": [f"127.0.0.1:{port}"]}))
        show_fps = fps or profile.model.output.fps
        source_fps = float(profile.source.options.fps) if profile.source is not None else 30.0
        backend_obj = make_backend(profile, realtime=True)
        tracked = time_updates(backend_obj)
        show = Show(backend_obj, [EffectSlot(effect, "effects[0]")], Stage((640, 480), show_fps, backend_obj.name),
                    limits=Limits(frames=int(seconds * source_fps)))
        metrics = show.run()
        time.sleep(0.3)  # the last echoes
    finally:
        pd.terminate()
        pd.wait(5)
        echoes.close()
    sent = effect.sent
    to_sent = [(s - c) * 1000 for c, s in sent.values()]
    to_pd = [(echoes.frames[q] - c) * 1000 for q, (c, _) in sent.items() if q in echoes.frames]
    tracking = [(tracked[q] - c) * 1000 for q, (c, _) in sent.items()]
    hand_off = [(s - tracked[q]) * 1000 for q, (_, s) in sent.items()]
    round_trip = [(echoes.frames[q] - s) * 1000 for q, (_, s) in sent.items() if q in echoes.frames]
    figures = {
        "backend": backend_obj.name, "source_fps": source_fps, "show_fps": show_fps,
        "sfps": round(metrics.sfps, 2), "frames": metrics.frames, "bundles_sent": len(sent),
        "frames_echoed": len(to_pd), "gestures_sent": sum(metrics.gestures_by_name.values()),
        "gesture_messages_echoed": echoes.gestures,
        "capture_to_tracked_ms": percentiles(tracking, (50, 99)),
        "tracked_to_sent_ms": percentiles(hand_off, (50, 99)),
        "capture_to_sent_ms": percentiles(to_sent, (50, 99)),
        "capture_to_pd_ms": percentiles(to_pd, (50, 99)),
        "pd_round_trip_ms": percentiles(round_trip, (50, 99)),
        "target_p99_ms": TARGET_P99_MS,
        "load_avg_1m": round(os.getloadavg()[0], 2),  # other work on the machine shows in the p99
    }
    figures["target_met"] = bool(figures["capture_to_pd_ms"]["p99"] <= TARGET_P99_MS)
    return figures


def main() -> None:
    args = parse_args(__doc__.splitlines()[0], lambda p: (
        p.add_argument("--seconds", type=float, default=10.0, help="how long to run (default 10)"),
        p.add_argument("--fps", type=float, help="show-loop rate (default: the profile's output.fps)"),
        p.add_argument("--backend", help="backend to use instead of the profile's")))
    f = run(args.seconds, args.fps, args.backend)
    rows = [[name, f[key]["p50"], f[key]["p99"]] for name, key in (
        ("capture -> tracked (backend update)", "capture_to_tracked_ms"),
        ("tracked -> OSC sent (host + effect)", "tracked_to_sent_ms"),
        ("capture -> OSC sent", "capture_to_sent_ms"), ("capture -> Pd (echo back)", "capture_to_pd_ms"),
        ("Pd round trip (sent -> echo)", "pd_round_trip_ms"))]
    rows.append([f"{f['backend']}, {f['source_fps']:.0f} Hz source, show loop {f['show_fps']:.0f} Hz, "
                 f"load average {f['load_avg_1m']}", "", ""])
    rows.append([f"frames {f['frames']}, bundles {f['bundles_sent']}, echoed {f['frames_echoed']}; "
                 f"target p99 <= {TARGET_P99_MS} ms: {'met' if f['target_met'] else 'MISSED'}", "", ""])
    report("OSC latency (ms)", f, rows, ["", "p50", "p99"], args.json)


if __name__ == "__main__":
    main()
