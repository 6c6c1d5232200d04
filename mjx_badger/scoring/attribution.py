"""One-factor swaps: which departure of the thesis text from its code, and which part of the reality gap,
moves which claim.

A `Swap` sets one protocol field (or one departure made of two fields, such as the JT gains
and rate) to the other protocol's value, or one field of the on-robot conditions back to the
simulation's (the estimate, the stones, the slope, the friction, the noise, the safety stop),
and names the runs that show its effect and the claims it may move. Each swap is run beside its unswapped baseline at the attribution size
(2 seeds x 10k steps, smaller than `quick`; docs/attribution.md says so), under
`results/attribution/<base protocol>/<swap or baseline>/<experiment>/`.
"""

import dataclasses
import functools
from pathlib import Path

import numpy as np

from mjx_badger.core import launch
from mjx_badger.experiments.registry import EXPERIMENTS, Profile, Run, result_name
from mjx_badger.learning import runner
from mjx_badger.learning.config import TrainConfig, from_results
from mjx_badger.learning.progress import progress_wanted, run_progress
from mjx_badger.protocol import protocols
from mjx_badger.records import analysis, results

PROFILE = Profile(2, 10_000, 1_000, 1_000, 400, "attribution runs: 2 seeds x 10k steps")
REAL_MEASURES = ("eval/desired_velocity", "eval/estimated_desired_velocity", "falls_total_mean")
"""What a condition swap moves: the true and the estimated evaluation speed, and the falls (safety stops)."""


@dataclasses.dataclass(frozen=True)
class Swap:
    name: str
    base: str
    """The protocol the swap starts from."""
    fields: tuple
    """Protocol fields set to the other protocol's value."""
    experiment: str
    approaches: tuple
    measures: tuple
    """Figures compared (analysis.summarize names, or `eval/...` for a final evaluation metric), one per claim kind."""
    claims: tuple
    """Ids of the claims (claims.py) this departure may move."""
    robot: str = "hb40"
    """The robot of the swapped runs (robot/description.py's ROBOTS); the baselines run on the HB40."""
    counted_as: str | None = None
    """For fields that change what is counted, not the run: the summary figure giving the swapped
    value from the baseline runs themselves, so the swap trains nothing."""
    algos: tuple = ("crossq",)
    """The algorithms of the runs (each approach with each)."""
    conditions: str = "sim"
    """The conditions of the runs, baseline and swapped (conditions.py)."""
    condition_changes: tuple = ()
    """((field, value), ...) of the conditions set in the swapped runs: a one-factor swap of the reality gap."""

    @property
    def changes(self) -> tuple:
        return tuple((field, protocols.other_value(field, self.base)) for field in self.fields)

    def describe(self) -> str:
        """The swapped settings, as `field=value, ...`."""
        robot = () if self.robot == "hb40" else (("robot", self.robot),)
        return ", ".join(f"{field}={value!r}" for field, value in robot + self.changes + self.condition_changes)

    def runs(self) -> tuple:
        first = EXPERIMENTS[self.experiment].runs[0]
        return tuple(Run(approach, algo, first.task, first.task_params) for approach in self.approaches
                     for algo in self.algos)


