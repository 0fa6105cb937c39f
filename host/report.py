"""The comparison report: Markdown a crew can read, PNG plots next to it (matplotlib, Agg).

Everything here is computed from the Runs of host/compare.py; nothing is re-measured.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from host.compare import AGREEMENT_WINDOW_S, OUTPUT_FPS, Run, agreement  # noqa: E402
from host.model import CANONICAL_GESTURES  # noqa: E402

NFR1_MIN_FPS, NFR1_PREFERRED_FPS = 10.0, 15.0  # thesis NFR1
COLOURS = dict(zip(CANONICAL_GESTURES, plt.get_cmap("tab10").colors))


@dataclass
class RecordingInfo:
    path: Path
    frames: int
    duration_s: float
    size: tuple[int, int]
    meta: dict[str, str]
    complete: bool


def _ok(runs: list[Run]) -> list[Run]:
    return [r for r in runs if r.error is None]


def plot_gestures(runs: list[Run], info: RecordingInfo, path: Path) -> None:
    """One row per backend: where hands were tracked (grey band) and each completed gesture."""
    fig, ax = plt.subplots(figsize=(10, 1.0 + 0.6 * len(runs)))
    t0 = min((r.frame_times[0] for r in runs if r.frame_times), default=0.0)
    for row, run in enumerate(runs):
        y = len(runs) - 1 - row
        times = np.array(run.frame_times) - t0
        tracked = np.array(run.hands_per_frame) > 0
        if times.size:
            ax.fill_between(times, y - 0.3, y + 0.3, where=tracked, color="0.88", step="mid", linewidth=0)
        for g in run.completed:
            ax.scatter(g.timestamp - t0, y, marker="|", s=300, linewidths=3, color=COLOURS[g.name])
    ax.set_yticks(range(len(runs)), [r.backend for r in reversed(runs)])
    ax.set_xlabel("recording time (s)")
    ax.set_xlim(0, max(info.duration_s, 1e-3))
    handles = [plt.Line2D([], [], color=c, marker="|", linestyle="", markersize=12, markeredgewidth=3, label=n)
               for n, c in COLOURS.items()]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, title="gesture")
    ax.set_title("Completed gestures over time (grey: a hand is tracked)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_fps(runs: list[Run], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(max(5, 1.6 * len(runs) + 2), 4))
    x = np.arange(len(runs))
    for i, (key, label) in enumerate((("sfps", "sFPS"), ("rfps", "rFPS"), ("effective_fps", "effective"))):
        ax.bar(x + (i - 1) * 0.27, [r.metrics[key] for r in runs], 0.27, label=label)
    ax.axhline(NFR1_MIN_FPS, color="red", linestyle="--", linewidth=1, label="NFR1 minimum (10)")
    ax.axhline(NFR1_PREFERRED_FPS, color="orange", linestyle=":", linewidth=1, label="NFR1 preferred (15)")
    ax.set_xticks(x, [r.backend for r in runs])
    ax.set_ylabel("frames per second")
    ax.set_title("Frame rates, unpaced (effective = (sFPS + rFPS) / 2)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_latency(runs: list[Run], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(max(5, 1.4 * len(runs) + 2), 4))
    data = [r.latencies_ms if r.latencies_ms.size else np.zeros(1) for r in runs]
    ax.boxplot(data, whis=(1, 99), showfliers=False)
    ax.set_xticks(range(1, len(runs) + 1), [r.backend for r in runs])
    ax.set_ylabel("capture -> effect latency (ms)")
    ax.set_title("Latency distribution (box: quartiles, whiskers: p1-p99)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _heatmap(matrix: np.ndarray, rows: list[str], cols: list[str], title: str, path: Path, fmt: str) -> None:
    fig, ax = plt.subplots(figsize=(1.1 * len(cols) + 2.5, 0.55 * len(rows) + 1.8))
    cmap = plt.get_cmap("viridis").with_extremes(bad="0.9")  # cells with no value: light grey, marked "-"
    ax.imshow(np.ma.masked_invalid(matrix), cmap=cmap, aspect="auto")
    high = np.nanmax(matrix) if np.isfinite(matrix).any() else 0.0
    for (i, j), v in np.ndenumerate(matrix):
        dark = not np.isnan(v) and v < 0.6 * high  # white text on the dark end of viridis, black elsewhere
        ax.text(j, i, _cell(v, fmt), ha="center", va="center",
                color="w" if dark else "k", fontsize=8)
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right")
    ax.set_yticks(range(len(rows)), rows)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def coverage_matrix(runs: list[Run]) -> np.ndarray:
    """Completed gestures per backend and canonical name; NaN where the backend's dictionary lacks it."""
    m = np.array([[counts[n] for n in CANONICAL_GESTURES] for counts in map(Run.counts, runs)], dtype=float)
    for i, r in enumerate(runs):
        if r.dictionary is not None:
            for j, n in enumerate(CANONICAL_GESTURES):
                if n not in r.dictionary:
                    m[i, j] = np.nan
    return m


