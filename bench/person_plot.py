"""A picture of bench.people's figures: for each dataset, every person's recall of every gesture as a
grid (red 0, green 1), so the worst performer and the gesture that fails them stand out at a glance."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TITLES = {"utd": "UTD-MHAD", "msrc": "MSRC-12", "kinder": "Kinder-Gator"}
SECTIONS = {"default": "default rules", "leave_one_person_out": "rules chosen without the person"}


def _grid(fig: dict) -> tuple[list[str], list[str], np.ndarray]:
    """(gestures, persons, recall per gesture and person; NaN where the person did not perform it)."""
    rows = fig["by_person"]
    persons = sorted({p for row in rows.values() for p in row})
    cells = np.array([[np.nan if row.get(p) is None else row[p] for p in persons] for row in rows.values()], float)
    return list(rows), persons, cells.reshape(len(rows), len(persons))


def _label(recall: float) -> str:
    """0, 1 or two decimals without the leading zero (.86): short enough for a cell."""
    return "0" if recall == 0 else "1" if recall == 1 else f"{recall:.2f}"[1:]


def _false_fires(fig: dict) -> str:
    rate = fig["false_fire_rate"]
    if isinstance(rate, dict):
        return ", ".join(f"{k} {v:.2f}" for k, v in rate.items() if v is not None)
    return "-" if rate is None else f"{rate:.2f}"


def plot_people(out: dict, path: Path) -> None:
    """One row per section of `bench.people.measure`'s output (default rules, and leave-one-person-out
    when measured), one panel per dataset."""
    sections = [s for s in SECTIONS if s in out]
    datasets = list(out["default"])
    figure, axes = plt.subplots(len(sections), len(datasets), squeeze=False,
                                figsize=(5.2 * len(datasets), 4.2 * len(sections)))
    for row, section in enumerate(sections):
        for col, ds in enumerate(datasets):
            ax, fig = axes[row][col], out[section][ds]
            gestures, persons, cells = _grid(fig)
            ax.imshow(np.ma.masked_invalid(cells), cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
            for (i, j), value in np.ndenumerate(cells):
                if not np.isnan(value):
                    ax.text(j, i, _label(value), ha="center", va="center", fontsize=7)
            ax.set_xticks(range(len(persons)), persons, rotation=90, fontsize=7)
            ax.set_yticks(range(len(gestures)), gestures, fontsize=7)
            worst = fig.get("worst_person_overall")
            ax.set_title(f"{TITLES.get(ds, ds)}: {SECTIONS[section]}\nfalse fires {_false_fires(fig)}"
                         + ("" if worst is None else f", worst person {worst:.2f}"), fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