SWAPS = (
    Swap("robot geometry", "thesis-code", (), "forward", ("jt-nf", "jt-oef", "jt-lpf"), ("falls_mean",),
         ("jt-falls",), robot="hb40-v1"),
    Swap("termination rule", "thesis-code", ("termination",), "forward", ("jt-nf", "jt-oef", "jt-lpf"),
         ("falls_mean",), ("jt-falls",)),
    Swap("fall counting", "thesis-code", ("falls_after_warmup",), "forward", ("jt-nf", "jt-oef", "jt-lpf"),
         ("falls_mean",), ("jt-falls",), counted_as="falls_total_mean"),
    Swap("CPG terminates", "thesis-code", ("cpg_terminates",), "forward", ("cpg-d", "cpg-vf", "cpg-rt"),
         ("falls_mean",), ("cpg-never-falls",)),
    # CPG episodes never end under thesis-code, so these read the falls its rule would have counted.
    Swap("CPG action on joint angles, falls", "thesis-code", ("cpg_action",), "forward", ("cpg-d", "cpg-vf"),
         ("would_falls_mean",), ("cpg-never-falls",)),
    Swap("action delay, CPG falls", "thesis-code", ("action_delay",), "forward", ("cpg-vf",),
         ("would_falls_mean",), ("cpg-never-falls",)),
    Swap("low-pass filter", "thesis-code", ("lowpass",), "forward", ("jt-lpf",),
         ("steps_to_target", "gait_hz"), ("jt-convergence", "jt-gait-order")),
    Swap("JT gains and rate", "thesis-code", ("jt_pd_gains", "jt_control_hz"), "forward", ("jt-nf", "jt-oef"),
         ("steps_to_target", "falls_mean", "gait_hz"), ("jt-convergence", "jt-falls", "jt-gait-order")),
    Swap("JT gains and rate at max velocity", "thesis-code", ("jt_pd_gains", "jt_control_hz"), "forward-max",
         ("jt-nf", "jt-oef", "jt-lpf"), ("final_eval_velocity_max", "falls_mean"),
         ("jt-max-velocity", "lpf-falls-most")),
    # The text runs DroQ at its algorithm's 20 Hz, CrossQ at 40; the code runs both JT at 50 (CrossQ's swap is the row above).
    Swap("JT gains and rate, DroQ", "thesis-code", ("jt_pd_gains", "jt_control_hz"), "algo-comparison", ("jt-nf",),
         ("minutes_to_target", "falls_mean"), ("crossq-first", "crossq-falls"), algos=("droq",)),
    Swap("low-pass filter at max velocity", "thesis-code", ("lowpass",), "forward-max", ("jt-lpf",),
         ("final_eval_velocity_max", "falls_mean"), ("jt-max-velocity", "lpf-falls-most")),
    Swap("action delay", "thesis-code", ("action_delay",), "forward", ("jt-nf",),
         ("falls_mean", "steps_to_target"), ("jt-falls", "jt-convergence")),
    Swap("CPG action on joint angles", "thesis-code", ("cpg_action",), "forward-max", ("cpg-d", "cpg-vf"),
         ("final_eval_velocity_max",), ("cpg-vf-max",)),
    Swap("actor log-std and temperature", "thesis-code", ("log_std_bounds", "temperature"), "forward",
         ("jt-nf", "jt-oef"), ("steps_to_target", "falls_mean"), ("jt-convergence", "jt-falls")),
    Swap("CrossQ details", "thesis-code",
         ("crossq_policy_delay", "crossq_renorm_warmup", "crossq_actor_renorm", "target_entropy"), "forward",
         ("jt-nf",), ("steps_to_target",), ("jt-convergence", "crossq-first")),
    Swap("reward forms", "thesis-code", ("rewards",), "omni-random", ("cpg-d", "cpg-vf"),
         ("eval/desired_mae", "eval/yaw_mae"), ("omni-cpg-vf-best",)),
    Swap("curriculum rules", "thesis-code", ("curriculum",), "omni-pdec", ("cpg-vf",), ("eval/desired_mae",),
         ("pdec-error", "pdec-beats-random")),
) + tuple(
    # The reality gap, one part at a time: outdoor runs with one condition set back to the simulation's.
    # (name, changes, claims[, approaches]): the approaches are JT-OEF and CPG-VF unless named.
    Swap(name, "thesis-code", (), "real-outdoor", approaches, REAL_MEASURES, claims,
         conditions="outdoor", condition_changes=changes)
    for name, changes, claims, approaches in ((*swap, ("jt-oef", "cpg-vf"))[:4] for swap in (
        ("true velocity in the loop", (("estimate_in_loop", False),),
         ("real-faster-than-believed", "real-outdoor-jt", "real-outdoor-cpg")),
        # Between the robot's filter (all four feet, reading a few per cent of a walk) and the truth: the same
        # filter with the contacts the motor torques imply (estimators.py, about nine tenths of a walk).
        ("estimate with contacts", (("sensing", "kinematic-kalman-contact"),),
         ("real-faster-than-believed", "real-outdoor-jt", "real-outdoor-cpg")),
        ("flat ground", (("ground.terrain", "flat"),), ("real-outdoor-jt", "real-outdoor-cpg")),
        ("no incline", (("ground.incline_deg", 0.0),), ("real-outdoor-jt", "real-outdoor-cpg")),
        ("simulation friction", (("ground.friction", 1.1),), ("real-outdoor-jt", "real-outdoor-cpg")),
        ("exact sensors", (("sensing", "exact"),), ("real-faster-than-believed", "real-outdoor-cpg")),
        ("no safety stop", (("safety_stop", False),), ("real-excluded-fall", "real-outdoor-cpg")),
        ("stop on the truth", (("stop_on_sensed", False),), ("real-excluded-fall", "real-outdoor-cpg")),
        # The CPG as the simulation ran it, one setting at a time (each on the approaches it touches).
        ("simulation CPG swing", (("cpg_swing_height_m", None),), ("real-outdoor-cpg",), ("cpg-d", "cpg-vf")),
        ("simulation CPG frequency", (("cpg_frequency_hz", None),), ("real-outdoor-cpg",), ("cpg-d",)),
        ("simulation CPG-RT mix", (("robot_cpg_residual", False),), ("real-excluded-fall",), ("cpg-rt",)),
    )))
