"""Action pipelines: from the policy's action in [-1, 1]^A to the motors' PD targets.

An action space is `init() -> state`, `step(state, action) -> (state, ctrl)` and
`observe(state) -> (predicted (12,), extra (k,))`, the approach's own observation blocks
of thesis Table 4.1. `ctrl` holds one PD target per actuator: 12, or 24 for the
torque-averaging residual CPG, whose model drives every joint with two half-strength PD
controllers (robot.load_model(split_pd=True)). The approaches of Table 5.2 are registered
by name in `APPROACHES`.
"""

from typing import Callable, NamedTuple

import jax.numpy as jnp
import numpy as np

from mjx_badger import cpg, filters, kinematics, robot


class ActionSpace(NamedTuple):
    """A named action pipeline with its action, control and extra-observation sizes."""

    name: str
    size: int
    init: Callable
    step: Callable
    observe: Callable
    predicted_name: str
    """What the 12-value predicted block holds: 'joint_angle' or 'feet_position'."""
    extra_size: int = 0
    split_pd: bool = False
    """Two PD controllers per joint whose torques are averaged (ctrl has 24 targets)."""

    @property
    def ctrl_size(self) -> int:
        return 2 * robot.NUM_JOINTS if self.split_pd else robot.NUM_JOINTS

    def rest_ctrl(self):
        """PD targets of the standing robot, before any action."""
        nominal = jnp.asarray(robot.NOMINAL_POSE)
        return jnp.concatenate([nominal, nominal]) if self.split_pd else nominal


class JTState(NamedTuple):
    filter: object
    target: jnp.ndarray  # (12,) the last joint targets sent


def joint_targets(name: str, filter_name: str, dt: float) -> ActionSpace:
    """JT (§4.2): nominal pose + action scaled to +-[0.2, 0.4, 0.4], then filtered."""
    filt = filters.make_filter(filter_name, dt)
    nominal = jnp.asarray(robot.NOMINAL_POSE)
    scale = jnp.asarray(robot.JT_ACTION_SCALE)

    def step(state, action):
        # Filtering the joint targets (radians), so the One Euro beta acts on rad/s.
        filter_state, target = filt.step(state.filter, nominal + scale * jnp.clip(action, -1.0, 1.0))
        return JTState(filter_state, target), target

    def observe(state):
        return state.target - nominal, jnp.zeros(0)

    return ActionSpace(name=name, size=robot.NUM_JOINTS, init=lambda: JTState(filt.init(nominal), nominal),
                       step=step, observe=observe, predicted_name="joint_angle")


# Thesis §4.3: foot offsets within +-0.15 m in x and y, +-0.1 m in z; frequency in [1, 4] Hz;
# residual joint angles within +-[0.1, 0.2, 0.2].
FOOT_OFFSET_SCALE = np.tile([0.15, 0.15, 0.1], 4).astype(np.float32)
CPG_FREQUENCY_HZ = 2.0
CPG_FREQUENCY_RANGE_HZ = (1.0, 4.0)
RESIDUAL_SCALE = np.tile([0.1, 0.2, 0.2], 4).astype(np.float32)
RESIDUAL_MODES = ("torque-average", "angle-average", "angle-sum")


class CPGActionState(NamedTuple):
    cpg: cpg.CPGState
    feet: jnp.ndarray  # (4, 3) the last commanded foot positions in the hip frames


def central_pattern(name: str, dt: float, variable_frequency: bool = False, residual: str | None = None
                    ) -> ActionSpace:
    """CPG (§4.3): trot foot heights + predicted foot offsets, through inverse kinematics.

    `variable_frequency` adds a 13th action, the frequency in [1, 4] Hz (CPG-VF).
    `residual` adds 12 residual joint angles around the nominal pose (CPG-RT), combined with
    the CPG's joint angles by one of RESIDUAL_MODES:
      torque-average  tau = (tau_cpg + tau_residual) / 2 from two PD controllers (simulation default)
      angle-average   phi = (phi_cpg + phi_residual) / 2 (what the real robot ran)
      angle-sum       phi = phi_cpg + residual, clipped to the joint ranges
    """
    if residual is not None and residual not in RESIDUAL_MODES:
        raise ValueError(f"residual mode {residual!r} is not one of {RESIDUAL_MODES}")
    nominal = jnp.asarray(robot.NOMINAL_POSE)
    nominal_feet = jnp.asarray(kinematics.NOMINAL_FEET)
    low, high = CPG_FREQUENCY_RANGE_HZ
    size = robot.NUM_JOINTS + int(variable_frequency) + (robot.NUM_JOINTS if residual else 0)

    def step(state, action):
        action = jnp.clip(action, -1.0, 1.0)
        offsets = (action[:12] * FOOT_OFFSET_SCALE).reshape(4, 3)
        frequency = low + (high - low) * 0.5 * (action[12] + 1.0) if variable_frequency else CPG_FREQUENCY_HZ
        pattern = cpg.advance(state.cpg, frequency, dt)
        feet = nominal_feet + offsets + jnp.zeros((4, 3)).at[:, 2].set(cpg.foot_heights(pattern.phase))
        angles = kinematics.inverse(feet).reshape(-1)
        if residual is None:
            ctrl = angles
        else:
            residual_target = nominal + action[-12:] * RESIDUAL_SCALE
            if residual == "torque-average":
                ctrl = jnp.concatenate([angles, residual_target])
            elif residual == "angle-average":
                ctrl = 0.5 * (angles + residual_target)
            else:
                ctrl = jnp.clip(angles + action[-12:] * RESIDUAL_SCALE, kinematics.JOINT_LOWER.reshape(-1),
                                kinematics.JOINT_UPPER.reshape(-1))
        return CPGActionState(pattern, feet), ctrl

    def observe(state):
        return (state.feet - nominal_feet).reshape(-1), cpg.progress(state.cpg.phase)

    return ActionSpace(name=name, size=size, init=lambda: CPGActionState(cpg.init(), nominal_feet), step=step,
                       observe=observe, predicted_name="feet_position", extra_size=2,
                       split_pd=residual == "torque-average")


APPROACHES = {
    "jt-nf": lambda dt: joint_targets("jt-nf", "none", dt),
    "jt-lpf": lambda dt: joint_targets("jt-lpf", "lowpass", dt),
    "jt-oef": lambda dt: joint_targets("jt-oef", "one_euro", dt),
    "cpg-d": lambda dt: central_pattern("cpg-d", dt),
    "cpg-vf": lambda dt: central_pattern("cpg-vf", dt, variable_frequency=True),
    "cpg-rt": lambda dt: central_pattern("cpg-rt", dt, residual="torque-average"),
    "cpg-rt-avg": lambda dt: central_pattern("cpg-rt-avg", dt, residual="angle-average"),
    "cpg-rt-sum": lambda dt: central_pattern("cpg-rt-sum", dt, residual="angle-sum"),
}


def make_action_space(approach: str, dt: float) -> ActionSpace:
    """The action pipeline of `approach` at control period `dt`."""
    return APPROACHES[approach](dt)
