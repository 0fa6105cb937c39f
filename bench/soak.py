"""An hour on stage: the stage profile with tracking, OSC and recording at 30 Hz, for a long time.

    python -m bench.soak [--minutes 60] [--json] [--profile profiles/stage.toml] [--size 640x360]

The show is the real one: the profile's synthetic performer (30 Hz, paced), the open engine, its
effects rendered headless (EGL), plus the `osc` effect sending to a UDP socket of this process
and every tracked frame recorded to an MCAP file (as `issv record` does). A sampler thread notes
every --sample seconds the process's resident memory, its open file handles and the show's
counters. After the warm-up (--warmup, default a tenth of the run, at most 5 minutes) it reports:

- memory growth: resident MB at the end minus after warm-up, and the least-squares slope in MB per
  hour (target: growth < 5 MB);
- frame-time drift: sFPS, rFPS and capture-to-effect latency p50/p99 in the first and the last
  window after warm-up;
- dropped frames (newest-wins skips, counted by the host), frames the backend failed on;
- open file handles after warm-up and at the end (a leak grows them);
- OSC datagrams received, the recording's size.
"""
from __future__ import annotations

import os
import tempfile
import threading
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from bench.common import parse_args, report
from bench.osc import UdpInbox
from effects.osc import OscEffect
from host import profile as profiles
from host.assemble import make_backend, make_effects, make_stage
from host.loop import EffectSlot, Limits, Show
from host.plugins import default_manager
from host.recording import RecordingWriter
from host.tap import SensorTap

ROOT = Path(__file__).resolve().parents[1]
SENSOR_HZ = 30.0
TARGET_GROWTH_MB = 5.0


def rss_mb() -> float:
    """Resident memory of this process (MB), from /proc (Linux)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6


def open_handles() -> int:
    return len(os.listdir("/proc/self/fd"))


class Counter(UdpInbox):
    """Counts the OSC datagrams the show sent."""

    count = 0

    def handle(self, data: bytes, at: float) -> None:
        self.count += 1


@dataclass
class Sample:
    t: float  # seconds since the show started
    rss_mb: float
    handles: int
    frames: int
    rendered: int
    dropped: int
    failed: int
    latencies: int  # how many capture-to-effect latencies the host has recorded so far


class Sampler:
    """Every `period` seconds, one Sample of the process and the show's counters."""

    def __init__(self, show: Show, period: float) -> None:
        self.show, self.period = show, period
        self.samples: list[Sample] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="soak-sampler", daemon=True)
        self._start = time.monotonic()

    def take(self) -> None:
        m = self.show.metrics
        self.samples.append(Sample(time.monotonic() - self._start, rss_mb(), open_handles(), m.frames,
                                   m.rendered, m.dropped, m.failed, len(m.latencies_ms)))

    def _run(self) -> None:
        while not self._stop.wait(self.period):
            self.take()

    def __enter__(self) -> "Sampler":
        self.take()
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()
        self.take()


def window(a: Sample, b: Sample, latencies: np.ndarray) -> dict:
    """Rates and latency between two samples."""
    dt = max(b.t - a.t, 1e-9)
    lat = latencies[a.latencies:b.latencies]
    p50, p99 = (np.percentile(lat, [50, 99]) if lat.size else (float("nan"),) * 2)
    return {"from_s": round(a.t, 1), "to_s": round(b.t, 1), "sfps": (b.frames - a.frames) / dt,
            "rfps": (b.rendered - a.rendered) / dt, "latency_p50_ms": float(p50), "latency_p99_ms": float(p99),
            "dropped": b.dropped - a.dropped, "rss_mb": b.rss_mb, "handles": b.handles}


