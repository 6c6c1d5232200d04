"""RealtimeConfig: the settings of one on-robot training run, checked before anything moves."""

import dataclasses

from mjx_badger import robot, tasks
from mjx_badger.actions import APPROACHES, is_cpg
from mjx_badger.agents import ALGORITHMS, AgentConfig


@dataclasses.dataclass(frozen=True)
class RealtimeConfig:
    """One on-robot training run."""

    approach: str = "jt-oef"
    algo: str = "crossq"
    task: str = "forward"
    target_velocity: float = 0.25
    """Forward task only: the thesis's office and outdoor runs asked for 0.25 m/s (§5.2)."""
    steps: int = 20_000
    warmup_steps: int = 1_000
    control_hz: float | None = None
    """None: the algorithm's rate (Table 4.3: 40 Hz CrossQ, 20 Hz the others)."""
    episode_seconds: float = 20.0
    planned_contacts: bool = False
    """Leg odometry from the CPG's planned stance legs instead of all four (CPG approaches only)."""
    updates_per_step: float | None = None
    """Learner cap in updates per learning step; None: the algorithm's replay ratio."""
    unthrottled: bool = False
    """The learner runs flat out (benchmarks: the most updates per step the machine sustains)."""
    eval_seconds: float = 10.0
    """Deterministic run after training, as the thesis's evaluation runs (0 skips it)."""
    seed: int = 0
    agent: AgentConfig | None = None
    """Agent settings; None means ALGORITHMS[algo]()."""

    @property
    def agent_config(self) -> AgentConfig:
        return ALGORITHMS[self.algo]() if self.agent is None else self.agent

    @property
    def hz(self) -> float:
        return self.agent_config.control_hz if self.control_hz is None else self.control_hz

    @property
    def utd(self) -> float:
        return self.agent_config.updates_per_step if self.updates_per_step is None else self.updates_per_step

    @property
    def name(self) -> str:
        return f"{self.approach}_{self.algo}_{self.task}"

    def as_dict(self) -> dict:
        """Every setting as plain data, the agent's resolved (the results document's and the checkpoint's)."""
        return dict(dataclasses.asdict(self), agent=dataclasses.asdict(self.agent_config))

    def validate(self) -> None:
        """Raise ValueError naming what is wrong, before anything compiles or moves."""
        if self.approach not in APPROACHES:
            raise ValueError(f"approach {self.approach!r} is not one of {sorted(APPROACHES)}")
        if self.approach == "cpg-rt":
            raise ValueError("cpg-rt averages two PD torques per joint, which only the simulator can do; "
                             "on a robot use cpg-rt-avg (averaged joint angles, what the thesis's robot ran) "
                             "or cpg-rt-sum")
        if self.algo not in ALGORITHMS:
            raise ValueError(f"algorithm {self.algo!r} is not one of {sorted(ALGORITHMS)}")
        if self.task not in tasks.TASKS:
            raise ValueError(f"task {self.task!r} is not one of {sorted(tasks.TASKS)}")
        if self.planned_contacts and not is_cpg(self.approach):
            raise ValueError("planned contacts come from the CPG's phase; the joint-target approaches have none")
        physics_hz = round(1.0 / robot.HB40.physics_dt)
        if not 1.0 <= self.hz <= physics_hz:
            raise ValueError(f"control rate {self.hz} Hz must lie in [1, {physics_hz}] Hz")
        if self.steps < 1 or self.warmup_steps < 0:
            raise ValueError("steps must be positive and warm-up steps not negative")
