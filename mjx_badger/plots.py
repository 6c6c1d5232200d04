"""Figures and tables drawn from results files only (nothing here trains)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mjx_badger import results  # noqa: E402
from mjx_badger.experiments import EXPERIMENTS, Experiment, result_name  # noqa: E402

COLORS = {"jt-nf": "tab:red", "jt-lpf": "tab:blue", "jt-oef": "tab:green",
          "cpg-d": "tab:purple", "cpg-vf": "tab:orange", "cpg-rt": "tab:brown",
          "sac": "tab:gray", "sac-utd20": "tab:olive", "droq": "tab:cyan", "crossq": "tab:red"}
NAMES = {"jt-nf": "JT-NF", "jt-lpf": "JT-LPF", "jt-oef": "JT-OEF", "cpg-d": "CPG-D", "cpg-vf": "CPG-VF",
         "cpg-rt": "CPG-RT", "sac": "SAC", "sac-utd20": "SAC-UTD20", "droq": "DroQ", "crossq": "CrossQ"}
REACHED_FRACTION = 0.9
"""A run has reached the target once the seed-mean training velocity is >= 90 % of it."""


def series(document: dict, name: str) -> np.ndarray:
    """Metric `name` as an array (chunks, seeds), NaN where undefined."""
    return np.array(document["metrics"][name], dtype=float)


def first_reached(document: dict, target: float) -> int | None:
    """Index of the first chunk whose seed-mean training velocity reaches 90 % of `target`."""
    mean = np.nanmean(series(document, "train/forward_velocity"), axis=1)
    hits = np.flatnonzero(mean >= REACHED_FRACTION * target)
    return int(hits[0]) if hits.size else None


def summarize(document: dict, target: float) -> dict:
    """Headline numbers of one run: time to target, final velocities, falls (mean and range)."""
    velocity = series(document, "train/forward_velocity")
    falls_curve = series(document, "train/falls")
    falls = falls_curve[-1]
    warmup = document["config"]["warmup_steps"]
    warmup_chunks = [i for i, step in enumerate(document["steps"]) if step <= warmup]
    falls_in_warmup = falls_curve[warmup_chunks[-1]] if warmup_chunks else np.zeros_like(falls)
    last = max(1, len(document["steps"]) // 10)
    reached = first_reached(document, target)
    return {
        "steps": document["steps"][-1],
        "minutes": document["sim_minutes"][-1],
        "steps_to_target": None if reached is None else document["steps"][reached],
        "minutes_to_target": None if reached is None else document["sim_minutes"][reached],
        "final_velocity": float(np.nanmean(velocity[-last:])),
        "final_eval_velocity": float(np.nanmean(series(document, "eval/forward_velocity")[-last:])),
        "falls_mean": float(falls.mean()),
        "falls_min": float(falls.min()),
        "falls_max": float(falls.max()),
        "falls_after_warmup_mean": float((falls - falls_in_warmup).mean()),
        "eval_falls_mean": float(np.nanmean(series(document, "eval/falls")[-last:])),
        "seeds": len(document["seeds"]),
        "complete": document["complete"],
    }


def load_experiment(experiment: Experiment, folder: Path) -> dict:
    """Results documents of the experiment's runs found in `folder`, keyed by the compared name."""
    found = {}
    for run in experiment.runs:
        path = Path(folder) / result_name(run)
        if path.exists():
            found[experiment.label(run)] = results.read(path)
    return found


def _band(ax, x, values, color, label):
    """Mean line with a min/max band over seeds."""
    with np.errstate(all="ignore"):
        ax.plot(x, np.nanmean(values, axis=1), color=color, label=label, lw=1.8)
        ax.fill_between(x, np.nanmin(values, axis=1), np.nanmax(values, axis=1), color=color, alpha=0.18, lw=0)


