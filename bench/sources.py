"""Depth sources at 640x480 on one core: decode time per frame, the rate each sustains, and the
latency a source adds between its library's frame and issv's DepthFrame.

File sources are read as fast as possible (looping), so their read time is all they add. Camera
sources are timed from the moment their library hands a frame over (libfreenect's callback,
librealsense's frameset) to the DepthFrame. The `kinect` row runs in a child process under
libfreenect's fakenect library, which replays at the recorded pace: its rate is the dump's, not
a decode limit. The `.oni` row is the real OpenNI take in tests/data, read with `realtime = false`
(OpenNI2's manual mode: its player decodes the next frame on each read, none skipped).
Target: >= 90 frames per second for every file format.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from bench.common import parse_args, percentiles, report
from host import Intrinsics
from sources.clip import ClipOptions, ClipSource
from sources.depth_images import DepthImagesOptions, DepthImagesSource
from sources.fakenect import FakenectOptions, FakenectSource
from sources.oni import OniOptions, OniSource

ROOT = Path(__file__).resolve().parents[1]
SR305 = ROOT / "tests" / "data" / "realsense-sr305-hands" / "20210326-231615"  # real 640x480 depth (MIT)
SR305_INTRINSICS = Intrinsics(476.007, 476.007, 313.683, 242.755)
ONI = ROOT / "tests" / "data" / "openni-user" / "user_new.oni"  # real 640x480 OpenNI 1.x take (MIT-style)
FPS = 30


def real_frames() -> list[np.ndarray]:
    """The SR305's raw counts (0.125 mm) of the four frames shipped with the tests."""
    return [cv2.imread(str(p), cv2.IMREAD_UNCHANGED) for p in sorted(SR305.glob("*.png"))]


def write_cases(folder: Path, raw: list[np.ndarray]) -> dict[str, object]:
    """Every file format, holding the same real depth (in its own unit), as sources to read."""
    mm = [np.round(r * 0.125).astype(np.uint16) for r in raw]
    cases: dict[str, object] = {}
    for name, images, suffix, unit in (("png-0.125mm", raw, ".png", 0.125), ("png-1mm", mm, ".png", 1.0),
                                       ("tiff-1mm", mm, ".tif", 1.0)):
        sub = folder / name
        sub.mkdir()
        for i, image in enumerate(images):
            cv2.imwrite(str(sub / f"{i}{suffix}"), image)
        cases[f"depth-images {suffix[1:]} ({unit:g} mm)"] = DepthImagesSource(DepthImagesOptions(
            path=str(sub), depth_unit_mm=unit, intrinsics=SR305_INTRINSICS.as_list(), fps=FPS, loop=True))
    np.savez(folder / "clip.npz", depth=np.stack(mm), timestamps=np.arange(len(mm)) / FPS,
             intrinsics=np.array(SR305_INTRINSICS.as_list()))
    cases["clip .npz"] = ClipSource(ClipOptions(path=str(folder / "clip.npz"), loop=True))
    dump = write_fakenect_dump(folder / "dump", mm)
    cases["fakenect dump"] = FakenectSource(FakenectOptions(path=str(dump), loop=True))
    try:
        from sources.realsense import RealSenseOptions, RealSenseSource, write_bag
        write_bag(folder / "take.bag", raw, SR305_INTRINSICS, FPS, depth_units_m=0.000125)
        cases["realsense .bag (0.125 mm)"] = RealSenseSource(RealSenseOptions(
            path=str(folder / "take.bag"), realtime=False, loop=True))
    except ImportError:
        print("bench.sources: realsense skipped (pip install 'issv[realsense]')", file=sys.stderr)
    if OniSource.availability() is None:
        cases[".oni (OpenNI2, 16zT, as fast as possible)"] = OniSource(OniOptions(path=str(ONI), loop=True,
                                                                                  realtime=False))
    else:
        print(f"bench.sources: .oni skipped ({OniSource.availability()})", file=sys.stderr)
    return cases


