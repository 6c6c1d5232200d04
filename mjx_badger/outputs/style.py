"""How the suite's figures look: matplotlib without a display, learning-curve panels (seed mean with a min/max
band), and saving a figure atomically."""

import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # before pyplot: figures are files, never windows
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mjx_badger.core import safe_io  # noqa: E402
from mjx_badger.records import results  # noqa: E402
from mjx_badger.records.analysis import display_color, display_name, series  # noqa: E402


def mean_and_band(ax, x, values, color, label, style=None, band=True):
    """Mean line with a min/max band over seeds (or the mean line alone)."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN chunks (no episode ended) stay gaps
        ax.plot(x, np.nanmean(values, axis=1), **{"color": color, "label": label, "lw": 1.8, **(style or {})})
        if band:
            ax.fill_between(x, np.nanmin(values, axis=1), np.nanmax(values, axis=1), color=color, alpha=0.15, lw=0)


def x_values(document: dict, x_axis: str):
    return np.array(document["steps"]) / 1000 if x_axis == "steps" else np.array(document["sim_minutes"])


def x_label(x_axis: str) -> str:
    return "environment steps [k]" if x_axis == "steps" else "simulated minutes (steps / control Hz)"


def seeds_note(documents: dict) -> str:
    """'3 seeds, mean and min/max band', naming any seed left out for diverging (results.healthy)."""
    seeds = sorted({len(d["seeds"]) for d in documents.values()})
    gone = [f"{display_name(label)} {words}" for label, d in documents.items() if (words := results.left_out_words(d))]
    return f"{'/'.join(map(str, seeds))} seeds, mean and min/max band" + "".join(f"; {g}" for g in gone)


def curve_panel(ax, documents: dict, metric: str, title: str, ylabel: str, x_axis: str = "steps",
                target: float | None = None, style=None, band=True):
    """One panel of learning curves: `metric` of every run that has it."""
    for label, document in documents.items():
        if metric in document["metrics"]:
            mean_and_band(ax, x_values(document, x_axis), series(document, metric), display_color(label),
                          display_name(label), style, band)
    if target is not None:
        ax.axhline(target, color="k", ls="--", lw=1, label=f"target {target} m/s")
    ax.set_title(title, fontsize=10)
    ax.set_ylabel(ylabel)
    ax.set_xlabel(x_label(x_axis))
    ax.grid(alpha=0.3)


def save(fig, out: Path) -> Path:
    try:
        safe_io.save_figure(fig, out, dpi=110)
    finally:
        plt.close(fig)
    return out