def agreement_matrix(runs: list[Run]) -> np.ndarray:
    m = np.full((len(runs), len(runs)), np.nan)
    for i, a in enumerate(runs):
        for j, b in enumerate(runs):
            score = agreement(a.gestures, b.gestures)[1]
            m[i, j] = np.nan if score is None else score
    return m


def _cell(v: float, fmt: str) -> str:
    return "-" if np.isnan(v) else format(v, fmt)


def _table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return "\n".join(lines + ["| " + " | ".join(row) + " |" for row in rows])


REFERENCES = ("truth", "replay")  # what was performed / what was tracked live: yardsticks, not contenders


def _best(runs: list[Run], key) -> tuple[list[str], float]:
    top = max(key(r) for r in runs)
    return [f"**{r.backend}**" for r in runs if key(r) == top], top


def findings(runs: list[Run]) -> list[str]:
    """What a crew reads first: speed against NFR1, breadth of dictionary, agreement with truth."""
    contenders = [r for r in runs if r.backend not in REFERENCES] or runs
    out = []
    names, fps = _best(contenders, lambda r: round(r.metrics["effective_fps"], 1))
    out.append(f"Fastest: {', '.join(names)} at {fps:.1f} effective FPS.")
    slow = [r.backend for r in contenders if r.metrics["sfps"] < NFR1_MIN_FPS]
    out.append(f"Below the thesis' 10 FPS minimum (NFR1) in tracking rate: {', '.join(slow)}." if slow
               else "Every backend tracks faster than the thesis' 10 FPS minimum (NFR1).")
    names, kinds = _best(contenders, lambda r: sum(v > 0 for v in r.counts().values()))
    out.append(f"Broadest dictionary on this recording: {', '.join(names)} "
               f"({kinds} of {len(CANONICAL_GESTURES)} canonical gestures seen).")
    names, share = _best(contenders, lambda r: round(100 * r.hands_fraction))
    out.append(f"Tracks hands most of the time: {', '.join(names)} ({share:.0f} % of frames).")
    truth = next((r for r in runs if r.backend == "truth"), None)
    scored = [r for r in contenders if r is not truth and truth is not None]
    if scored and any(agreement(r.gestures, truth.gestures)[1] is not None for r in scored):
        names, score = _best(scored, lambda r: round(agreement(r.gestures, truth.gestures)[1] or 0.0, 2))
        out.append(f"Closest to the recording's ground truth: {', '.join(names)} (agreement {score:.2f}).")
    return out


