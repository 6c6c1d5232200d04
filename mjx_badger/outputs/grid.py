"""Fig 4.2 drawn as the thesis drew it: a grid of learning rate x batch size (a), and the training curves of the
cells marked in it (b), from the results files of a sweep (learning/sweep.py) per batch size."""

import json
from pathlib import Path

import numpy as np

from mjx_badger.outputs.style import plt, save
from mjx_badger.records import analysis, results

LEARNING_RATES = (1e-4, 5e-4, 1e-3, 5e-3, 1e-2, 5e-2)
BATCH_SIZES = (32, 64, 128, 256)
"""Fig 4.2's grid (its caption)."""


def load_cells(folder: Path) -> dict:
    """(learning rate, batch size) -> results document, from every sweep member's file under `folder`."""
    cells = {}
    for path in sorted(Path(folder).rglob("*.json")):
        document = json.loads(path.read_text())
        if document.get("schema") != results.SCHEMA or not document.get("complete"):
            continue
        agent = document["config"]["agent"]
        cells[(float(agent["learning_rate"]), int(agent["batch_size"]))] = document
    return cells


def cell_numbers(document: dict) -> dict:
    """A cell's final evaluation velocity and falls, seeds' means, and its training curve."""
    return {"velocity": float(np.nanmean(analysis.final(document, "eval/desired_velocity"))),
            "falls": float(np.mean(analysis.series(document, "train/falls")[-1])),
            "steps": np.asarray(document["steps"]),
            "curve": np.nanmean(analysis.series(document, "train/forward_velocity"), axis=1)}


def marked(numbers: dict, default: tuple) -> dict:
    """The cells drawn in (b): the best, the worst and the protocol's own setting where the grid has it."""
    ranked = sorted(numbers, key=lambda cell: numbers[cell]["velocity"])
    picks = {"best": ranked[-1], "worst": ranked[0]}
    if default in numbers:
        picks["the protocol's"] = default
    return picks


def table(numbers: dict) -> str:
    """Markdown: final evaluation velocity (m/s) and falls per cell, batch sizes as rows."""
    lines = ["| batch \\ learning rate | " + " | ".join(f"{lr:g}" for lr in LEARNING_RATES) + " |",
             "|---" * (len(LEARNING_RATES) + 1) + "|"]
    for batch in BATCH_SIZES:
        cells = [f"{numbers[(lr, batch)]['velocity']:.2f} m/s, {numbers[(lr, batch)]['falls']:.0f} falls"
                 if (lr, batch) in numbers else "not run" for lr in LEARNING_RATES]
        lines.append(f"| {batch} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def figure(numbers: dict, default: tuple, out: Path, label: str) -> Path:
    """(a) the grid coloured by final evaluation velocity, each cell with its falls; (b) the marked cells' curves."""
    fig, (grid_ax, curve_ax) = plt.subplots(1, 2, figsize=(14, 4.6), constrained_layout=True,
                                            gridspec_kw={"width_ratios": [1.2, 1]})
    values = np.array([[numbers[(lr, b)]["velocity"] if (lr, b) in numbers else np.nan for lr in LEARNING_RATES]
                       for b in BATCH_SIZES])
    image = grid_ax.imshow(values, cmap="viridis", origin="lower", aspect="auto")
    for row, batch in enumerate(BATCH_SIZES):
        for column, lr in enumerate(LEARNING_RATES):
            if (lr, batch) in numbers:
                n = numbers[(lr, batch)]
                grid_ax.text(column, row, f"{n['velocity']:.2f}\n{n['falls']:.0f} falls", ha="center", va="center",
                             fontsize=7, color="w" if n["velocity"] < np.nanmax(values) * 0.6 else "k")
    picks = marked(numbers, default)
    for name, (lr, batch) in picks.items():
        grid_ax.add_patch(plt.Rectangle((LEARNING_RATES.index(lr) - 0.5, BATCH_SIZES.index(batch) - 0.5), 1, 1,
                                        fill=False, lw=2, ec="tab:red" if name == "worst" else "w"))
        n = numbers[(lr, batch)]
        curve_ax.plot(n["steps"], n["curve"], label=f"{name}: lr {lr:g}, batch {batch}")
    grid_ax.set_xticks(range(len(LEARNING_RATES)), [f"{lr:g}" for lr in LEARNING_RATES])
    grid_ax.set_yticks(range(len(BATCH_SIZES)), BATCH_SIZES)
    grid_ax.set_xlabel("learning rate")
    grid_ax.set_ylabel("batch size")
    grid_ax.set_title("(a) final evaluation velocity [m/s] and falls, seeds' mean; marked cells in (b)", fontsize=9)
    fig.colorbar(image, ax=grid_ax, label="m/s")
    curve_ax.set_title("(b) training forward velocity of the marked cells, seeds' mean", fontsize=9)
    curve_ax.set_xlabel("steps")
    curve_ax.set_ylabel("m/s")
    curve_ax.grid(alpha=0.3)
    curve_ax.legend(fontsize=8)
    fig.suptitle(f"Fig 4.2's grid search: {label}", fontsize=10)
    return save(fig, out)
