"""A training run's saved policy, one seed of it, run again under one command: checked, then loaded with its env.

`evaluate` and `render` (and a robot's computer) run it on native MuJoCo with NumPy; the env is the
run's own, rebuilt from its results file, with one episode as long as the evaluation.
"""

import dataclasses
from pathlib import Path

from mjx_badger.core.validation import INT32_MAX, integer, number
from mjx_badger.learning.config import from_results
from mjx_badger.protocol.conditions import CONDITIONS
from mjx_badger.records import policy, results
from mjx_badger.sim import native

MAX_COMMAND = 10.0
"""The largest |VX|, |VY| or |YAW| a command may ask for (m/s, rad/s)."""


def check(path: Path, seed: int | None, seconds: float, max_seconds: float, command: str | None,
          conditions: str | None) -> None:
    """ValueError naming what makes the saved run unusable: the file, its policy, the seed, the seconds, the command
    ('VX,VY,YAW') or the conditions; nothing is compiled."""
    number("--seconds", seconds, 0.0, max_seconds, low_open=True)
    if conditions is not None and conditions not in CONDITIONS:
        raise ValueError(f"--conditions {conditions!r}: choose from {', '.join(CONDITIONS)}")
    if seed is not None:
        integer("--seed", seed, 0, INT32_MAX)
    if not path.is_file():
        raise ValueError(f"no results file {str(path)!r}")
    document = results.read(path)
    if "policy" not in document:
        raise ValueError(f"{path} has no saved policy (complete runs since policies are saved have one)")
    saved = path.parent / document["policy"]
    if not saved.is_file():
        raise ValueError(f"{path}: its saved policy {str(saved)!r} is missing (a committed reference "
                         "result keeps only its best seed's, where one was attached)")
    seed = policy.load(saved, seed).seed  # the seed exists (default: the file's first), the file is whole
    from_results(document)  # the run can be rebuilt
    if seed in results.diverged(document):
        raise ValueError(f"seed {seed} of {path.name} diverged at step "
                         f"{results.diverged(document)[seed]}; its policy is frozen from before, choose another")
    if command is not None:
        parse_command(command)


def parse_command(command: str) -> list[float]:
    """[VX, VY, YAW] from 'VX,VY,YAW'; ValueError for anything else or a value past MAX_COMMAND."""
    try:
        vx, vy, yaw = [float(x) for x in command.split(",")]
    except ValueError:
        raise ValueError(f"--command takes VX,VY,YAW, three numbers; got {command!r}") from None
    for name, value in (("VX", vx), ("VY", vy), ("YAW", yaw)):
        number(f"--command {name}", value, -MAX_COMMAND, MAX_COMMAND)
    return [vx, vy, yaw]


def load(path: Path, seed: int | None, seconds: float, command: str | None = None, conditions: str | None = None):
    """(env, actor, command) of the run: its env with one long episode, the seed's NumPy actor, the command
    (default: the task's first evaluation command); under other `conditions` the whole set of them, none of the
    run's own changes."""
    document = results.read(path)
    actor = policy.load(path.parent / document["policy"], seed)
    config = from_results(document)
    if conditions is not None:
        config = dataclasses.replace(config, conditions=conditions, condition_changes=())
    env = native.evaluation_env(config, seconds)
    chosen = parse_command(command) if command else list(next(iter(env.task.eval_commands.values())))
    return env, actor, chosen


def evaluate(path: Path, seed: int | None, seconds: float, command: str | None = None, conditions: str | None = None,
             engine: str = "native") -> dict:
    """The saved policy's report on `engine` ('native' MuJoCo, or 'mjx', the training env): velocity from the trunk's
    positions, falls, gait frequency, and which seed, engine and conditions it ran under."""
    env, actor, chosen = load(path, seed, seconds, command, conditions)
    run = native.run_native if engine == "native" else native.run_mjx
    return dict(run(env, actor, chosen, seconds), engine=engine, seed=actor.seed, conditions=env.conditions.name)
