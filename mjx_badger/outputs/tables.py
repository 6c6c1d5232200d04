"""Markdown tables of our numbers beside the thesis's, one per experiment kind, from results files only."""

import numpy as np

from mjx_badger.experiments.registry import Experiment
from mjx_badger.outputs import real_world
from mjx_badger.records.analysis import DIRECTIONS, display_name, final, per_seed_released_measures, series, summarize


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
    """'Hz gait / thesis Hz gait': the seeds' mean frequency and most common gait (sim/gait.py)."""
    ours = _value(s["gait_hz"], "{:.1f}") + (f" {s['gait']}" if s.get("gait") else "")
    return f"{ours} / {_thesis(thesis, 'gait_hz')}" + (f" {thesis['gait']}" if "gait" in thesis else "")


def comparison_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Markdown table of our numbers beside the thesis's; time to target in steps or simulated minutes."""
    by_minutes = x_axis == "minutes"
    lines = [
        f"| {experiment.compares.replace('algo', 'algorithm')} "
        f"| seeds x steps{' (simulated min)' if by_minutes else ''} "
        f"| {'minutes' if by_minutes else 'steps'} to 90 % of {experiment.target_velocity} m/s (ours / thesis) "
        "| final train velocity "
        "| final eval velocity | falls mean [min-max] (ours / thesis, 50k steps) | of which after warm-up "
        "| gait Hz and kind (ours / thesis) |",
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


def _per_run(experiment: Experiment, documents: dict, columns: list[str], cells) -> str:
    """A table with one row per run: approach and size, then `cells(document, summary, thesis numbers)`."""
    lines = ["| " + " | ".join(["approach", "seeds x steps", *columns]) + " |", "|---" * (len(columns) + 2) + "|"]
    for label, document in documents.items():
        s = summarize(document, None)
        lines.append(f"{_run_cells(label, s)} | {cells(document, s, experiment.thesis_numbers.get(label, {}))} |")
    return "\n".join(lines) + "\n"


def max_velocity_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Tables 6.1/6.2 (simulation column) with our maximal velocities beside the thesis's."""
    columns = ["max velocity, thesis (m/s)", "ours: final train velocity mean [best seed]",
               "ours: final eval velocity mean [best seed]", "falls mean [min-max] (ours / thesis)",
               "gait Hz and kind (ours / thesis)"]
    return _per_run(experiment, documents, columns, lambda document, s, thesis: (
        f"{_thesis(thesis, 'max_velocity', '{}')} | {s['final_velocity']:.2f} [{s['final_velocity_max']:.2f}] "
        f"| {_value(s['final_eval_velocity'])} [{_value(s['final_eval_velocity_max'])}] "
        f"| {_falls_cell(s, thesis)} | {_gait_cell(s, thesis)}"))


def omni_table(experiment: Experiment, documents: dict, x_axis: str) -> str:
    """Final evaluation per approach: errors, velocity along the command per direction, falls, curriculum."""
    columns = ["desired / lateral / yaw MAE", "velocity along command at 0.5 m/s: forward, backward, left, right",
               "same at 0.25 m/s", "falls mean [min-max] (ours / thesis)", "bins learned", "thesis finding"]

    def cells(document, s, thesis):
        f = lambda name: float(np.nanmean(final(document, name)))
        errors = " / ".join(f"{f(f'eval/{k}_mae'):.2f}" for k in ("desired", "lateral", "yaw"))
        speeds = [", ".join(f"{f(f'eval/{d}_{level}/desired_velocity'):.2f}" for d in DIRECTIONS)
                  for level in ("full", "half")]
        bins = (f"{float(np.mean(series(document, 'curriculum/learned_bins')[-1])):.1f}"
                if "curriculum/learned_bins" in document["metrics"] else "-")
        finding = thesis.get("finding", f"desired MAE ~{thesis['desired_mae']}" if "desired_mae" in thesis else "")
        return f"{errors} | {speeds[0]} | {speeds[1]} | {_falls_cell(s, thesis)} | {bins} | {finding}"

    return _per_run(experiment, documents, columns, cells)


RELEASED_MEASURES = {
    "steps_to_0.45": ("steps to 0.45 m/s", lambda x: "never" if x is None else f"{x / 1000:.0f}k"),
    "velocity_last_3k": ("velocity, last 3k steps (m/s)", "{:.2f}".format),
    "falls": ("falls after warm-up", "{:.0f}".format),
}
"""The released code's per-seed measures (analysis.per_seed_released_measures): title and format."""


def _inside(ours: list, theirs: list) -> str:
    """How many of our seeds lie inside the released code's [min, max]; 'never' (None) counts as infinite."""
    value = lambda x: float("inf") if x is None else x
    low, high = min(map(value, theirs)), max(map(value, theirs))
    return f"{sum(low <= value(x) <= high for x in ours)} of {len(ours)}"


def released_code_table(documents: dict, released: dict, profile: str) -> str:
    """Per approach, our seeds beside the released code's on a CPU: steps to 0.45 m/s, velocity of the last 3k
    steps, falls after warm-up; and how many of our seeds fall inside its range."""
    lines = ["| approach | " + " | ".join(f"{title}: released code / ours at {profile} (inside its range)"
                                          for title, _ in RELEASED_MEASURES.values()) + " |",
             "|---" * (len(RELEASED_MEASURES) + 1) + "|"]
    for label, document in documents.items():
        theirs = released["approaches"].get(label)
        if theirs is None:
            continue
        ours = per_seed_released_measures(document)
        words = lambda values, fmt: ", ".join(map(fmt, values))
        cells = [f"{words(theirs[key], fmt)} / {words(ours[key], fmt)} ({_inside(ours[key], theirs[key])})"
                 for key, (_, fmt) in RELEASED_MEASURES.items()]
        lines.append(f"| {display_name(label)} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


TABLES = {"comparison": comparison_table, "max-velocity": max_velocity_table, "omni": omni_table,
          "real": lambda experiment, documents, x_axis: real_world.table(experiment, documents)}
"""Table kind (Experiment.table) -> (experiment, documents, x_axis) -> Markdown."""
