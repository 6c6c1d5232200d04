"""Figures drawn from results files only (nothing here trains); numbers from analysis.py, tables from tables.py."""

import json
import textwrap
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mjx_badger import drawn, real_world, results, safe_io  # noqa: E402
from mjx_badger.actions import APPROACHES  # noqa: E402
from mjx_badger.analysis import (DIRECTIONS, display_color, display_name, gait_frequency, released_code,  # noqa: E402
                                 load_experiment, series, summarize)
from mjx_badger.experiments import EXPERIMENTS, GROUPS, Experiment  # noqa: E402
from mjx_badger.robot import ROBOTS  # noqa: E402
from mjx_badger.realtime.report import SCHEMA as LOOP_SCHEMA  # noqa: E402
from mjx_badger.tables import TABLES, released_code_table  # noqa: E402


def _band(ax, x, values, color, label, style=None, band=True):
    """Mean line with a min/max band over seeds (or the mean line alone)."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN chunks (no episode ended) stay gaps
        ax.plot(x, np.nanmean(values, axis=1), **{"color": color, "label": label, "lw": 1.8, **(style or {})})
        if band:
            ax.fill_between(x, np.nanmin(values, axis=1), np.nanmax(values, axis=1), color=color, alpha=0.15, lw=0)


def _x(document: dict, x_axis: str):
    return np.array(document["steps"]) / 1000 if x_axis == "steps" else np.array(document["sim_minutes"])


def _x_label(x_axis: str) -> str:
    return "environment steps [k]" if x_axis == "steps" else "simulated minutes (steps / control Hz)"


def _seeds_note(documents: dict) -> str:
    """'3 seeds, mean and min/max band', naming any seed left out for diverging (results.healthy)."""
    seeds = sorted({len(d["seeds"]) for d in documents.values()})
    gone = [f"{display_name(label)} {words}" for label, d in documents.items() if (words := results.left_out_words(d))]
    return f"{'/'.join(map(str, seeds))} seeds, mean and min/max band" + "".join(f"; {g}" for g in gone)


def curve_panel(ax, documents: dict, metric: str, title: str, ylabel: str, x_axis: str = "steps",
                target: float | None = None, style=None, band=True):
    """One panel of learning curves: `metric` of every run that has it."""
    for label, document in documents.items():
        if metric in document["metrics"]:
            _band(ax, _x(document, x_axis), series(document, metric), display_color(label), display_name(label),
                  style, band)
    if target is not None:
        ax.axhline(target, color="k", ls="--", lw=1, label=f"target {target} m/s")
    ax.set_title(title, fontsize=10)
    ax.set_ylabel(ylabel)
    ax.set_xlabel(_x_label(x_axis))
    ax.grid(alpha=0.3)


def _save(fig, out: Path) -> Path:
    try:
        safe_io.save_figure(fig, out, dpi=110)
    finally:
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
    thesis = f"thesis {experiment.thesis_figure} (10 seeds, 50k steps): {thesis_note[1]}"
    # A title line wider than the figure is cut at both edges: wrap it at about 11 characters per inch.
    lines = textwrap.wrap(thesis, width=int(11 * fig.get_figwidth()))
    fig.suptitle("\n".join([f"{thesis_note[0]}, {profile} ({_seeds_note(documents)})", *lines]), fontsize=10)
    return _save(fig, out)


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
                 f"policy, first kept seed ({profile}; {_seeds_note(documents)}); thesis {experiment.thesis_figure}",
                 fontsize=10)
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
                 f"{_seeds_note({**{'random ' + k: v for k, v in random.items()}, **pdec})});\n"  # one line would be wider than the figure
                 "thesis Fig 5.12: the curriculum improves every CPG approach, desired MAE ~0.05 m/s", fontsize=10)
    return _save(fig, out)


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
    fig.suptitle(f"mjx_badger: every thesis simulation experiment at a glance ({profile}; {_seeds_note(every)})",
                 fontsize=12)
    return _save(fig, out)


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
    return _save(fig, out)


def experiment_files(experiment: Experiment, figures_dir: Path, profile: str) -> list[Path]:
    """Every file `draw` writes for `experiment` into `figures_dir` (one protocol's)."""
    name = experiment.name
    paths = [figures_dir / f"{name}{'' if index == 0 else f'_vs_{experiment.baseline}' if kind == 'versus' else f'_{kind}'}"
                           f"_{profile}.png" for index, kind in enumerate(experiment.figures)]
    return paths + [figures_dir / f"{name}_{profile}.md", figures_dir / f"{name}_vs_released-code_{profile}.md"]


def draw(results_dir: Path, figures_dir: Path, profile: str, names=None, protocol: str = "thesis-code",
         kept: list | None = None) -> list[Path]:
    """Draw every figure and table whose results exist; returns the files written.

    `results_dir` holds one protocol's experiments; files go to figures_dir/<protocol>/ and every
    title names the profile and the protocol. An experiment's files drawn before from more
    complete runs than there are now are kept instead (each appended to `kept` with the reason;
    drawn.py), so that a partial rerun never replaces a fuller figure.
    """
    written = []
    figures_dir = Path(figures_dir) / protocol
    label = f"{profile} profile, {protocol} protocol"
    loaded = {name: load_experiment(EXPERIMENTS[name], Path(results_dir) / name) for name in EXPERIMENTS}
    record = drawn.Drawn(figures_dir, profile)
    for name in names or EXPERIMENTS:
        experiment, documents = EXPERIMENTS[name], loaded[name]
        if not documents:
            continue
        done, needed = drawn.complete_runs(experiment, documents)
        if record.keeps(experiment_files(experiment, figures_dir, profile), done, needed,
                        f"{done} of {needed} runs complete under {Path(results_dir) / name}", kept):
            continue
        before = len(written)
        for index, kind in enumerate(experiment.figures):
            suffix = "" if index == 0 else f"_vs_{experiment.baseline}" if kind == "versus" else f"_{kind}"
            path = FIGURES[kind](experiment, documents, figures_dir / f"{name}{suffix}_{profile}.png", label, loaded)
            written += [path] if path is not None else []
        table_path = figures_dir / f"{name}_{profile}.md"
        table = TABLES[experiment.table](experiment, documents, experiment.x_axis)
        safe_io.write_text(table_path, f"Protocol: {protocol}, profile: {profile}\n\n" + table)
        written.append(table_path)
        released = released_code(name) if protocol == "thesis-code" else None
        if released is not None:  # the released code's own spread, the check for thesis-code
            beside = figures_dir / f"{name}_vs_released-code_{profile}.md"
            safe_io.write_text(beside, f"Protocol: {protocol}, profile: {profile}. {released['what']}\n\n"
                              + released_code_table(documents, released, profile))
            written.append(beside)
        record.note(written[before:], done)
    counts = [drawn.complete_runs(EXPERIMENTS[name], loaded[name]) for name in GROUPS["simulation"]]
    done, needed = sum(c[0] for c in counts), sum(c[1] for c in counts)
    overview = figures_dir / f"overview_{profile}.png"
    if any(loaded[name] for name in GROUPS["simulation"]) and not record.keeps([overview], done, needed, f"{done} of {needed} runs complete "
                                                                          f"under {results_dir}", kept):
        written.append(overview_figure(loaded, overview, label))
        record.note([overview], done)
    if loaded["forward-max"] and (loaded["real-office"] or loaded["real-outdoor"]):
        path = figures_dir / f"table_6_{profile}.md"
        safe_io.write_text(path, f"Protocol: {protocol}, profile: {profile}. Tables 6.1/6.2: forward velocity (m/s), "
                           "simulation at maximal velocity, office and outdoor at the 0.25 m/s target.\n\n"
                           + real_world.table_6(loaded["forward-max"], loaded["real-office"], loaded["real-outdoor"]))
        written.append(path)
    loop = load_loop(Path(results_dir).parent.parent.joinpath(*real_world.LOOP_FOLDER))
    if loop and loaded["real-outdoor"]:
        path = figures_dir / f"real-outdoor_loop_{profile}.md"
        safe_io.write_text(path, f"Profile: {profile}. The on-robot loop (`realtime --conditions outdoor`, one run, 40 Hz "
                           "wall-clock) beside the vmapped real-outdoor runs of the same approach.\n\n"
                           + real_world.loop_table(loop, loaded["real-outdoor"]))
        written.append(path)
    return written


def load_loop(folder: Path) -> dict:
    """The forward-task CrossQ runs of the on-robot loop in `folder`, by approach (none when it does not exist)."""
    runs = {}
    for path in sorted(folder.glob("*_crossq_forward.json")) if folder.is_dir() else ():
        document = json.loads(path.read_text())
        if document.get("schema") != LOOP_SCHEMA:
            raise ValueError(f"{path}: not a {LOOP_SCHEMA} results file (realtime's)")
        runs[document["config"]["approach"]] = document
    return runs
