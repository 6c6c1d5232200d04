"""The two protocols: the thesis as its released code ran it, and the thesis as its text reads.

A protocol is one frozen object; every place the two differ is a named field whose docstring
cites its source (docs/thesis-code.md sections for `thesis-code`, the thesis text for
`thesis-text`). The environment, the action pipelines, the tasks, the agents and the trainer
read these fields and nothing else, so a one-factor swap (one field set to the other
protocol's value) is `protocol.replace(field=value)`.
"""

import dataclasses

from mjx_badger.agents.config import ALGORITHMS, AgentConfig


@dataclasses.dataclass(frozen=True)
class Protocol:
    """Every choice on which the released code and the thesis text differ."""

    name: str
    jt_pd_gains: tuple
    """(Kp, Kd) of the joint-target approaches. Code: PDControl defaults 25 / 1, the scripts' 60 / 3
    never reach it (docs/thesis-code.md §2 'JT bug'). Text: silent; the scripts' 60 / 3."""
    cpg_pd_gains: tuple
    """(Kp, Kd) of the CPG approaches: 60 / 3 in both (docs/thesis-code.md §2; scripts)."""
    jt_control_hz: float | None
    """JT control rate. Code: 50 Hz, the PD default (§2). Text: None, the algorithm's rate (Table 4.3: CrossQ 40, others 20)."""
    cpg_control_hz: float | None
    """CPG control rate. Code: 40 Hz (§2). Text: None, the algorithm's rate."""
    action_delay: bool
    """Table 5.1's |0.03 + N(0, 0.05^2)| s delay. Code: absent (§2). Text: applied."""
    episode_seconds: float
    """Code: 10 s, the default no script overrides (§6). Text: 20 s (§5.1.1)."""
    termination: str
    """'thesis-code': |roll| or |pitch| >= 30 deg, |angular velocity| > 4 rad/s, trunk contact, or
    > 1500 W for 3 steps (§6). 'tilt-height': our reading of the text, tilt > 0.8 rad or trunk below 0.15 m."""
    cpg_terminates: bool
    """Code: False, `terminated = False` is hard-coded in the CPG env (§6); would-be falls are still
    counted as `train/would_falls`. Text: True (§5.1.2 reports falls as if they could happen)."""
    falls_after_warmup: bool
    """Code: True, falls are counted only once learning has started (§6, crossq.py). Text: False, every fall."""
    joint_velocity_clip: float | None
    """Code: joint velocities clipped to +-25 rad/s after every physics step (§1). Text: None."""
    lowpass: str
    """JT-LPF filter. Code: 'butterworth', 2nd order, 4 Hz designed at 40 Hz (§3). Text: 'first-order' at 0.4 Hz (Table 4.4)."""
    one_euro_first_output_is_input: bool
    """Code: True, the OneEuroFilter package returns its first input (§3). Text: False, the filter starts at rest at the nominal pose."""
    cpg_action: str
    """Code: 'joint-offsets', the action is added to the joint angles of the code's own IK, around
    its stance (feet 0.30 m below the hips; §2). Text: 'foot-offsets', added to foot positions
    before IK, around the nominal pose (§4.3)."""
    cpg_residual: str
    """CPG-RT. Code: 'average-d-bug', one PD on the average of the two targets, with the offsets as a
    velocity target (§2). Text: 'torque-average', two PD controllers, each clipped, averaged (§4.3)."""
    cpg_heights_before_advance: bool
    """Code: True, swing heights are read before the phase advances, so the first step is (0, 0) (beat.py).
    Text: False, the phase advances first."""
    observation: str
    """Code: 'thesis-code' scaling (q / 3.14, qdot / 25, action / 3.14, omega / 10), acceleration without
    gravity, CPG block = the two swing heights (§4). Text: 'thesis-text', Table 4.1 with our scales."""
    rewards: str
    """Code: 'thesis-code' forms: track_x with |yaw|, max_x unclipped, track_xy with 0.5 |yaw error|
    and no energy term (§5). Text: 'thesis-text', Tables 4.5 and 4.6 as this suite reads them (docs/readings.md)."""
    curriculum: str
    """PDEC rules (`curriculum.RULES`). Code: 'thesis-code', the released curriculum.py: the halves grow
    until they meet, 50/50 halves until each has a bin, 0.25 m/s until complete, learned-region
    speeds U(0.1, cap) or 0, a rolling 400-step mean (§7). Text: 'thesis-text', §4.5.1 as we read it."""
    truncation_bootstraps_from: str
    """Code: 'next-episode', CrossQ's replay's next state at a time-out is the next episode's first
    observation (Q/replay_buffer.py; a bug, reproduced; RL-X's SAC, SAC-UTD and DroQ store the final
    observation, sac/*/sac.py, droq.py). Text: 'final-observation'."""
    crossq_policy_delay: int
    """Code: 1, the actor updates every step (§8). Text: 3, the CrossQ paper's default."""
    crossq_renorm_warmup: int
    """Batch-renorm warm-up in updates. Code: 1000 (§8). Text: 100000, the CrossQ paper's default."""
    crossq_actor_renorm: bool
    """Code: True, batch renorm in the actor too (§8). Text: False, the CrossQ paper's actor."""
    target_entropy: float | None
    """Code: -6 for every action space (the scripts, §8). Text: None, -|A| / 2 (Table 4.3)."""
    utd_actor_updates: int | None
    """Actor updates per env step of the many-updates algorithms. Code: 1, RL-X's SAC-UTD and DroQ
    update the actor once per step (§8). Text: None, once per critic update."""
    log_std_bounds: str
    """Code: 'clip', every RL-X policy clips its log-std to [-20, 2] (Q/policy.py, sac/*/policy.py), so an
    untrained actor explores with std ~1. Text: 'squash', smoothly into [-10, 2] (the text is silent)."""
    temperature: str
    """Code: 'thesis-code', loss alpha (H - target) with optax's default Adam (b1 0.9) for alpha
    (Q/crossq.py, sac/utd/sac.py). Text: 'thesis-text', log alpha (H - target), the algorithm's Adam (§2.3)."""

    def replace(self, **changes) -> "Protocol":
        unknown = set(changes) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise ValueError(f"unknown protocol field(s) {sorted(unknown)}; fields: {', '.join(FIELDS)}")
        return dataclasses.replace(self, **changes)

    def pd_gains(self, approach_is_cpg: bool) -> tuple:
        """(Kp, Kd) of an approach."""
        return self.cpg_pd_gains if approach_is_cpg else self.jt_pd_gains

    def control_hz(self, approach_is_cpg: bool, algo: str) -> float:
        """Control rate of an approach trained by `algo`."""
        fixed = self.cpg_control_hz if approach_is_cpg else self.jt_control_hz
        return fixed if fixed is not None else ALGORITHMS[algo]().control_hz

    def bootstraps_from_next_episode(self, algo: str) -> bool:
        """Whether a time-out's next state is the next episode's start (the released CrossQ only: any registered
        algorithm of CrossQ's kind, AgentConfig.is_crossq)."""
        return self.truncation_bootstraps_from == "next-episode" and ALGORITHMS[algo]().is_crossq

    def agent_config(self, algo: str) -> AgentConfig:
        """The algorithm's configuration under this protocol; the crossq_* settings and the target entropy go to
        every algorithm of CrossQ's kind (AgentConfig.is_crossq), not to a name."""
        config = ALGORITHMS[algo]()
        if not config.from_thesis:
            return config  # what the protocols settle is how the thesis ran its four; a newer agent runs as published
        crossq = config.is_crossq
        config = config.replace(log_std_clip=self.log_std_bounds == "clip")
        if self.temperature == "thesis-code":
            config = config.replace(alpha_loss_scaled=True, alpha_adam_b1=0.9)
        if self.target_entropy is not None and crossq:
            config = config.replace(target_entropy=self.target_entropy)
        if crossq:
            return config.replace(policy_delay=self.crossq_policy_delay, renorm_warmup_steps=self.crossq_renorm_warmup,
                                  actor_batch_renorm=self.crossq_actor_renorm)
        if self.utd_actor_updates is not None and config.updates_per_step > 1:
            config = config.replace(actor_updates_per_step=self.utd_actor_updates)
        return config


