"""Recording cost: milliseconds per frame to write and to read back, bytes per frame and the
lossless compression ratio, for Kinect-like synthetic depth (640x480, noisy) and a real UTD-MHAD
clip (320x240, background removed). Recording runs on the sensor thread, so write time adds to
every frame's latency: it should stay a small part of a 33 ms (30 Hz) frame. The user label image
(`/user_labels`, written when the backend knows it: here the synthetic scenes' own) is measured
apart too: its KiB per frame and the milliseconds its encoding adds to each write.
"""
from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

from mcap.reader import make_reader

from backends.truth import TruthBackend
from bench.common import data_set, parse_args, percentiles, report
from host.recording import Recording, RecordingWriter, codec
from sources.clip import ClipOptions, ClipSource
from sources.synthetic import SyntheticOptions, SyntheticSource

CLIP = "clips/a1_s1_t1_swipe_left.npz"  # in the UTD-MHAD dev set


def measure(name: str, source, frames: int) -> dict:
    tracked = []
    with TruthBackend(source) as backend:
        while len(tracked) < frames and (frame := backend.update()) is not None:
            tracked.append(frame)
    path = Path(tempfile.mkdtemp()) / f"{name}.mcap"
    write_ms = []
    with RecordingWriter(path) as writer:
        for frame in tracked:
            t0 = time.perf_counter()
            writer.write_frame(frame)
            write_ms.append((time.perf_counter() - t0) * 1000)
    t0 = time.perf_counter()
    with Recording(path) as rec:
        read = sum(1 for _ in rec.frames())
    read_ms = (time.perf_counter() - t0) * 1000 / max(read, 1)
    raw = sum(f.depth.data.nbytes for f in tracked)
    size = path.stat().st_size
    labelled = [f for f in tracked if f.user_labels is not None]
    labels_ms = []
    for f in labelled:
        t0 = time.perf_counter()
        codec.encode_labels(f.depth, f.user_labels)
        labels_ms.append((time.perf_counter() - t0) * 1000)
    with open(path, "rb") as f:
        labels_bytes = sum(len(m.data) for _, _, m in make_reader(f).iter_messages(topics=[codec.LABELS]))
    return {"frames": len(tracked), "size": f"{tracked[0].depth.width}x{tracked[0].depth.height}",
            "write_ms": percentiles(write_ms), "read_ms_per_frame": read_ms,
            "kib_per_frame": size / len(tracked) / 1024, "compression_ratio": raw / size,
            "labels_kib_per_frame": labels_bytes / max(len(labelled), 1) / 1024,
            "labels_write_ms": percentiles(labels_ms)}


def main() -> None:
    def extra(p):
        p.add_argument("--frames", type=int, default=150, help="frames per case")
    args = parse_args(__doc__, extra, data=True)
    cases = {"synthetic 640x480": SyntheticSource(SyntheticOptions(seed=1)),
             "synthetic duet 640x480": SyntheticSource(SyntheticOptions(seed=1, scene="duet"))}
    utd = data_set(args, "utd-mhad-dev", "the real UTD-MHAD clip row")
    if utd is not None:
        cases["UTD-MHAD clip 320x240"] = ClipSource(ClipOptions(path=str(utd / CLIP), loop=True))
    figures, rows = {}, []
    for name, source in cases.items():
        m = figures[name] = measure(name, source, args.frames)
        rows.append([name, m["write_ms"]["p50"], m["write_ms"]["p99"], m["read_ms_per_frame"],
                     m["kib_per_frame"], m["compression_ratio"], m["labels_kib_per_frame"],
                     m["labels_write_ms"]["p50"]])
    figures["load_average"] = os.getloadavg()[0]
    report(f"issv recording bench (load {figures['load_average']:.1f})", figures, rows,
           ["depth", "write p50 (ms/frame)", "write p99", "read (ms/frame)", "KiB/frame", "compression x",
            "labels KiB/frame", "labels write p50 (ms)"], args.json)


if __name__ == "__main__":
    main()
