"""mediapipe on a 640x480 video: frames per second and frame-to-Frame latency, on this machine's cores.

The video is looped for `--frames` frames after ten of warm-up. Every frame goes through
MediaPipe pose (the user, both hands in mm, the recogniser) and, unless `--no-mask`, as a show
with a silhouette would ask, the selfie mask. Latency is from the frame read off the video
to the Frame returned (what a live camera adds on top is its own exposure and transfer). The CPU
time per frame (every thread of the process) estimates what an unloaded machine reaches: on a
shared one the wall-clock rate mostly measures the others.
Target: >= 20 fps. Needs the `webcam` extra; the video defaults to ISSV_DATA's colour take.

`python -m bench.webcam [--video FILE] [--no-mask] [--frames 300] [--json]`
"""
from __future__ import annotations

import os
import time
from pathlib import Path

from bench.common import parse_args, percentiles, report

TARGET_FPS = 20.0
WARMUP = 10


def run(video: Path, mask: bool, frames: int, warmup: int = WARMUP) -> dict:
    """`frames` frames of the video (looped) after `warmup` ones (MediaPipe's first frames load
    models and find the performer: reported apart, as a show's first second)."""
    from backends.webcam.backend import MediaPipeBackend
    from sources.webcam import WebcamOptions, WebcamSource
    source = WebcamSource(WebcamOptions(path=str(video), width=640, height=480, loop=True))
    backend = MediaPipeBackend(source, MediaPipeBackend.Options(user_mask=mask))
    latencies, first, hands = [], [], 0
    with backend:
        for i in range(warmup + frames):
            if i == warmup:
                start, cpu = time.perf_counter(), time.process_time()
            t0 = time.perf_counter()
            frame = backend.update()
            if mask:
                frame.user_mask  # noqa: B018  (made on demand, as a silhouette effect asks)
            (first if i < warmup else latencies).append((time.perf_counter() - t0) * 1000)
            hands += sum(h.in_view for h in frame.hands) if i >= warmup else 0
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    fps = frames / seconds
    return {"video": str(video), "frames": frames, "fps": fps, "latency_ms": percentiles(latencies, (50, 90, 99)),
            "warmup_ms": sum(first), "hands_per_frame": hands / frames, "mask": mask, "cores": os.cpu_count(),
            "cpu_ms_per_frame": cpu / frames * 1000, "load_avg_1m": round(os.getloadavg()[0], 2),
            "target_met": fps >= TARGET_FPS}


def main() -> None:
    default = Path(os.environ.get("ISSV_DATA", "../shared/data")) / "real-depth" / "kinect-desk-hand-rgb.mp4"
    args = parse_args(__doc__.splitlines()[0], lambda p: (
        p.add_argument("--video", type=Path, default=default, help="a 640x480 video (default: the real colour take)"),
        p.add_argument("--no-mask", action="store_true", help="skip the selfie mask"),
        p.add_argument("--frames", type=int, default=300, help="frames measured, the video looped (default 300)")))
    from backends.webcam.backend import availability
    reason = availability()
    if reason is not None:
        raise SystemExit(f"bench.webcam: {reason}")
    f = run(args.video, not args.no_mask, args.frames)
    rows = [["frame read -> Frame (ms)", f["latency_ms"]["p50"], f["latency_ms"]["p90"], f["latency_ms"]["p99"]],
            [f"{f['frames']} frames at 640x480, {f['fps']:.1f} fps (target >= {TARGET_FPS:.0f}: "
             f"{'met' if f['target_met'] else 'MISSED'}), mask {'on' if f['mask'] else 'off'}, "
             f"{f['hands_per_frame']:.2f} hands per frame, {f['cores']} cores, load average {f['load_avg_1m']}",
             "", "", ""],
            [f"first {WARMUP} frames (models loading, the performer found): {f['warmup_ms']:.0f} ms in all, "
             f"not counted", "", "", ""],
            [f"CPU time {f['cpu_ms_per_frame']:.1f} ms per frame, all threads: about "
             f"{1000 / max(f['cpu_ms_per_frame'], 1e-9):.0f} fps with the cores to itself (an estimate: "
             f"it assumes no waiting)", "", "", ""]]
    report("mediapipe (webcam)", f, rows, ["", "p50", "p90", "p99"], args.json)


if __name__ == "__main__":
    main()