def soak(profile: Path, seconds: float, size: tuple[int, int] | None, sample_s: float, warmup_s: float,
         out_dir: Path) -> dict:
    prof = profiles.load(profile)
    output = prof.model.output
    output.mode, output.fps = "headless", SENSOR_HZ
    if size is not None:
        output.size = size
    backend = make_backend(prof, realtime=True)
    inbox = Counter()
    osc = OscEffect(OscEffect.Options(destinations=[f"127.0.0.1:{inbox.port}"]))
    effects = [s for s in make_effects(prof) if s.effect.name != "console"]  # an hour of printed events: no
    effects.append(EffectSlot(osc, "soak osc"))
    recording = out_dir / "soak.mcap"
    writer = RecordingWriter(recording, {"profile": str(profile), "backend": backend.name, "source": "soak"})
    tap = SensorTap(backend, writer.write_frame, closed=writer.close, observe_end=writer.write_end_gestures)
    stage = make_stage(prof, backend)
    from host.render import make_renderer  # moderngl only when the bench runs
    renderer = make_renderer(output, stage) if any(s.effect.renders for s in effects) else None
    show = Show(tap, effects, stage, pm=default_manager(), limits=Limits(seconds=seconds), renderer=renderer)
    with Sampler(show, sample_s) as sampler:
        metrics = show.run()
    inbox.close()
    samples = sampler.samples
    latencies = np.frombuffer(metrics.latencies_ms, dtype=np.float64)
    warm = next((s for s in samples if s.t >= warmup_s), samples[-1])
    after = [s for s in samples if s.t >= warm.t]
    windows = [window(a, b, latencies) for a, b in zip(samples, samples[1:])]
    steady = [w for w in windows if w["from_s"] >= warm.t - 1e-6
              and w["to_s"] - w["from_s"] >= sample_s / 2]  # the last, partial window is too short to say
    slope = (float(np.polyfit([s.t for s in after], [s.rss_mb for s in after], 1)[0]) * 3600
             if len(after) >= 3 else float("nan"))
    first, last = (steady[0], steady[-1]) if steady else ({}, {})
    return {
        "seconds": round(samples[-1].t, 1), "warmup_s": round(warm.t, 1), "size": list(output.size),
        "sensor_hz": SENSOR_HZ, "frames": metrics.frames, "rendered": metrics.rendered,
        "dropped": metrics.dropped, "failed": metrics.failed, "gestures": metrics.gestures,
        "rss_mb": {"start": round(samples[0].rss_mb, 1), "after_warmup": round(warm.rss_mb, 1),
                   "end": round(samples[-1].rss_mb, 1), "max": round(max(s.rss_mb for s in samples), 1)},
        "growth_mb": round(samples[-1].rss_mb - warm.rss_mb, 2), "growth_mb_per_hour": round(slope, 2),
        "target_growth_mb": TARGET_GROWTH_MB,
        "handles": {"after_warmup": warm.handles, "end": samples[-1].handles, "max": max(s.handles for s in samples)},
        "drift": {"first": first, "last": last},
        "osc_datagrams": inbox.count, "recording_mb": round(recording.stat().st_size / 1e6, 1),
        "recorded_frames": writer.frames, "windows": windows, "samples": [asdict(s) for s in samples],
    }


def size_arg(text: str) -> tuple[int, int]:
    w, h = (int(v) for v in text.lower().split("x"))
    return (w, h)


def main() -> None:
    args = parse_args(__doc__.splitlines()[0], lambda p: (
        p.add_argument("--minutes", type=float, default=60.0, help="how long the show runs (default 60)"),
        p.add_argument("--profile", type=Path, default=ROOT / "profiles" / "stage.toml"),
        p.add_argument("--size", type=size_arg, metavar="WxH", help="output size (default: the profile's)"),
        p.add_argument("--sample", type=float, default=None, metavar="S",
                       help="seconds between samples (default: a sixtieth of the run, 1 to 60)"),
        p.add_argument("--warmup", type=float, default=None, metavar="S",
                       help="seconds not counted in growth and drift (default: a tenth of the run, at most 300)")))
    seconds = args.minutes * 60
    sample = args.sample or min(60.0, max(1.0, seconds / 60))
    warmup = args.warmup if args.warmup is not None else min(300.0, seconds / 10)
    with tempfile.TemporaryDirectory(prefix="issv-soak-") as tmp:
        f = soak(args.profile, seconds, args.size, sample, warmup, Path(tmp))
    first, last = f["drift"]["first"], f["drift"]["last"]
    rows = [["duration / warm-up (s)", f"{f['seconds']} / {f['warmup_s']}"],
            ["frames / rendered / dropped / failed", f"{f['frames']} / {f['rendered']} / {f['dropped']} / {f['failed']}"],
            ["RSS start / after warm-up / end / max (MB)",
             " / ".join(str(f["rss_mb"][k]) for k in ("start", "after_warmup", "end", "max"))],
            ["memory growth after warm-up (MB; target < 5)", f"{f['growth_mb']:+.2f} ({f['growth_mb_per_hour']:+.2f} MB/h)"],
            ["open handles after warm-up / end / max", f"{f['handles']['after_warmup']} / {f['handles']['end']} / "
                                                       f"{f['handles']['max']}"],
            ["OSC datagrams / recorded frames / recording MB",
             f"{f['osc_datagrams']} / {f['recorded_frames']} / {f['recording_mb']}"]]
    for key, label in (("sfps", "sFPS"), ("rfps", "rFPS"), ("latency_p50_ms", "latency p50 (ms)"),
                       ("latency_p99_ms", "latency p99 (ms)")):
        if first:
            rows.append([f"{label}: first / last window", f"{first[key]:.2f} / {last[key]:.2f}"])
    report(f"soak: {args.profile.name}, {f['size'][0]}x{f['size'][1]}, sensor {SENSOR_HZ:.0f} Hz", f, rows,
           ["figure", "value"], args.json)


if __name__ == "__main__":
    main()
