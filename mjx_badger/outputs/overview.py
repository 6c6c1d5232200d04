"""Every thesis simulation experiment at a glance: the headline curve of each and the falls per approach, at one
budget (the overview figure) or at several side by side (`claims --budgets ... --plot`)."""

from pathlib import Path

import numpy as np

from mjx_badger.control.actions import APPROACHES
from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.outputs.style import curve_panel, plt, save, seeds_note
from mjx_badger.records.analysis import display_name, summarize

HEADLINE = {
    "algo-comparison": ("train/forward_velocity", "algorithms (Fig 5.2): forward velocity", "minutes",
                        EXPERIMENTS["algo-comparison"].target_velocity),
    "forward": ("train/forward_velocity", f"forward {EXPERIMENTS['forward'].target_velocity} m/s (Fig 5.3): velocity",
                "steps", EXPERIMENTS["forward"].target_velocity),
    "forward-max": ("train/forward_velocity", "maximal velocity (Fig 5.6): velocity", "steps", None),
    "omni-random": ("eval/desired_mae", "omni, random (Fig 5.9): desired MAE", "steps", None),
    "omni-pdec": ("eval/desired_mae", "omni, PDEC (Fig 5.12): desired MAE", "steps", None),
}
"""Experiment -> (metric, title, x axis, target) of its one curve in the overview figures."""


def _no_results_panel(ax, name: str, title: str, command: str) -> None:
    """An empty panel that says which command would fill it."""
    ax.text(0.5, 0.5, f"no {name} results yet:\n{command}", ha="center", va="center", fontsize=9, color="0.4",
            transform=ax.transAxes)
    ax.set_title(title, fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])


def overview_figure(loaded: dict, out: Path, profile: str) -> Path:
    """Everything at a glance: the headline curve of every experiment with results, and falls per approach."""
    fig, axes = plt.subplots(2, 3, figsize=(16, 9), constrained_layout=True)
    axes = axes.ravel()
    for ax, (name, (metric, title, x_axis, target)) in zip(axes, HEADLINE.items()):
        if not loaded.get(name):
            _no_results_panel(ax, name, title, f"python -m mjx_badger reproduce\n--profile {profile.split()[0]} "
                              f"--experiments {name}")
            continue
        curve_panel(ax, loaded[name], metric, title, "[m/s]", x_axis, target)
        ax.legend(fontsize=7)
    falls_panel(axes[5], [(name, loaded.get(name), f"C{i}", None) for i, name in enumerate(FALLS_EXPERIMENTS)])
    every = {f"{name} {label}": d for name, documents in loaded.items() if documents for label, d in documents.items()}
    fig.suptitle(f"mjx_badger: every thesis simulation experiment at a glance ({profile}; {seeds_note(every)})",
                 fontsize=12)
    return save(fig, out)


FALLS_EXPERIMENTS = ("forward", "forward-max", "omni-random", "omni-pdec")
"""The experiments whose falls the overview figures draw, each in its own colour (C0, C1, ...)."""


def falls_panel(ax, bars: list) -> None:
    """Bars of falls during training, mean over seeds, per approach: one bar per (label, runs, colour, hatch) with runs."""
    bars = [bar for bar in bars if bar[1]]
    width = 0.8 / max(len(bars), 1)
    approaches = [a for a in APPROACHES if any(a in documents for _, documents, _, _ in bars)]
    for i, (label, documents, color, hatch) in enumerate(bars):
        means = [summarize(documents[a], None)["falls_mean"] if a in documents else np.nan for a in approaches]
        ax.bar(np.arange(len(approaches)) + i * width, means, width, color=color, hatch=hatch,
               edgecolor="white" if hatch else None, label=label)
    ax.set_xticks(np.arange(len(approaches)) + width * (len(bars) - 1) / 2, [display_name(a) for a in approaches],
                  fontsize=8)
    ax.set_title("falls during training, mean over seeds", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")


def budgets_figure(loaded: dict, out: Path, protocol: str) -> Path:
    """The overview at several budgets: each experiment's headline curve per profile (the last solid with its
    min/max band, the others dashed), and falls per approach at each budget. `loaded`: profile -> experiment -> runs."""
    budgets = list(loaded)
    *earlier, last = budgets
    fig, axes = plt.subplots(2, 3, figsize=(16, 9), constrained_layout=True)
    axes = axes.ravel()
    for ax, (name, (metric, title, x_axis, target)) in zip(axes, HEADLINE.items()):
        if not any(loaded[budget].get(name) for budget in budgets):
            _no_results_panel(ax, name, title, f"at {' or '.join(budgets)}")
            continue
        missing = not loaded[last].get(name)  # then the dashed lines carry the legend, and the panel says so
        for budget in earlier:
            curve_panel(ax, loaded[budget].get(name, {}), metric, title, "[m/s]", x_axis,
                        style={"ls": "--", "lw": 1.1, **({} if missing else {"label": None})}, band=False)
        curve_panel(ax, loaded[last].get(name, {}), metric, title, "[m/s]", x_axis, target)
        if missing:
            ax.text(0.98, 0.02, f"no {name} results at {last} yet", ha="right", va="bottom", fontsize=8, color="0.4",
                    transform=ax.transAxes)
        ax.legend(fontsize=7)
    falls_panel(axes[5], [(f"{name} {budget}", loaded[budget].get(name), f"C{i}", None if budget == last else "//")
                          for i, name in enumerate(FALLS_EXPERIMENTS[:2]) for budget in budgets])
    seeds = {budget: sorted({len(d["seeds"]) for docs in loaded[budget].values() if docs for d in docs.values()})
             for budget in budgets}
    notes = "; ".join(f"{budget}: {'/'.join(map(str, n))} seeds" for budget, n in seeds.items() if n)
    fig.suptitle(f"Every thesis simulation experiment at {' and '.join(budgets)} ({protocol} protocol): solid {last} "
                 f"(mean, min/max band), dashed {', '.join(earlier)} (mean)\n{notes}", fontsize=11)
    return save(fig, out)
