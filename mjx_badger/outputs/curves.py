"""The figures of each thesis experiment, from its results documents: learning curves (Figs 5.2, 5.3, 5.6, 5.9,
5.12), gaits (Figs 5.4/5.5, 5.7/5.8) and evaluation by direction (Figs 5.10/5.11, 5.13/5.14)."""

import textwrap
from pathlib import Path

import numpy as np

from mjx_badger.experiments.registry import Experiment
from mjx_badger.outputs import real_world
from mjx_badger.outputs.style import curve_panel, plt, save, seeds_note
from mjx_badger.records.analysis import DIRECTIONS, display_color, display_name, gait_names
from mjx_badger.robot.description import ROBOTS
from mjx_badger.sim.gait import GAITS, gait_frequency, gait_name


def learning_curves(experiment: Experiment, documents: dict, out: Path, profile: str, x_axis: str,
                    panels: tuple, thesis_note: tuple) -> Path:
    """Learning curves, one panel per (metric, title, y label), mean with a min/max band over seeds."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.3), constrained_layout=True)
    for ax, (metric, title, ylabel) in zip(axes, panels):
        target = experiment.target_velocity if metric.endswith("forward_velocity") else None
        curve_panel(ax, documents, metric, title, ylabel, x_axis, target)
    axes[0].legend(loc="best", fontsize=8)
    thesis = f"thesis {experiment.thesis_figure} (10 seeds, 50k steps): {thesis_note[1]}"
    # A title line wider than the figure is cut at both edges: wrap it at about 11 characters per inch.
    lines = textwrap.wrap(thesis, width=int(11 * fig.get_figwidth()))
    fig.suptitle("\n".join([f"{thesis_note[0]}, {profile} ({seeds_note(documents)})", *lines]), fontsize=10)
    return save(fig, out)


def gait_figure(experiment: Experiment, documents: dict, out: Path, profile: str, target: float | None) -> Path:
    """Figs 5.4/5.5 (5.7/5.8): one second of foot contacts and of forward velocity after training, first kept seed."""
    documents = {k: d for k, d in documents.items() if d.get("gait")}
    fig, axes = plt.subplots(len(documents), 2, figsize=(12, 1.5 * len(documents) + 1), squeeze=False,
                             constrained_layout=True, gridspec_kw={"width_ratios": [1.3, 1]})
    for (label, document), (contact_ax, velocity_ax) in zip(documents.items(), axes):
        gait = document["gait"]
        dt = gait["physics_dt"]
        window = int(round(1.0 / dt))
        contacts = np.asarray(gait["contacts"][0])[-window:]
        t = np.arange(len(contacts)) * dt
        legs = ROBOTS[document["config"].get("robot", "hb40")].legs
        for leg in range(len(legs)):
            on = contacts[:, leg] > 0
            contact_ax.fill_between(t, leg - 0.4, leg + 0.4, where=on, color=display_color(label), step="post", lw=0)
        contact_ax.set_yticks(range(len(legs)), legs)
        contact_ax.set_ylim(len(legs) - 0.4, -0.6)
        thesis = experiment.thesis_numbers.get(label, {})
        thesis_words = " ".join(w for w in (thesis.get("gait"), thesis.get("gait_hz") and f"~{thesis['gait_hz']} Hz") if w)
        names = gait_names(document)
        seeds = ", ".join(f"{name} {names.count(name)}" for name in GAITS if name in names)
        whole = gait["contacts"][0]  # the frequency and the gait from the whole record: one second holds few cycles
        contact_ax.set_title(f"{display_name(label)}: {gait_name(whole, dt)} at {gait_frequency(whole, dt):.1f} Hz" + (f" (thesis {thesis_words})" if thesis_words
                                                                          else "") + f"; seeds: {seeds}",
                             fontsize=9, loc="left")
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
                 f"policy, first kept seed ({profile}; {seeds_note(documents)})\nthesis {experiment.thesis_figure}; "
                 "gaits named from the feet's phases over the whole record (sim/gait.py)", fontsize=10)
    return save(fig, out)


def direction_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Figs 5.10/5.11 (5.13/5.14): evaluation in four directions at full and half speed over training."""
    documents = {k: d for k, d in documents.items() if "eval/forward_full/desired_velocity" in d["metrics"]}
    runs = [f"{d}_{level}" for level in ("full", "half") for d in DIRECTIONS]
    rows = (("desired_velocity", "velocity along command [m/s]"), ("lateral_velocity", "lateral velocity [m/s]"),
            ("yaw_rate", "yaw rate [rad/s]"))
    fig, axes = plt.subplots(len(rows), len(runs), figsize=(2.6 * len(runs), 2.3 * len(rows) + 0.8),
                             sharex=True, sharey="row", constrained_layout=True)
    for column, run in enumerate(runs):
        speed = experiment.target_velocity * (1.0 if run.endswith("full") else 0.5)
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
    v = experiment.target_velocity
    fig.suptitle(f"{experiment.name}: deterministic evaluation every chunk in four directions at {v} and {v / 2} m/s "
                 f"({profile}, {seeds_note(documents)}); thesis {experiment.thesis_figure}", fontsize=10)
    return save(fig, out)


