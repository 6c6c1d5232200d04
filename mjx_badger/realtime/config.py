"""RealtimeConfig: the settings of one on-robot training run, checked before anything moves."""

import dataclasses

import tyro

from mjx_badger.agents.config import AgentConfig
from mjx_badger.control.actions import is_cpg
from mjx_badger.core import validation
from mjx_badger.learning.spec import RunSpec
from mjx_badger.realtime import pretrained
from mjx_badger.tasks import locomotion as tasks

MAX_SPEED = 5.0
"""m/s: ten times the thesis's commands, beyond any the HB40 can walk."""
MAX_SECONDS = 3600.0
"""An episode or evaluation of at most an hour."""


@dataclasses.dataclass(frozen=True)
class RealtimeConfig(RunSpec):
    """One on-robot training run: what it trains (RunSpec, under thesis-text) and how the loop runs."""

    protocol: str = "thesis-text"
    """The on-robot loop observes as a robot can (IMU with gravity, gyro differences): thesis-text only."""
    target_velocity: float = 0.25
    """Forward task only: the thesis's office and outdoor runs asked for 0.25 m/s (§5.2)."""
    steps: int = 20_000
    """Control steps, warm-up included."""
    warmup_steps: int = 1_000
    """Steps before learning starts: uniform random actions, or with `init_from` the pretrained policy's own."""
    control_hz: float | None = None
    """None: the algorithm's rate (Table 4.3: 40 Hz CrossQ, 20 Hz the others)."""
    episode_seconds: float = 20.0
    """Longest episode before a time-out (the thesis's 20 s)."""
    planned_contacts: bool = False
    """Leg odometry from the CPG's planned stance legs instead of all four (CPG approaches only)."""
    updates_per_step: float | None = None
    """Learner cap in updates per learning step; None: the algorithm's replay ratio."""
    unthrottled: bool = False
    """The learner runs flat out (benchmarks: the most updates per step the machine sustains)."""
    eval_seconds: float = 10.0
    """Deterministic run after training, as the thesis's evaluation runs (0 skips it)."""
    seed: int = 0
    """Seed of the agent, the commands and the simulated robot's noise."""
    init_from: str | None = None
    """A training run's results file (thesis-text, same approach, algorithm and networks) whose saved agent
    the loop starts from, learning on from it; None: a fresh agent."""
    init_seed: int = 0
    """Which seed of `init_from`."""
    agent: tyro.conf.Suppress[AgentConfig | None] = None
    """Agent settings; None means the protocol's configuration of `algo` with `algo_params`."""

    @property
    def agent_config(self) -> AgentConfig:
        return super().agent_config if self.agent is None else self.agent

    @property
    def hz(self) -> float:
        return self.agent_config.control_hz if self.control_hz is None else self.control_hz

    @property
    def utd(self) -> float:
        return self.agent_config.updates_per_step if self.updates_per_step is None else self.updates_per_step

    def as_dict(self) -> dict:
        """Every setting as plain data, the agent's resolved (the results document's and the checkpoint's)."""
        return dict(dataclasses.asdict(self), agent=dataclasses.asdict(self.agent_config))

    def validate(self) -> None:
        """Raise ValueError naming what is wrong, before anything compiles or moves."""
        super().validate()
        if self.protocol != "thesis-text":
            raise ValueError(f"the on-robot loop runs the thesis-text protocol (a robot's IMU), not {self.protocol!r}")
        if self.approach == "cpg-rt":
            raise ValueError("cpg-rt averages two PD torques per joint, which only the simulator can do; "
                             "on a robot use cpg-rt-avg (averaged joint angles, what the thesis's robot ran) "
                             "or cpg-rt-sum")
        if self.planned_contacts and not is_cpg(self.approach):
            raise ValueError("planned contacts come from the CPG's phase; the joint-target approaches have none")
        physics_hz = round(1.0 / self.robot_spec.physics_dt)
        if not 1.0 <= self.hz <= physics_hz:
            raise ValueError(f"control rate {self.hz} Hz must lie in [1, {physics_hz}] Hz")
        if self.steps < 1 or self.warmup_steps < 0:
            raise ValueError("steps must be positive and warm-up steps not negative")
        validation.integer("steps", self.steps, 1, validation.INT32_MAX)
        validation.number("target_velocity", self.target_velocity, -MAX_SPEED, MAX_SPEED)
        validation.number("episode_seconds", self.episode_seconds, 0.0, MAX_SECONDS, low_open=True)
        validation.number("eval_seconds", self.eval_seconds, 0.0, MAX_SECONDS)
        if self.updates_per_step is not None:
            validation.number("updates_per_step", self.updates_per_step, 0.0, 1000.0, low_open=True)
        for name in ("seed", "init_seed"):
            validation.integer(name, getattr(self, name), 0, validation.INT32_MAX)
        if self.warmup_steps >= self.steps:
            raise ValueError(f"warmup_steps ({self.warmup_steps}) must be smaller than steps ({self.steps})")
        if self.init_from is not None:
            pretrained.check(self)

    def make_task(self) -> tasks.Task:
        """The task under the protocol, the forward one at `target_velocity`."""
        params = dict(self.task_params)
        if self.task == "forward":
            params.setdefault("target_velocity", self.target_velocity)
        protocol = self.protocol_spec
        return tasks.make_task(self.task, protocol.rewards, protocol.curriculum, **params)
