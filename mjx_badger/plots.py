"""Figures and tables drawn from results files only (nothing here trains)."""

import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mjx_badger import results  # noqa: E402
from mjx_badger.actions import APPROACHES  # noqa: E402
from mjx_badger.agents.config import ALGORITHMS  # noqa: E402
from mjx_badger.experiments import EXPERIMENTS, Experiment, result_name  # noqa: E402


def display_name(name: str) -> str:
    """How figures and tables name an approach or algorithm (their registries), else the name itself."""
    entry = APPROACHES.get(name) or ALGORITHMS.get(name)
    return name if entry is None else entry.label


def display_color(name: str) -> str | None:
    """The colour of an approach or algorithm in figures (their registries); None lets matplotlib choose."""
    entry = APPROACHES.get(name) or ALGORITHMS.get(name)
    return None if entry is None else entry.color


LEGS = ("FL", "FR", "RL", "RR")
DIRECTIONS = ("forward", "backward", "left", "right")
REACHED_FRACTION = 0.9
"""A run has reached the target once the seed-mean training velocity is >= 90 % of it."""


def series(document: dict, name: str) -> np.ndarray:
    """Metric `name` as an array (chunks, seeds), NaN where undefined."""
    return np.array(document["metrics"][name], dtype=float)


def last_chunks(document: dict) -> int:
    """How many final chunks count as 'final' (the last tenth of the run, at least one)."""
    return max(1, len(document["steps"]) // 10)


def final(document: dict, name: str) -> np.ndarray:
    """Metric `name` averaged over the final chunks, per seed (seeds,)."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(series(document, name)[-last_chunks(document):], axis=0)


def first_reached(document: dict, target: float) -> int | None:
    """Index of the first chunk whose seed-mean training velocity reaches 90 % of `target`."""
    mean = np.nanmean(series(document, "train/forward_velocity"), axis=1)
    hits = np.flatnonzero(mean >= REACHED_FRACTION * target)
    return int(hits[0]) if hits.size else None


def gait_frequency(contacts, dt: float, low_hz: float = 0.5, high_hz: float = 12.0) -> float:
    """Gait frequency (Hz): the strongest frequency of the feet's contact signals, summed over feet.

    A spectral peak rather than a touchdown count, so a foot that brushes the floor twice in
    one cycle does not double the figure (Hann window, zero-padded to 0.01 Hz bins).
    """
    contacts = np.asarray(contacts, dtype=float)
    signal = (contacts - contacts.mean(axis=0)) * np.hanning(len(contacts))[:, None]
    n = max(int(round(1.0 / (0.01 * dt))), len(contacts))
    power = np.sum(np.abs(np.fft.rfft(signal, n=n, axis=0)) ** 2, axis=1)
    frequency = np.fft.rfftfreq(n, dt)
    band = (frequency >= low_hz) & (frequency <= high_hz)
    if not np.any(power[band] > 0):
        return float("nan")  # no foot changes contact: standing still
    peak = frequency[band][np.argmax(power[band])]
    # Two touchdowns per cycle can make the second harmonic the strongest line: take the lowest
    # whole fraction of the peak that still carries a third of its power, the cycle itself.
    for divisor in (4, 3, 2):
        near = band & (np.abs(frequency - peak / divisor) <= 0.15)
        if peak / divisor >= low_hz and np.any(near) and power[near].max() >= power[band].max() / 3:
            return float(frequency[near][np.argmax(power[near])])
    return float(peak)


def gait_frequencies(document: dict) -> list[float]:
    """Gait frequency of every seed's gait record, or [] if the file has none."""
    gait = document.get("gait")
    if not gait:
        return []
    return [gait_frequency(c, gait["physics_dt"]) for c in gait["contacts"]]


def summarize(document: dict, target: float | None) -> dict:
    """Headline numbers of one run: time to target, final velocities, falls (mean and range), gait."""
    falls_curve = series(document, "train/falls")
    falls = falls_curve[-1]
    warmup = document["config"]["warmup_steps"]
    warmup_chunks = [i for i, step in enumerate(document["steps"]) if step <= warmup]
    falls_in_warmup = falls_curve[warmup_chunks[-1]] if warmup_chunks else np.zeros_like(falls)
    reached = None if target is None else first_reached(document, target)
    frequencies = gait_frequencies(document)
    metrics = document["metrics"]
    eval_velocity = final(document, "eval/forward_velocity") if "eval/forward_velocity" in metrics else None
    return {
        "steps": document["steps"][-1],
        "minutes": document["sim_minutes"][-1],
        "steps_to_target": None if reached is None else document["steps"][reached],
        "minutes_to_target": None if reached is None else document["sim_minutes"][reached],
        "final_velocity": float(np.nanmean(final(document, "train/forward_velocity"))),
        "final_velocity_max": float(np.nanmax(final(document, "train/forward_velocity"))),
        "final_eval_velocity": None if eval_velocity is None else float(np.nanmean(eval_velocity)),
        "final_eval_velocity_max": None if eval_velocity is None else float(np.nanmax(eval_velocity)),
        "falls_mean": float(falls.mean()),
        "falls_min": float(falls.min()),
        "falls_max": float(falls.max()),
        "falls_after_warmup_mean": float((falls - falls_in_warmup).mean()),
        "gait_hz": float(np.nanmean(frequencies)) if frequencies and not np.all(np.isnan(frequencies)) else None,
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


def _band(ax, x, values, color, label, style=None):
    """Mean line with a min/max band over seeds."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN chunks (no episode ended) stay gaps
        ax.plot(x, np.nanmean(values, axis=1), **{"color": color, "label": label, "lw": 1.8, **(style or {})})
        ax.fill_between(x, np.nanmin(values, axis=1), np.nanmax(values, axis=1), color=color, alpha=0.15, lw=0)


def _x(document: dict, x_axis: str):
    return np.array(document["steps"]) / 1000 if x_axis == "steps" else np.array(document["sim_minutes"])


def _x_label(x_axis: str) -> str:
    return "environment steps [k]" if x_axis == "steps" else "simulated minutes (steps / control Hz)"


def _seeds_note(documents: dict) -> str:
    seeds = sorted({len(d["seeds"]) for d in documents.values()})
    return f"{'/'.join(map(str, seeds))} seeds, mean and min/max band"


def curve_panel(ax, documents: dict, metric: str, title: str, ylabel: str, x_axis: str = "steps",
                target: float | None = None, style=None):
    """One panel of learning curves: `metric` of every run that has it."""
    for label, document in documents.items():
        if metric in document["metrics"]:
            _band(ax, _x(document, x_axis), series(document, metric), display_color(label), display_name(label),
                  style)
    if target is not None:
        ax.axhline(target, color="k", ls="--", lw=1, label=f"target {target} m/s")
    ax.set_title(title, fontsize=10)
    ax.set_ylabel(ylabel)
    ax.set_xlabel(_x_label(x_axis))
    ax.grid(alpha=0.3)


def _save(fig, out: Path) -> Path:
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def learning_curves(experiment: Experiment, documents: dict, out: Path, profile: str, x_axis: str,
                    panels: tuple, thesis_note: tuple) -> Path:
    """Learning curves, one panel per (metric, title, y label), mean with a min/max band over seeds."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.3), constrained_layout=True)
    for ax, (metric, title, ylabel) in zip(axes, panels):
        target = experiment.target_velocity if metric.endswith("forward_velocity") else None
        curve_panel(ax, documents, metric, title, ylabel, x_axis, target)
    axes[0].legend(loc="best", fontsize=8)
    fig.suptitle(f"{thesis_note[0]}, {profile} ({_seeds_note(documents)})\n"
                 f"thesis {experiment.thesis_figure} (10 seeds, 50k steps): {thesis_note[1]}", fontsize=10)
    return _save(fig, out)


def gait_figure(experiment: Experiment, documents: dict, out: Path, profile: str, target: float | None) -> Path:
    """Figs 5.4/5.5 (5.7/5.8): one second of foot contacts and of forward velocity after training, seed 0."""
    documents = {k: d for k, d in documents.items() if d.get("gait")}
    fig, axes = plt.subplots(len(documents), 2, figsize=(12, 1.5 * len(documents) + 1), squeeze=False,
                             constrained_layout=True, gridspec_kw={"width_ratios": [1.3, 1]})
    for (label, document), (contact_ax, velocity_ax) in zip(documents.items(), axes):
        gait = document["gait"]
        dt = gait["physics_dt"]
        window = int(round(1.0 / dt))
        contacts = np.asarray(gait["contacts"][0])[-window:]
        t = np.arange(len(contacts)) * dt
        for leg in range(4):
            on = contacts[:, leg] > 0
            contact_ax.fill_between(t, leg - 0.4, leg + 0.4, where=on, color=display_color(label), step="post", lw=0)
        contact_ax.set_yticks(range(4), LEGS)
        contact_ax.set_ylim(3.6, -0.6)
        thesis_hz = experiment.thesis_numbers.get(label, {}).get("gait_hz")
        contact_ax.set_title(f"{display_name(label)}: gait {gait_frequency(contacts, dt):.1f} Hz"
                             + (f" (thesis ~{thesis_hz} Hz)" if thesis_hz else ""), fontsize=9, loc="left")
        velocity = np.asarray(gait["forward_velocity"][0])[-window:]
        velocity_ax.plot(t, velocity, color=display_color(label), lw=1.2)
        if target is not None:
            velocity_ax.axhline(target, color="k", ls="--", lw=0.8)
            velocity_ax.fill_between(t, velocity, target, where=velocity < target, color="tab:red", alpha=0.3, lw=0)
        velocity_ax.set_ylabel("v_x [m/s]")
        velocity_ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s] (stance shaded)")
    axes[-1, 1].set_xlabel("time [s]" + ("" if target is None else f" (below {target} m/s shaded red)"))
    fig.suptitle(f"{experiment.name}: gait and forward velocity over one second after training, deterministic "
                 f"policy, seed 0 ({profile}); thesis {experiment.thesis_figure}", fontsize=10)
    return _save(fig, out)


def direction_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Figs 5.10/5.11 (5.13/5.14): evaluation in four directions at full and half speed over training."""
    documents = {k: d for k, d in documents.items() if "eval/forward_full/desired_velocity" in d["metrics"]}
    runs = [f"{d}_{level}" for level in ("full", "half") for d in DIRECTIONS]
    rows = (("desired_velocity", "velocity along command [m/s]"), ("lateral_velocity", "lateral velocity [m/s]"),
            ("yaw_rate", "yaw rate [rad/s]"))
    fig, axes = plt.subplots(len(rows), len(runs), figsize=(2.6 * len(runs), 2.3 * len(rows) + 0.8),
                             sharex=True, sharey="row", constrained_layout=True)
    for column, run in enumerate(runs):
        speed = 0.5 * (1.0 if run.endswith("full") else 0.5)
        for row, (metric, ylabel) in enumerate(rows):
            ax = axes[row, column]
            curve_panel(ax, documents, f"eval/{run}/{metric}", run.replace("_", ", ") if row == 0 else "", ylabel
                        if column == 0 else "", target=speed if metric == "desired_velocity" else 0.0)
            if row < len(rows) - 1:
                ax.set_xlabel("")
            if column:
                ax.set_ylabel("")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=8)
    fig.suptitle(f"{experiment.name}: deterministic evaluation every chunk in four directions at 0.5 and 0.25 m/s "
                 f"({profile}, {_seeds_note(documents)}); thesis {experiment.thesis_figure}", fontsize=10)
    return _save(fig, out)


def forward_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.3-style: forward velocity (training, evaluation) and falls vs steps."""
    def thesis_item(a, n):
        steps = n["steps_to_target"]
        return f"{display_name(a)} {f'~{steps // 1000}k' if isinstance(steps, int) else steps}"
    thesis = ", ".join(thesis_item(a, n) for a, n in experiment.thesis_numbers.items()) + " steps; falls " + ", ".join(
        f"{display_name(a)} {n['falls']}" for a, n in experiment.thesis_numbers.items())
    panels = (("train/forward_velocity", "training (mean over each 1k-step chunk)", "forward velocity [m/s]"),
              ("eval/forward_velocity", "deterministic evaluation after each chunk", "forward velocity [m/s]"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "steps", panels,
                           ("Forward locomotion at 0.5 m/s, CrossQ", thesis))


def forward_max_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.6-style: forward velocity, lateral velocity and falls under the maximal-velocity reward."""
    thesis = ", ".join(f"{display_name(a)} {n['max_velocity']}" for a, n in experiment.thesis_numbers.items())
    panels = (("train/forward_velocity", "forward velocity (training)", "forward velocity [m/s]"),
              ("train/lateral_velocity", "lateral velocity (training)", "lateral velocity [m/s]"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "steps", panels,
                           ("Forward locomotion at maximal velocity, CrossQ", f"velocities (m/s) {thesis}"))


def omni_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.9 / 5.12-style: velocity along the command, evaluation errors, falls (and curriculum progress)."""
    panels = [("train/desired_velocity", "velocity along the command (training)", "[m/s]"),
              ("eval/desired_mae", "evaluation: desired-velocity MAE (8 runs)", "[m/s]"),
              ("eval/yaw_mae", "evaluation: yaw-rate MAE", "[rad/s]"),
              ("train/falls", "falls during training (cumulative)", "falls")]
    if any("curriculum/learned_bins" in d["metrics"] for d in documents.values()):
        panels.append(("curriculum/learned_bins", "curriculum: bins learned (of 10)", "bins"))
    note = "; ".join(f"{display_name(a)}: {n.get('finding', '')}{', MAE ~%s' % n['desired_mae'] if 'desired_mae' in n else ''}"
                     f" ({n['falls']} falls)" for a, n in experiment.thesis_numbers.items())
    title = ("Omnidirectional locomotion, random commands" if experiment.name == "omni-random"
             else "Omnidirectional locomotion with the PDEC curriculum")
    return learning_curves(experiment, documents, out, profile, "steps", tuple(panels), (title, note))


def pdec_versus_random_figure(pdec: dict, random: dict, out: Path, profile: str) -> Path:
    """Fig 5.12-style: the CPG approaches with the curriculum (solid) and with random commands (dashed)."""
    metrics = (("eval/desired_mae", "desired-velocity MAE [m/s]"), ("eval/lateral_mae", "lateral-velocity MAE [m/s]"),
               ("eval/yaw_mae", "yaw-rate MAE [rad/s]"))
    fig, axes = plt.subplots(1, len(metrics), figsize=(15, 4.3), constrained_layout=True)
    for ax, (metric, label) in zip(axes, metrics):
        curve_panel(ax, pdec, metric, label, label)
        curve_panel(ax, {k: v for k, v in random.items() if k in pdec}, metric, label, label,
                    style={"ls": "--", "label": None})
    axes[0].legend(fontsize=8, title="solid PDEC, dashed random", title_fontsize=8)
    fig.suptitle(f"Curriculum (PDEC) vs random commands, evaluation over 8 runs ({profile}); "
                 "thesis Fig 5.12: the curriculum improves every CPG approach, desired MAE ~0.05 m/s", fontsize=10)
    return _save(fig, out)


def algorithms_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.2-style: velocity, episode return and falls vs simulated minutes for the four algorithms."""
    thesis = ("CrossQ reaches 0.5 m/s after ~2 min, DroQ ~7; falls CrossQ ~14, DroQ ~32; "
              "SAC / SAC-UTD20 reach the target at lower velocities")
    panels = (("train/forward_velocity", "forward velocity (training)", "forward velocity [m/s]"),
              ("train/episode_return", "episode return (one episode: the protocol's seconds x control Hz steps)", "return"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "minutes", panels,
                           ("Algorithm comparison, JT-NF forward at 0.5 m/s", thesis))


def _value(value, fmt="{:.2f}", missing="-"):
    return missing if value is None else fmt.format(value)


def _thesis(numbers: dict, key: str, fmt="~{}"):
    return fmt.format(numbers[key]) if key in numbers else "not given"


def _run_cells(label: str, s: dict) -> str:
    """'| name | seeds x steps' of a table row, marked when the run is incomplete."""
    return f"| {display_name(label)} | {s['seeds']} x {s['steps']:,}{'' if s['complete'] else ' (incomplete)'}"


def _falls_cell(s: dict, thesis: dict) -> str:
    return f"{s['falls_mean']:.1f} [{s['falls_min']:.0f}-{s['falls_max']:.0f}] / {_thesis(thesis, 'falls')}"


def _gait_cell(s: dict, thesis: dict) -> str:
    return f"{_value(s['gait_hz'], '{:.1f}')} / {_thesis(thesis, 'gait_hz')}"


def comparison_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Markdown table of our numbers beside the thesis's; time to target in steps or simulated minutes."""
    by_minutes = x_axis == "minutes"
    lines = [
        f"| {experiment.compares.replace('algo', 'algorithm')} "
        f"| seeds x steps{' (simulated min)' if by_minutes else ''} "
        f"| {'minutes' if by_minutes else 'steps'} to 90 % of 0.5 m/s (ours / thesis) | final train velocity "
        "| final eval velocity | falls mean [min-max] (ours / thesis, 50k steps) | of which after warm-up "
        "| gait Hz (ours / thesis) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    unit, fmt = ("minutes_to_target", "{:.1f}") if by_minutes else ("steps_to_target", "{:,}")
    for label, document in documents.items():
        s = summarize(document, experiment.target_velocity)
        thesis = experiment.thesis_numbers.get(label, {})
        ours = "not reached" if s[unit] is None else fmt.format(s[unit])
        theirs = thesis.get(unit, "reached (no figure given)")
        theirs = f"~{fmt.format(theirs)}" if isinstance(theirs, (int, float)) else theirs
        size = f"{s['seeds']} x {s['steps']:,}" + (f" ({s['minutes']:.1f})" if by_minutes else "")
        lines.append(
            f"| {display_name(label)} | {size}{'' if s['complete'] else ' (incomplete)'} | {ours} / {theirs} "
            f"| {s['final_velocity']:.2f} m/s | {_value(s['final_eval_velocity'])} m/s "
            f"| {_falls_cell(s, thesis)} | {s['falls_after_warmup_mean']:.1f} | {_gait_cell(s, thesis)} |")
    return "\n".join(lines) + "\n"


def max_velocity_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Tables 6.1/6.2 (simulation column) with our maximal velocities beside the thesis's."""
    lines = ["| approach | seeds x steps | max velocity, thesis (m/s) | ours: final train velocity mean [best seed] "
             "| ours: final eval velocity mean [best seed] | falls mean [min-max] (ours / thesis) "
             "| gait Hz (ours / thesis) |", "|---|---|---|---|---|---|---|"]
    for label, document in documents.items():
        s = summarize(document, None)
        thesis = experiment.thesis_numbers.get(label, {})
        lines.append(
            f"{_run_cells(label, s)} | {_thesis(thesis, 'max_velocity', '{}')} "
            f"| {s['final_velocity']:.2f} [{s['final_velocity_max']:.2f}] "
            f"| {_value(s['final_eval_velocity'])} [{_value(s['final_eval_velocity_max'])}] "
            f"| {_falls_cell(s, thesis)} | {_gait_cell(s, thesis)} |")
    return "\n".join(lines) + "\n"


def omni_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Final evaluation per approach: errors, velocity along the command per direction, falls, curriculum."""
    lines = ["| approach | seeds x steps | desired / lateral / yaw MAE | velocity along command at 0.5 m/s: "
             "forward, backward, left, right | same at 0.25 m/s | falls mean [min-max] (ours / thesis) "
             "| bins learned | thesis finding |", "|---|---|---|---|---|---|---|---|"]
    for label, document in documents.items():
        s = summarize(document, None)
        thesis = experiment.thesis_numbers.get(label, {})
        f = lambda name: float(np.nanmean(final(document, name)))
        errors = " / ".join(f"{f(f'eval/{k}_mae'):.2f}" for k in ("desired", "lateral", "yaw"))
        speeds = [", ".join(f"{f(f'eval/{d}_{level}/desired_velocity'):.2f}" for d in DIRECTIONS)
                  for level in ("full", "half")]
        bins = (f"{float(np.mean(series(document, 'curriculum/learned_bins')[-1])):.1f}"
                if "curriculum/learned_bins" in document["metrics"] else "-")
        finding = thesis.get("finding", f"desired MAE ~{thesis['desired_mae']}" if "desired_mae" in thesis else "")
        lines.append(
            f"{_run_cells(label, s)} | {errors} | {speeds[0]} | {speeds[1]} "
            f"| {_falls_cell(s, thesis)} | {bins} | {finding} |")
    return "\n".join(lines) + "\n"


FIGURES = {
    "algo-comparison": (algorithms_figure, comparison_table, "minutes"),
    "forward": (forward_figure, comparison_table, "steps"),
    "forward-max": (forward_max_figure, max_velocity_table, "steps"),
    "omni-random": (omni_figure, omni_table, "steps"),
    "omni-pdec": (omni_figure, omni_table, "steps"),
}


def overview_figure(loaded: dict, out: Path, profile: str) -> Path:
    """Everything at a glance: the headline curve of every experiment with results, and falls per approach."""
    headline = {
        "algo-comparison": ("train/forward_velocity", "algorithms (Fig 5.2): forward velocity", "minutes", 0.5),
        "forward": ("train/forward_velocity", "forward 0.5 m/s (Fig 5.3): velocity", "steps", 0.5),
        "forward-max": ("train/forward_velocity", "maximal velocity (Fig 5.6): velocity", "steps", None),
        "omni-random": ("eval/desired_mae", "omni, random (Fig 5.9): desired MAE", "steps", None),
        "omni-pdec": ("eval/desired_mae", "omni, PDEC (Fig 5.12): desired MAE", "steps", None),
    }
    fig, axes = plt.subplots(2, 3, figsize=(16, 9), constrained_layout=True)
    axes = axes.ravel()
    for ax, (name, (metric, title, x_axis, target)) in zip(axes, headline.items()):
        if not loaded.get(name):
            ax.text(0.5, 0.5, f"no {name} results yet:\npython -m mjx_badger reproduce\n--profile {profile.split()[0]} "
                    f"--experiments {name}", ha="center", va="center", fontsize=9, color="0.4", transform=ax.transAxes)
            ax.set_title(title, fontsize=10)
            ax.set_xticks([])
            ax.set_yticks([])
            continue
        curve_panel(ax, loaded[name], metric, title, "[m/s]", x_axis, target)
        ax.legend(fontsize=7)
    falls_ax = axes[5]
    experiments = [n for n in ("forward", "forward-max", "omni-random", "omni-pdec") if loaded.get(n)]
    width = 0.8 / max(len(experiments), 1)
    approaches = [a for a in APPROACHES if any(a in loaded[n] for n in experiments)]
    for i, name in enumerate(experiments):
        means = [summarize(loaded[name][a], None)["falls_mean"] if a in loaded[name] else np.nan for a in approaches]
        falls_ax.bar(np.arange(len(approaches)) + i * width, means, width, label=name)
    falls_ax.set_xticks(np.arange(len(approaches)) + width * (len(experiments) - 1) / 2,
                        [display_name(a) for a in approaches], fontsize=8)
    falls_ax.set_title("falls during training, mean over seeds", fontsize=10)
    falls_ax.legend(fontsize=7)
    falls_ax.grid(alpha=0.3, axis="y")
    fig.suptitle(f"mjx_badger: every thesis simulation experiment at a glance ({profile})", fontsize=12)
    return _save(fig, out)


def _rolling(x, window: int):
    """Trailing mean over `window` samples (shorter at the start)."""
    cumulative = np.cumsum(np.insert(np.asarray(x, np.float64), 0, 0.0))
    index = np.arange(1, len(x) + 1)
    return (cumulative[index] - cumulative[np.maximum(index - window, 0)]) / np.minimum(index, window)


def realtime_figure(document: dict, trace: np.ndarray, out: Path) -> Path:
    """An on-robot run: velocity (estimated and true) over training time with the falls, the
    estimator's bias over ten seconds (as thesis Fig 2.1), and the control-period spread."""
    config, timing = document["config"], document["timing"]
    hz = config["hz"]
    minutes = trace[:, 1] / 60
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2), gridspec_kw={"width_ratios": [2.2, 1.6, 1.2]})
    ax = axes[0]
    window = int(5 * hz)
    ax.plot(minutes, _rolling(trace[:, 4], window), color="tab:blue", lw=1.6, label="true (simulator)")
    ax.plot(minutes, _rolling(trace[:, 2], window), color="tab:orange", lw=1.6, label="estimated (Kalman)")
    if config["task"] == "forward":
        ax.axhline(config["target_velocity"], color="k", ls="--", lw=1, label=f"target {config['target_velocity']} m/s")
    for fall_minute in minutes[trace[:, 7] > 0]:
        ax.axvline(fall_minute, color="tab:red", alpha=0.25, lw=0.8)
    ax.plot([], [], color="tab:red", alpha=0.5, label=f"safety stop ({document['falls']})")
    ax.set_xlabel("training minutes (resets excluded)")
    ax.set_ylabel("forward velocity [m/s], 5 s mean")
    ax.set_title(f"{config['algo']} {config['approach']} on the simulated HB40, {hz:g} Hz", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)

    ax = axes[1]
    last = trace[-int(10 * hz):]
    seconds = last[:, 1] - last[0, 1]
    ax.plot(seconds, last[:, 4], color="tab:blue", lw=1.2, label="true")
    ax.plot(seconds, last[:, 2], color="tab:orange", lw=1.2, label="estimated")
    bias = np.nanmean(last[:, 2] - last[:, 4])
    ax.set_title(f"last 10 s of training: estimate - truth = {bias:+.3f} m/s", fontsize=10)
    ax.set_xlabel("seconds")
    ax.set_ylabel("forward velocity [m/s]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)

    ax = axes[2]
    histogram = timing["period_histogram"]
    edges = np.asarray(histogram["edges_ms"])
    ax.bar(edges[:-1], histogram["counts"], width=np.diff(edges), align="edge", color="tab:gray")
    ax.axvline(timing["nominal_period_ms"], color="k", ls="--", lw=1)
    ax.set_yscale("log")
    ax.set_xlabel("control period [ms]")
    ax.set_title(f"p50 {timing['period_p50_ms']:.2f} ms, p99 error {timing['period_error_p99_ms']:.2f} ms, "
                 f"{timing['missed_deadlines']} late" if timing["period_p50_ms"] is not None
                 else "no control period timed in this session", fontsize=10)
    outside = histogram["below"] + histogram["above"]
    notes = [f"largest period error {timing['period_error_max_ms']:.1f} ms"]
    if outside:
        notes.insert(0, f"{outside} periods outside the axis")
    if timing.get("scheduling"):
        notes.append(f"control thread: {timing['scheduling']}")
    ax.text(0.02, 0.95, "\n".join(notes), transform=ax.transAxes, fontsize=8, va="top")
    evaluation = document.get("evaluation") or {}
    summary = (f"{document['steps']} steps, {document['train_minutes']:.1f} min training "
               f"({document['minutes_with_resets']:.1f} with resets), {document['falls']} falls, "
               f"{document['updates_per_learning_step']:.2f} updates per learning step")
    if evaluation.get("true_velocity") is not None:
        summary += (f"; evaluation {evaluation['true_velocity']:.2f} m/s mean, "
                    f"{evaluation['true_peak_1s']:.2f} m/s best second")
    fig.suptitle(summary, fontsize=10)
    fig.tight_layout()
    return _save(fig, out)


def draw(results_dir: Path, figures_dir: Path, profile: str, names=None, protocol: str = "thesis-code") -> list[Path]:
    """Draw every figure and table whose results exist; returns the files written.

    `results_dir` holds one protocol's experiments; files go to figures_dir/<protocol>/ and every
    title names the profile and the protocol.
    """
    written = []
    figures_dir = Path(figures_dir) / protocol
    figures_dir.mkdir(parents=True, exist_ok=True)
    label = f"{profile} profile, {protocol} protocol"
    loaded = {name: load_experiment(EXPERIMENTS[name], Path(results_dir) / name) for name in EXPERIMENTS}
    for name in names or EXPERIMENTS:
        experiment, documents = EXPERIMENTS[name], loaded[name]
        if not documents:
            continue
        figure, table, x_axis = FIGURES[name]
        written.append(figure(experiment, documents, figures_dir / f"{name}_{profile}.png", label))
        table_path = figures_dir / f"{name}_{profile}.md"
        table_path.write_text(f"Protocol: {protocol}, profile: {profile}\n\n" + table(experiment, documents, x_axis))
        written.append(table_path)
        if any(d.get("gait") for d in documents.values()) and name != "algo-comparison":
            written.append(gait_figure(experiment, documents, figures_dir / f"{name}_gait_{profile}.png", label,
                                       experiment.target_velocity))
        if name.startswith("omni"):
            written.append(direction_figure(experiment, documents, figures_dir / f"{name}_directions_{profile}.png",
                                            label))
    if loaded["omni-pdec"] and loaded["omni-random"]:
        written.append(pdec_versus_random_figure(loaded["omni-pdec"], loaded["omni-random"],
                                                 figures_dir / f"omni-pdec_vs_random_{profile}.png", label))
    if any(loaded.values()):
        written.append(overview_figure(loaded, figures_dir / f"overview_{profile}.png", label))
    return written