SWAPS_BY_NAME = {swap.name: swap for swap in SWAPS}


def folder(results_dir: Path, swap: Swap | None, base: str, conditions: str = "sim") -> Path:
    """Where a swap's runs (or, for None, the baseline's under `conditions`) live."""
    label = ("baseline" if conditions == "sim" else f"baseline-{conditions}") if swap is None else swap.name.replace(" ", "-")
    return Path(results_dir) / "attribution" / base / label


def train_config(swap: Swap, run: Run, baseline: bool = False) -> TrainConfig:
    return TrainConfig(approach=run.approach, algo=run.algo, task=run.task, task_params=run.task_params,
                       total_steps=PROFILE.steps, chunk_steps=PROFILE.chunk_steps, warmup_steps=PROFILE.warmup_steps,
                       eval_steps=PROFILE.eval_steps, protocol=swap.base,
                       protocol_changes=() if baseline else swap.changes, robot="hb40" if baseline else swap.robot,
                       conditions=swap.conditions, condition_changes=() if baseline else swap.condition_changes)


def planned(results_dir: Path, swaps: tuple = SWAPS):
    """(swap, run, config, path) of the swaps' runs, each baseline once (shared between swaps)."""
    seen = set()
    for swap in swaps:
        for run in swap.runs():
            for baseline in (True,) if swap.counted_as else (True, False):
                where = folder(results_dir, None if baseline else swap, swap.base, swap.conditions)
                path = where / swap.experiment / result_name(run)
                if path not in seen:
                    seen.add(path)
                    yield swap, run, train_config(swap, run, baseline), path


def _figure(path: Path, swap: Swap, measure: str):
    if not path.exists():
        return None
    document = results.read(path, leave_out_diverged=True)
    if measure.startswith("eval/"):  # an evaluation metric: its final value, mean over seeds
        return float(np.nanmean(analysis.final(document, measure)))
    return analysis.summarize(document, EXPERIMENTS[swap.experiment].target_velocity)[measure]


def _words(value, measure: str) -> str:
    if value is None:
        return {"steps_to_target": "never", "minutes_to_target": "never", "gait_hz": "no gait"}.get(measure, "-")
    if measure == "steps_to_target":
        return f"{value / 1000:.0f}k steps"
    if measure == "minutes_to_target":
        return f"{value:.1f} simulated min"
    if measure in ("falls_mean", "falls_total_mean"):
        return f"{value:.1f} falls"
    if measure == "would_falls_mean":
        return f"{value:.1f} would-be falls"
    if measure == "gait_hz":
        return f"{value:.1f} Hz"
    if measure == "eval/desired_mae":
        return f"{value:.2f} m/s desired MAE"
    if measure == "eval/yaw_mae":
        return f"{value:.2f} rad/s yaw MAE"
    if measure == "eval/estimated_desired_velocity":
        return f"{value:.2f} m/s estimated"
    return f"{value:.2f} m/s"


