"""Every figure and table of a profile's experiments, drawn from results files only (nothing here trains): the
figures of curves.py and overview.py, the tables of tables.py, and what they were drawn from (drawn.py)."""

import json
from pathlib import Path

import numpy as np

from mjx_badger.core import safe_io
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, Experiment, load_experiment
from mjx_badger.outputs import drawn, real_world
from mjx_badger.outputs.curves import FIGURES
from mjx_badger.outputs.overview import overview_figure
from mjx_badger.outputs.tables import TABLES, released_code_table
from mjx_badger.realtime.report import SCHEMA as LOOP_SCHEMA
from mjx_badger.records.analysis import released_code
from mjx_badger.records.real_world import LOOP_FOLDERS


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
    loops = {}
    for experiment, folder in LOOP_FOLDERS.items():
        where = Path(results_dir).parent.parent.joinpath(*folder)
        loop = load_loop(where)
        if loop:
            loops[folder[-1]] = {approach: (document, load_trace(where, document)) for approach, document in loop.items()}
        if loop and loaded[experiment]:
            path = figures_dir / f"{experiment}_loop_{profile}.md"
            safe_io.write_text(path, f"Profile: {profile}. The on-robot loop (`realtime --conditions {folder[-1]}`, "
                               f"one run, wall-clock) beside the vmapped {experiment} runs of the same approach.\n\n"
                               + real_world.loop_table(loop, loaded[experiment]))
            written.append(path)
    if loops:
        # The loop's runs are one protocol's (thesis-text) whichever protocol is drawn: one file for all of them.
        written.append(real_world.milestones_figure(loops, figures_dir.parent / "realtime" / "milestones.png"))
        path = figures_dir.parent / "realtime" / "milestones.md"
        safe_io.write_text(path, "The on-robot loop's wall clock (`realtime`, one run each), minutes as training / with "
                           "resets, the thesis's (§5.2, resets included) in brackets; docs/real-world.md explains the "
                           "milestones.\n\n" + real_world.milestones_table(loops))
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


def load_trace(folder: Path, document: dict) -> np.ndarray:
    """The per-step trace saved beside an on-robot run's results file."""
    config = document["config"]
    return np.load(folder / f"{config['approach']}_{config['algo']}_{config['task']}.trace.npy")