def learning_curves(experiment: Experiment, documents: dict, out: Path, profile: str, x_axis: str,
                    panels: tuple, thesis_note: str) -> Path:
    """Learning curves, mean with a min/max band over seeds, one panel per (metric, title, y label)."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.3), constrained_layout=True)
    for label, document in documents.items():
        x = np.array(document["steps"]) / 1000 if x_axis == "steps" else np.array(document["sim_minutes"])
        for ax, (metric, _, _) in zip(axes, panels):
            _band(ax, x, series(document, metric), COLORS.get(label), NAMES.get(label, label))
    for ax, (metric, title, ylabel) in zip(axes, panels):
        if metric.endswith("forward_velocity"):
            ax.axhline(experiment.target_velocity, color="k", ls="--", lw=1, label=f"target {experiment.target_velocity} m/s")
        ax.set_title(title)
        ax.set_ylabel(ylabel)
        ax.set_xlabel("environment steps [k]" if x_axis == "steps" else "simulated minutes (steps / control Hz)")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    seeds = sorted({len(d["seeds"]) for d in documents.values()})
    fig.suptitle(f"{thesis_note[0]}, {profile} profile ({'/'.join(map(str, seeds))} seeds, mean and min/max band)\n"
                 f"thesis {experiment.thesis_figure} (10 seeds, 50k steps): {thesis_note[1]}", fontsize=10)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def forward_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.3-style: forward velocity (training, evaluation) and falls vs steps."""
    thesis = "; ".join(f"{NAMES[a]}: ~{n['steps_to_target'] // 1000}k steps, {n['falls']} falls"
                       for a, n in experiment.thesis_numbers.items())
    panels = (("train/forward_velocity", "training (mean over each 1k-step chunk)", "forward velocity [m/s]"),
              ("eval/forward_velocity", "deterministic evaluation after each chunk", "forward velocity [m/s]"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "steps", panels,
                           ("Forward locomotion at 0.5 m/s, CrossQ", thesis))


def algorithms_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.2-style: velocity, episode return and falls vs simulated minutes for the four algorithms."""
    thesis = ("CrossQ reaches 0.5 m/s after ~2 min, DroQ ~7; falls CrossQ ~14, DroQ ~32; "
              "SAC / SAC-UTD20 reach the target at lower velocities")
    panels = (("train/forward_velocity", "forward velocity (training)", "forward velocity [m/s]"),
              ("train/episode_return", "episode return (800 steps at 40 Hz, 400 at 20 Hz)", "return"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "minutes", panels,
                           ("Algorithm comparison, JT-NF forward at 0.5 m/s", thesis))


def comparison_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Markdown table of our numbers beside the thesis's; time to target in steps or simulated minutes."""
    by_minutes = x_axis == "minutes"
    lines = [
        f"| {experiment.compares.replace('algo', 'algorithm')} "
        f"| seeds x steps{' (simulated min)' if by_minutes else ''} "
        f"| {'minutes' if by_minutes else 'steps'} to 90 % of 0.5 m/s (ours / thesis) | final train velocity "
        "| final eval velocity | falls mean [min-max] (ours / thesis, 50k steps) | of which after warm-up |",
        "|---|---|---|---|---|---|---|",
    ]
    unit, fmt = ("minutes_to_target", "{:.1f}") if by_minutes else ("steps_to_target", "{:,}")
    for label, document in documents.items():
        s = summarize(document, experiment.target_velocity)
        thesis = experiment.thesis_numbers.get(label, {})
        ours = "not reached" if s[unit] is None else fmt.format(s[unit])
        theirs = f"~{fmt.format(thesis[unit])}" if unit in thesis else "reached (no figure given)"
        size = f"{s['seeds']} x {s['steps']:,}" + (f" ({s['minutes']:.1f})" if by_minutes else "")
        thesis_falls = f"~{thesis['falls']}" if "falls" in thesis else "not given"
        lines.append(
            f"| {NAMES.get(label, label)} | {size}{'' if s['complete'] else ' (incomplete)'} | {ours} / {theirs} "
            f"| {s['final_velocity']:.2f} m/s | {s['final_eval_velocity']:.2f} m/s "
            f"| {s['falls_mean']:.1f} [{s['falls_min']:.0f}-{s['falls_max']:.0f}] / {thesis_falls} "
            f"| {s['falls_after_warmup_mean']:.1f} |")
    return "\n".join(lines) + "\n"


FIGURES = {"forward": (forward_figure, "steps"), "algo-comparison": (algorithms_figure, "minutes")}


def draw(results_dir: Path, figures_dir: Path, profile: str, names=None) -> list[Path]:
    """Draw every figure whose results exist; returns the files written."""
    written = []
    for name in names or EXPERIMENTS:
        experiment = EXPERIMENTS[name]
        documents = load_experiment(experiment, Path(results_dir) / name)
        if not documents:
            continue
        figure, x_axis = FIGURES[name]
        written.append(figure(experiment, documents, Path(figures_dir) / f"{name}_{profile}.png", profile))
        table_path = Path(figures_dir) / f"{name}_{profile}.md"
        table_path.write_text(comparison_table(experiment, documents, x_axis))
        written.append(table_path)
    return written