THESIS_CODE = Protocol(
    name="thesis-code",
    jt_pd_gains=(25.0, 1.0),
    cpg_pd_gains=(60.0, 3.0),
    jt_control_hz=50.0,
    cpg_control_hz=40.0,
    action_delay=False,
    episode_seconds=10.0,
    termination="thesis-code",
    cpg_terminates=False,
    falls_after_warmup=True,
    joint_velocity_clip=25.0,
    lowpass="butterworth",
    one_euro_first_output_is_input=True,
    cpg_action="joint-offsets",
    cpg_residual="average-d-bug",
    cpg_heights_before_advance=True,
    observation="thesis-code",
    rewards="thesis-code",
    curriculum="thesis-code",
    truncation_bootstraps_from="next-episode",
    crossq_policy_delay=1,
    crossq_renorm_warmup=1000,
    crossq_actor_renorm=True,
    target_entropy=-6.0,
    utd_actor_updates=1,
    log_std_bounds="clip",
    temperature="thesis-code",
)

THESIS_TEXT = Protocol(
    name="thesis-text",
    jt_pd_gains=(60.0, 3.0),
    cpg_pd_gains=(60.0, 3.0),
    jt_control_hz=None,
    cpg_control_hz=None,
    action_delay=True,
    episode_seconds=20.0,
    termination="tilt-height",
    cpg_terminates=True,
    falls_after_warmup=False,
    joint_velocity_clip=None,
    lowpass="first-order",
    one_euro_first_output_is_input=False,
    cpg_action="foot-offsets",
    cpg_residual="torque-average",
    cpg_heights_before_advance=False,
    observation="thesis-text",
    rewards="thesis-text",
    curriculum="thesis-text",
    truncation_bootstraps_from="final-observation",
    crossq_policy_delay=3,
    crossq_renorm_warmup=100_000,
    crossq_actor_renorm=False,
    target_entropy=None,
    utd_actor_updates=None,
    log_std_bounds="squash",
    temperature="thesis-text",
)

PROTOCOLS = {p.name: p for p in (THESIS_CODE, THESIS_TEXT)}
FIELDS = tuple(f.name for f in dataclasses.fields(Protocol) if f.name != "name")


def get(name: str, changes: tuple = ()) -> Protocol:
    """The protocol `name` with one-factor `changes` ((field, value) pairs) applied."""
    if name not in PROTOCOLS:
        raise ValueError(f"unknown protocol {name!r}; choose from {', '.join(PROTOCOLS)}")
    return PROTOCOLS[name].replace(**dict(changes))


def other_value(field: str, name: str):
    """The value `field` has in the protocol other than `name`: what a one-factor swap sets."""
    other = THESIS_TEXT if name == THESIS_CODE.name else THESIS_CODE
    return getattr(other, field)