def write_fakenect_dump(folder: Path, mm: list[np.ndarray]) -> Path:
    """A fakenect-record dump of the same scene: mm back to Kinect v1 11-bit disparities."""
    folder.mkdir()
    names = []
    for i, depth in enumerate(mm):
        z = np.maximum(depth.astype(np.float64), 1)
        raw = np.where(depth > 0, np.round((np.arctan(z / 123.6) - 1.1863) * 2842.5), 2047)
        name = f"d-{1000 + i / FPS:f}-{i * 2002155}.pgm"
        (folder / name).write_bytes(b"P5 640 480 65535\n" + np.clip(raw, 0, 2047).astype("<u2").tobytes())
        names.append(name)
    (folder / "INDEX.txt").write_text("\n".join(names) + "\n")
    return folder


def measure(source, frames: int) -> dict:
    source.open()
    try:
        source.read()  # the first frame opens files and fills caches
        read_ms, handover_ms = [], []
        start = time.perf_counter()
        for _ in range(frames):
            t0 = time.perf_counter()
            frame = source.read()
            read_ms.append((time.perf_counter() - t0) * 1000)
            if hasattr(source, "handover_s"):
                handover_ms.append(source.handover_s * 1000)
            if frame is None:
                break
        total = time.perf_counter() - start
    finally:
        source.close()
    live = bool(handover_ms)
    return {"frames": len(read_ms), "size": f"{frame.width}x{frame.height}", "read_ms": percentiles(read_ms),
            "fps": len(read_ms) / total,
            "latency_ms": percentiles(handover_ms if live else read_ms),
            "latency_from": "library frame -> DepthFrame" if live else "read() (decode)"}


def kinect_child(frames: int) -> None:
    """Runs under `fakenect`: the kinect source's handover latency and the rate fakenect replays at."""
    from sources.kinect import KinectOptions, KinectSource
    print(json.dumps(measure(KinectSource(KinectOptions()), frames)))


def kinect_row(folder: Path, frames: int) -> dict | None:
    from sources.kinect import KinectSource
    if shutil.which("fakenect") is None or KinectSource.availability() is not None:
        print("bench.sources: kinect skipped (needs Debian libfreenect-bin and 'issv[kinect]')", file=sys.stderr)
        return None
    dump = folder / "dump"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cpu = str(min(os.sched_getaffinity(0)))
    done = subprocess.run(["taskset", "-c", cpu, "fakenect", str(dump), sys.executable, "-m", "bench.sources",
                           "--kinect-child", "--frames", str(min(frames, len(list(dump.glob("d-*"))) - 2))],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
    if done.returncode != 0:
        print(f"bench.sources: kinect failed: {done.stderr[-500:]}", file=sys.stderr)
        return None
    return json.loads(done.stdout.splitlines()[-1])


def main() -> None:
    def extra(p):
        p.add_argument("--frames", type=int, default=300, help="frames per source")
        p.add_argument("--kinect-child", action="store_true", help="internal: measure the kinect source under fakenect")
    args = parse_args(__doc__, extra)
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core, before any library starts threads
    cv2.setNumThreads(1)
    if args.kinect_child:
        kinect_child(args.frames)
        return
    folder = Path(tempfile.mkdtemp(prefix="issv-bench-sources-"))
    raw = real_frames()
    figures, rows = {}, []
    cases = write_cases(folder, raw)
    for name, source in cases.items():
        figures[name] = measure(source, args.frames)
    # a dump long enough to time (the 4 real frames, repeated: fakenect cannot loop)
    shutil.rmtree(folder / "dump")
    write_fakenect_dump(folder / "dump", [np.round(r * 0.125).astype(np.uint16) for r in raw] * 20)
    kinect = kinect_row(folder, args.frames)
    if kinect is not None:
        figures["kinect (libfreenect fakenect, paced)"] = kinect
    for name, m in figures.items():
        rows.append([name, m["size"], m["read_ms"]["p50"], m["read_ms"]["p99"], m["fps"],
                     m["latency_ms"]["p50"], m["latency_ms"]["p99"], m["latency_from"]])
    shutil.rmtree(folder, ignore_errors=True)
    report("issv depth sources (one core)", figures, rows,
           ["source", "size", "read p50 (ms)", "read p99 (ms)", "sustained fps", "latency p50 (ms)",
            "latency p99 (ms)", "latency measured"], args.json)


if __name__ == "__main__":
    main()