def write(out_dir: Path, info: RecordingInfo, runs: list[Run]) -> Path:
    """DIR/report.md, its PNGs, and DIR/gestures.jsonl (every gesture event, per backend)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    ok = _ok(runs)
    md = [f"# Backend comparison: `{info.path.name}`", ""]
    md.append(f"Recording `{info.path}`: {info.frames} depth frames, {info.duration_s:.1f} s, "
              f"{info.size[0]}x{info.size[1]}; recorded from source `{info.meta.get('source', '?')}` with backend "
              f"`{info.meta.get('backend', '?')}`" + ("" if info.complete else " (the file was cut short: read up to the cut)") + ".")
    md.append(f"Backends compared: {', '.join(f'`{r.backend}`' for r in runs)}. Each read the identical recorded depth "
              f"images, as fast as it could, one after the other, through the show's frame loop "
              f"(output capped at {OUTPUT_FPS:.0f} Hz, no rendering, so rFPS is the delivery rate).")
    failed = [r for r in runs if r.error is not None]
    for r in failed:
        md.append(f"\n**`{r.backend}` failed**: {r.error}")
    if ok:
        md += ["", "## Findings", ""] + [f"- {line}" for line in findings(ok)]
        md += ["", "## Summary", ""]
        rows = []
        for r in ok:
            m, lat = r.metrics, r.metrics["latency_ms"]
            rows.append([f"`{r.backend}`", str(m["frames"]), f"{m['sfps']:.1f}", f"{m['rfps']:.1f}",
                         f"{m['effective_fps']:.1f}", f"{lat['p50']:.1f} / {lat['p95']:.1f} / {lat['p99']:.1f}",
                         f"{100 * r.hands_fraction:.0f} %", str(len(r.completed)), f"{r.wall_s:.1f}"])
        md.append(_table(["backend", "frames", "sFPS", "rFPS", "effective FPS", "latency p50 / p95 / p99 (ms)",
                          "frames with a hand", "gestures completed", "wall time (s)"], rows))
        plot_gestures(ok, info, out_dir / "gestures.png")
        plot_fps(ok, out_dir / "fps.png")
        plot_latency(ok, out_dir / "latency.png")
        md += ["", "## Gestures over time", "", "![gestures over time](gestures.png)",
               "", "## Frame rates", "", "![frame rates](fps.png)",
               "", "## Latency", "", "![latency](latency.png)"]
        cov = coverage_matrix(ok)
        _heatmap(cov, [r.backend for r in ok], list(CANONICAL_GESTURES), "Completed gestures (-: not in its dictionary)",
                 out_dir / "coverage.png", ".0f")
        md += ["", "## Dictionary coverage", "",
               "Completed gestures by canonical name (`-`: the backend's dictionary does not have it).", "",
               _table(["backend", *CANONICAL_GESTURES], [[f"`{r.backend}`", *(_cell(v, ".0f") for v in row)]
                                                        for r, row in zip(ok, cov)]),
               "", "![dictionary coverage](coverage.png)"]
        if len(ok) > 1:
            agree = agreement_matrix(ok)
            _heatmap(agree, [r.backend for r in ok], [r.backend for r in ok], "Agreement (Dice)",
                     out_dir / "agreement.png", ".2f")
            md += ["", "## Agreement between backends", "",
                   f"Two backends agree on a gesture when both complete one with the same canonical name and the "
                   f"gestures' spans (from `in_progress` to `complete`) overlap or come within {AGREEMENT_WINDOW_S} s; "
                   f"the score is 2 x matches / (gestures of one + gestures of the other), 1 = the same gestures, "
                   f"`-` = neither completed any.", "",
                   _table(["", *(f"`{r.backend}`" for r in ok)], [[f"`{r.backend}`", *(_cell(v, ".2f") for v in row)]
                                                                  for r, row in zip(ok, agree)]),
                   "", "![agreement](agreement.png)"]
    md += ["", "Every gesture event of every backend is in `gestures.jsonl` "
           "(event lines of docs/architecture.md plus `backend`).", ""]
    with open(out_dir / "gestures.jsonl", "w") as f:
        for r in ok:
            for g in r.gestures:
                f.write(json.dumps({"backend": r.backend, **g.to_json()}) + "\n")
    report = out_dir / "report.md"
    report.write_text("\n".join(md))
    return report
