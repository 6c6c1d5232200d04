"""How long the runs left will take, from what the runs done so far cost on this machine.

A run's training seconds scale with its work. Per seed, every step is one env step, every learning
step adds its gradient updates, and every chunk ends with one deterministic evaluation run per
evaluation command of the task (one for the forward tasks, eight for the omni ones). The rest of a
run (compiling, the gait record, saving) costs about the same for every run of a task, whatever its
length, and a task with more evaluation commands compiles a larger program. Both are measured on the runs done: there is no ETA before the first run ends, and a run
that copies an earlier one of the same configuration costs nothing.
"""

import json
import statistics
from pathlib import Path
from typing import NamedTuple

from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, PROFILES

UPDATE_COST = 2.2
"""One gradient update costs about this many env steps of the same seeds (quick runs on a 2-core CPU:
a forward CrossQ step with its evaluation share 8.7 ms per seed, an omni one 14-17 ms, SAC-UTD20 97 ms)."""
AGENT_UPDATE_COST = {"xqc": 18.4, "simbav2": 48.8, "bro": 10.7, "fastsac": 6.4}
"""A newer agent's update over a thesis agent's, their larger networks (benchmarks/results/bench_agents.json:
SAC 126.8 updates/s at batch 256; XQC 6.9, SimbaV2 2.6, BRO 11.8, FastSAC 19.9 on the same 2-core CPU)."""
OTHER_COST_PER_COMMAND = 0.07
"""Each evaluation command beyond the first adds this share to a run's compile (quick runs on a 2-core CPU:
30-48 s for the forward tasks' one command, 45-76 s for the omni tasks' eight)."""


class Planned(NamedTuple):
    """A run as the ETA sees it before it starts."""

    work: float
    """Env-step equivalents over all its seeds (module docstring)."""
    task: str
    other_weight: float = 1.0
    """Its compile and recording relative to a run with one evaluation command."""
    copy: bool = False
    """A copy of an earlier run of the same configuration and seeds: nothing to train or compile."""


class Done(NamedTuple):
    """What a finished run cost."""

    planned: Planned
    train_s: float
    """Seconds in its training chunks (a results file's wall_clock.run_s)."""
    other_s: float
    """Every other second of the run: compiling, recording, saving."""


def planned(config, seeds: int, copy: bool = False) -> Planned:
    """The ETA's view of the TrainConfig `config` run for `seeds` seeds."""
    commands = len(config.make_task().eval_commands)
    learning_steps = config.total_steps - config.warmup_steps
    updates = UPDATE_COST * AGENT_UPDATE_COST.get(config.algo, 1.0) * config.agent_config.updates_per_step * learning_steps
    work = seeds * (config.total_steps + updates + config.num_chunks * commands * config.eval_steps)
    return Planned(work, config.task, 1.0 + OTHER_COST_PER_COMMAND * (commands - 1), copy)


def seconds_left(remaining: list[Planned], done: list[Done]) -> float | None:
    """Seconds the `remaining` runs will take at the rates of the `done` ones; None before any was trained."""
    trained = [d for d in done if not d.planned.copy]
    if not trained:
        return None
    per_work = sum(d.train_s for d in trained) / sum(d.planned.work for d in trained)
    per_weight = sum(d.other_s for d in trained) / sum(d.planned.other_weight for d in trained)

    def other(run: Planned) -> float:
        same_task = [d.other_s for d in trained if d.planned.task == run.task]
        return statistics.mean(same_task) if same_task else run.other_weight * per_weight

    return sum(0.0 if run.copy else run.work * per_work + other(run) for run in remaining)


def replay(runs: list[tuple[Planned, tuple[float, float]]]) -> list[tuple[float, float]]:
    """(ETA, seconds actually left) after each run but the last, for runs that cost (train_s, other_s) each."""
    cost = [0.0 if plan.copy else train_s + other_s for plan, (train_s, other_s) in runs]
    done = [Done(plan, *((0.0, 0.0) if plan.copy else spent)) for plan, spent in runs]
    return [(seconds_left([plan for plan, _ in runs[k:]], done[:k]), sum(cost[k:])) for k in range(1, len(runs))]


def profile_plan(profile: str) -> list[tuple[str, Planned, int]]:
    """(experiment/file, planned, gradient updates) of every run `reproduce --profile` makes, in its order;
    a run repeating an earlier one's configuration is a copy."""
    plans, seen, seeds = [], [], PROFILES[profile].seeds
    for name in GROUPS["simulation"]:
        experiment = EXPERIMENTS[name]
        for run in experiment.runs:
            config = experiment.train_config(run, profile)
            updates = config.total_steps * config.agent_config.updates_per_step * seeds
            plans.append((f"{name}/{experiment.result_name(run)}", planned(config, seeds, config in seen), updates))
            seen.append(config)
    return plans


def measured_costs(profile: str, root: Path) -> dict:
    """{experiment/file: (training s, compile s)} of a profile's runs as they went on the machine this project is
    developed on, in the repository at `root`: quick's committed results, a fresh clone's smoke profile."""
    if profile == "smoke":
        runs = json.loads((root / "tools" / "results" / "smoke_profile_time.json").read_text())["runs"]
        return {name: (run["run_s"], run["compile_s"]) for name, run in runs.items()}
    cost = {}
    for path in (root / "figures" / "data" / profile / "thesis-code").glob("*/*.json"):
        clock = json.loads(path.read_text())["wall_clock"]
        cost[f"{path.parent.name}/{path.name}"] = (clock["run_s"], clock["compile_s"])
    return cost