def forward_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.3-style: forward velocity (training, evaluation) and falls vs steps."""
    def thesis_item(a, n):
        steps = n["steps_to_target"]
        return f"{display_name(a)} {f'~{steps // 1000}k' if isinstance(steps, int) else steps}"
    thesis = ", ".join(thesis_item(a, n) for a, n in experiment.thesis_numbers.items()) + " steps; falls " + ", ".join(
        f"{display_name(a)} {n['falls']}" for a, n in experiment.thesis_numbers.items())
    panels = (("train/forward_velocity", "training (mean over each 1k-step chunk)", "forward velocity [m/s]"),
              ("eval/desired_velocity", "deterministic evaluation after each chunk", "forward velocity [m/s]"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "steps", panels,
                           (f"Forward locomotion at {experiment.target_velocity} m/s, CrossQ", thesis))


def forward_max_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.6-style: forward velocity, lateral velocity and falls under the maximal-velocity reward."""
    thesis = ", ".join(f"{display_name(a)} {n['max_velocity']}" for a, n in experiment.thesis_numbers.items())
    panels = (("train/forward_velocity", "forward velocity (training)", "forward velocity [m/s]"),
              ("train/lateral_velocity", "lateral velocity (training)", "lateral velocity [m/s]"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "steps", panels,
                           ("Forward locomotion at maximal velocity, CrossQ", f"velocities (m/s) {thesis}"))


def omni_thesis_note(numbers: dict) -> str:
    """One approach's thesis numbers for an omni figure's title: its finding, desired MAE and falls."""
    parts = [numbers.get("finding"), f"MAE ~{numbers['desired_mae']}" if "desired_mae" in numbers else None]
    return ", ".join(part for part in parts if part) + f" ({numbers['falls']} falls)"


def omni_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.9 / 5.12-style: velocity along the command, evaluation errors, falls (and curriculum progress)."""
    panels = [("train/desired_velocity", "velocity along the command (training)", "[m/s]"),
              ("eval/desired_mae", "evaluation: desired-velocity MAE (8 runs)", "[m/s]"),
              ("eval/yaw_mae", "evaluation: yaw-rate MAE", "[rad/s]"),
              ("train/falls", "falls during training (cumulative)", "falls")]
    if any("curriculum/learned_bins" in d["metrics"] for d in documents.values()):
        panels.append(("curriculum/learned_bins", "curriculum: bins learned (of 10)", "bins"))
    note = "; ".join(f"{display_name(a)}: {omni_thesis_note(n)}" for a, n in experiment.thesis_numbers.items())
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
    fig.suptitle(f"Curriculum (PDEC) vs random commands, evaluation over 8 runs ({profile}; "
                 f"{seeds_note({**{'random ' + k: v for k, v in random.items()}, **pdec})});\n"  # one line would be wider than the figure
                 "thesis Fig 5.12: the curriculum improves every CPG approach, desired MAE ~0.05 m/s", fontsize=10)
    return save(fig, out)


def algorithms_figure(experiment: Experiment, documents: dict, out: Path, profile: str) -> Path:
    """Fig 5.2-style: velocity, episode return and falls vs simulated minutes for the four algorithms."""
    thesis = ("CrossQ reaches 0.5 m/s after ~2 min, DroQ ~7; falls CrossQ ~14, DroQ ~32; "  # the thesis's words
              "SAC / SAC-UTD20 reach the target at lower velocities")
    panels = (("train/forward_velocity", "forward velocity (training)", "forward velocity [m/s]"),
              ("train/episode_return", "episode return (one episode: the protocol's seconds x control Hz steps)", "return"),
              ("train/falls", "falls during training (cumulative)", "falls"))
    return learning_curves(experiment, documents, out, profile, "minutes", panels,
                           (f"Algorithm comparison, JT-NF forward at {experiment.target_velocity} m/s", thesis))


FIGURES = {
    "real": lambda e, docs, out, label, loaded: real_world.figure(e, docs, out, label),
    "algorithms": lambda e, docs, out, label, loaded: algorithms_figure(e, docs, out, label),
    "forward": lambda e, docs, out, label, loaded: forward_figure(e, docs, out, label),
    "forward-max": lambda e, docs, out, label, loaded: forward_max_figure(e, docs, out, label),
    "omni": lambda e, docs, out, label, loaded: omni_figure(e, docs, out, label),
    "gait": lambda e, docs, out, label, loaded: (gait_figure(e, docs, out, label, e.target_velocity)
                                                 if any(d.get("gait") for d in docs.values()) else None),
    "directions": lambda e, docs, out, label, loaded: direction_figure(e, docs, out, label),
    "versus": lambda e, docs, out, label, loaded: (pdec_versus_random_figure(docs, loaded[e.baseline], out, label)
                                                   if loaded.get(e.baseline) else None),
}
"""Figure kind (Experiment.figures) -> (experiment, its documents, out, title label, every experiment's) -> Path or None."""