def _flat(value, prefix: str = "") -> dict:
    """A nested settings object as {'a.b': leaf}."""
    if dataclasses.is_dataclass(value):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    if not isinstance(value, dict):
        return {prefix: value}
    return {k: v for key, inner in value.items() for k, v in _flat(inner, f"{prefix}{key}.").items()}


def baseline_differs(swap: Swap, base: dict, swapped: dict) -> list[str]:
    """The conditions in which a swapped run differs from its baseline's beyond the swap itself: the fields a rule
    changed after one of them ran (such a row compares more than one condition, so it is not scored)."""
    base_config, swapped_config = from_results(base), from_results(swapped)
    expected = dataclasses.replace(base_config, condition_changes=base_config.condition_changes + swap.condition_changes)
    want, got = (_flat(config.env_config.conditions) for config in (expected, swapped_config))
    return sorted(k.rstrip(".") for k in want.keys() | got.keys() if want.get(k) != got.get(k))


def table(results_dir: Path, conditions: bool = False) -> str:
    """Markdown 'departure -> claims it moves' of the complete attribution results: the protocol swaps
    (docs/attribution.md), or with `conditions` the reality gap's swaps (docs/real-world.md)."""
    head = ("| condition set back to the simulation's | run | outdoor baseline | swapped | findings it can move |"
            if conditions else
            "| departure (fields set to the other protocol's value) | run | thesis-code baseline | swapped "
            "| claims it can move |")
    lines = [head, "|---|---|---|---|---|"]
    for swap in SWAPS:
        if bool(swap.condition_changes) != conditions:
            continue
        for run in swap.runs():
            base_path = folder(results_dir, None, swap.base, swap.conditions) / swap.experiment / result_name(run)
            swapped_path = base_path if swap.counted_as else (
                folder(results_dir, swap, swap.base) / swap.experiment / result_name(run))
            if not swapped_path.exists() or not (results.read_or_skip(swapped_path) or {}).get("complete"):
                continue  # not run yet, or still running
            differs = baseline_differs(swap, results.read(base_path), results.read(swapped_path)) \
                if swap.condition_changes else []  # the conditions' fields are the ones added since runs were made
            if differs:
                lines.append(f"| {swap.name} ({swap.describe()}) | {swap.experiment} {run.approach} | ran beside another "
                             f"baseline ({', '.join(differs)} differ): rerun it | | {', '.join(swap.claims)} |")
                continue
            swapped_measures = (swap.counted_as,) if swap.counted_as else swap.measures
            cells = ["; ".join(_words(_figure(path, swap, measure), measure) for measure in measures)
                     for path, measures in ((base_path, swap.measures), (swapped_path, swapped_measures))]
            algo = "" if run.algo == "crossq" else f" {run.algo}"
            lines.append(f"| {swap.name} ({swap.describe()}) | {swap.experiment} {run.approach}{algo} "
                         f"| {cells[0]} | {cells[1]} | {', '.join(swap.claims)} |")
    return "\n".join(lines) + "\n"


def run(results_dir: Path, only: tuple | None = None, launcher=None) -> tuple[str, str]:
    """Train every planned run of the swaps (those named in `only`, else all) that has no complete results yet, each
    baseline once, where `launcher` says (cli.common.Launch; None: here, one after another); returns the tables of
    the protocol swaps and of the conditions' swaps."""
    swaps = tuple(swap for swap in SWAPS if only is None or swap.name in only)
    seeds = list(range(PROFILE.seeds))
    progress = progress_wanted() and (launcher is None or launcher.here)  # one bar at a time
    jobs = []
    for _, _, config, path in planned(results_dir, swaps):
        if path.exists() and (results.read_or_skip(path) or {}).get("complete"):
            print(f"skip {path}: complete")
            continue
        name = str(path.relative_to(Path(results_dir) / "attribution"))  # with its folder: runs share file names
        jobs.append(launch.Job(name, runner.run, (config, seeds, path, progress, True, True, ""),
                               functools.partial(run_progress, path, config.num_chunks * config.chunk_steps)))
    if launcher is None:
        launch.run(jobs)
    else:
        launcher.run(jobs, results_dir)
    return table(results_dir), table(results_dir, conditions=True)
