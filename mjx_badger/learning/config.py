"""TrainConfig: one training run, what it trains (RunSpec) and for how long; and the run a results file holds."""

import dataclasses
import json
from typing import Annotated

import tyro

from mjx_badger.agents.config import AgentConfig
from mjx_badger.control import actions
from mjx_badger.core import validation
from mjx_badger.learning.spec import RunSpec
from mjx_badger.protocol import conditions as on_robot
from mjx_badger.records import results
from mjx_badger.sim.env import EnvConfig

MAX_EVAL_STEPS = 100_000
"""Steps of each evaluation run (the thesis's: 400); longer ones only make every chunk slower."""


MAX_GAIT_SECONDS = 60.0


@dataclasses.dataclass(frozen=True)
class TrainConfig(RunSpec):
    """One training run: what to train (RunSpec) and for how long. Shapes follow from it."""

    total_steps: Annotated[int, tyro.conf.arg(aliases=("--steps",))] = 50_000
    """Environment steps per seed, warm-up included (thesis: 50k)."""
    chunk_steps: int = 1_000
    """Steps per compiled chunk: one progress tick, one results row, one evaluation."""
    warmup_steps: int = 1_000
    """Uniform random actions before learning starts (thesis §5.1: 1000)."""
    eval_steps: int = 400
    """Length of each deterministic evaluation run after every chunk."""
    num_envs: int = 1
    """Environments per seed, stepped together, feeding one learner and its replay (FastSAC's regime: hundreds);
    each step of the run is one step of every one of them. The thesis ran one."""
    gait_seconds: float = 4.0
    """Simulated seconds of the deterministic run after training; its second half is kept as the gait record."""
    env: tyro.conf.Suppress[EnvConfig | None] = None
    """Environment settings; None means the protocol's, at its rate for this approach and algorithm."""
    agent: tyro.conf.Suppress[AgentConfig | None] = None
    """Agent settings; None means the protocol's configuration of `algo` with `algo_params`."""

    def validate(self) -> None:
        """Raise ValueError naming the valid choices for any unknown name, before anything compiles."""
        super().validate()
        for name in ("total_steps", "chunk_steps", "eval_steps"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be a positive number of steps, not {getattr(self, name)}")
        if self.warmup_steps < 0:
            raise ValueError(f"warmup_steps must not be negative, not {self.warmup_steps}")
        validation.integer("num_envs", self.num_envs, 1, 4096)
        if self.chunk_steps > self.total_steps:
            raise ValueError(f"chunk_steps ({self.chunk_steps}) must not exceed total_steps ({self.total_steps})")
        if self.warmup_steps >= self.total_steps:
            raise ValueError(f"warm-up ({self.warmup_steps} steps) must be shorter than the run ({self.total_steps})")
        # The step counter, the replay index and the agent's update index (steps x updates per step) are int32.
        utd = self.agent_config.updates_per_step
        limit = validation.INT32_MAX // utd
        validation.integer("total_steps", self.total_steps, 1, limit,
                           f"int32 step counters at {utd} update{'s' if utd > 1 else ''} per step")
        if self.num_chunks * self.chunk_steps > limit:
            raise ValueError(f"chunk_steps ({self.chunk_steps}) rounds the run up to {self.num_chunks * self.chunk_steps}"
                             f" steps, past the int32 step counters' {limit}: choose one that divides total_steps")
        validation.integer("eval_steps", self.eval_steps, 1, MAX_EVAL_STEPS)
        validation.number("gait_seconds", self.gait_seconds, 0.0, MAX_GAIT_SECONDS, low_open=True,
                          why="the gait record is kept at the physics rate in the results file")

    @property
    def agent_config(self) -> AgentConfig:
        return super().agent_config if self.agent is None else self.agent

    @property
    def env_config(self) -> EnvConfig:
        if self.env is not None:
            return self.env
        spec = self.protocol_spec
        on_robot = self.conditions_spec if (self.conditions, self.condition_changes) != ("sim", ()) else None
        return EnvConfig(control_hz=spec.control_hz(actions.is_cpg(self.approach), self.algo), protocol=spec,
                         conditions=on_robot)

    @property
    def num_chunks(self) -> int:
        return -(-self.total_steps // self.chunk_steps)


def from_results(document: dict) -> TrainConfig:
    """The TrainConfig a results document was written by; ValueError if it cannot be rebuilt exactly."""
    as_tuple = lambda v: tuple(as_tuple(x) for x in v) if isinstance(v, list) else v
    stored = _as_written_then(document["config"])
    fields = {f.name for f in dataclasses.fields(TrainConfig)} - {"env", "agent"}
    try:
        config = TrainConfig(**{k: as_tuple(v) for k, v in stored.items() if k in fields})
    except (TypeError, KeyError) as error:  # a hand-edited value of the wrong kind
        raise ValueError(f"the results' configuration cannot be rebuilt: {error}") from None
    if json.loads(json.dumps(results.config_dict(config))) != {**json.loads(json.dumps(results.config_dict(config))), **stored}:
        raise ValueError("the results' env or agent settings differ from their protocol's; cannot rebuild the run")
    return config


def _as_written_then(stored: dict) -> dict:
    """`stored` with each condition field added since it was written (conditions.ADDED_LATER) set, in its conditions
    and as a condition change where it differs from the named conditions' value today: the run as it ran."""
    written = (stored.get("env") or {}).get("conditions")
    if written is None:
        return stored
    kalman = (written.get("sensing") or {}).get("kalman")
    missing = {}
    for key, value in on_robot.ADDED_LATER.items():
        group, _, field = key.rpartition(".")
        holder = kalman if group == "kalman" else written
        if holder is not None and field not in holder:
            missing[key] = value
    if not missing:
        return stored
    named = on_robot.get(stored.get("conditions", "sim"), ())
    today = lambda k: getattr(named.sensing.kalman, k.split(".")[1]) if k.startswith("kalman.") else getattr(named, k)
    changes = [[k, v] for k, v in missing.items() if today(k) != v]
    conditions = {**written, **{k: v for k, v in missing.items() if not k.startswith("kalman.")}}
    if kalman is not None:
        conditions["sensing"] = {**written["sensing"], "kalman": {
            **kalman, **{k.split(".")[1]: v for k, v in missing.items() if k.startswith("kalman.")}}}
    return {**stored, "env": {**stored["env"], "conditions": conditions},
            "condition_changes": [*stored.get("condition_changes", []), *changes]}
