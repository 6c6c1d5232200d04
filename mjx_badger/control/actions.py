"""Action pipelines: from the policy's action in [-1, 1]^A to the motors' PD targets.

An action space is `init() -> state`, `step(state, action) -> (state, ctrl)` and
`observe(state) -> (predicted (12,), extra (k,))`, the approach's own observation blocks
of thesis Table 4.1. `ctrl` holds one PD target per actuator: 12, or 24 for the
torque-averaging residual CPG, whose model drives every joint with two half-strength PD
controllers (mjcf.load_model(split_pd=True)). The approaches of Table 5.2 are `Approach`
records in `APPROACHES`: what they are (`kind`), how figures show them, how to build them.
"""

import dataclasses
import inspect
from typing import Callable, NamedTuple

import jax.numpy as jnp
import numpy as np

from mjx_badger.control import cpg, filters
from mjx_badger.protocol import protocols
from mjx_badger.protocol.protocols import Protocol
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics


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
    spec: robot.RobotSpec = robot.HB40
    """The robot whose nominal pose the pipeline works around."""

    @property
    def ctrl_size(self) -> int:
        return 2 * self.spec.num_joints if self.split_pd else self.spec.num_joints

    def rest_ctrl(self):
        """PD targets of the standing robot, before any action."""
        nominal = jnp.asarray(robot.nominal_pose(self.spec))
        return jnp.concatenate([nominal, nominal]) if self.split_pd else nominal


class JTState(NamedTuple):
    filter: object
    target: jnp.ndarray  # (12,) the last joint targets sent


def joint_targets(filt: filters.Filter, spec: robot.RobotSpec = robot.HB40) -> ActionSpace:
    """JT (§4.2): nominal pose + action scaled to +-[0.2, 0.4, 0.4], then filtered."""
    nominal = jnp.asarray(robot.nominal_pose(spec))
    scale = jnp.asarray(robot.jt_action_scale(spec))

    def step(state, action):
        # Filtering the joint targets (radians), so the One Euro beta acts on rad/s; a linear
        # filter started at rest at the nominal pose equals the released code's zero-state
        # filter of the offsets.
        filter_state, target = filt.step(state.filter, nominal + scale * jnp.clip(action, -1.0, 1.0))
        return JTState(filter_state, target), target

    def observe(state):
        return state.target - nominal, jnp.zeros(0)

    return ActionSpace(name="jt", size=spec.num_joints, init=lambda: JTState(filt.init(nominal), nominal),
                       step=step, observe=observe, predicted_name="joint_angle", spec=spec)


def jt_filter(kind: str, dt: float, protocol: Protocol, **params) -> filters.Filter:
    """The filter of a JT approach ('none', 'lowpass', 'one_euro') under a protocol, with its parameters."""
    if kind == "lowpass":
        return filters.make_filter("butterworth" if protocol.lowpass == "butterworth" else "lowpass", dt, **params)
    if kind == "one_euro":
        return filters.make_filter("one_euro", dt, start_at_first_input=protocol.one_euro_first_output_is_input,
                                   **params)
    return filters.make_filter(kind, dt, **params)


# Thesis §4.3: foot offsets within +-0.15 m in x and y, +-0.1 m in z; frequency in [1, 4] Hz;
# residual joint angles within +-[0.1, 0.2, 0.2]. The released code adds its offsets to joint
# angles instead, within +-[0.15, 0.15, 0.10] rad (docs/thesis-code.md §2).
FOOT_OFFSET_SCALE = np.tile([0.15, 0.15, 0.1], 4).astype(np.float32)
JOINT_OFFSET_SCALE = FOOT_OFFSET_SCALE
CPG_FREQUENCY_HZ = 2.0
CPG_FREQUENCY_RANGE_HZ = (1.0, 4.0)
RESIDUAL_SCALE = np.tile([0.1, 0.2, 0.2], 4).astype(np.float32)
RESIDUAL_MODES = ("torque-average", "angle-average", "angle-sum", "average-d-bug")
ROBOT_RESIDUAL = {"thesis-code": "angle-sum", "thesis-text": "angle-average"}
"""CPG-RT as the robot ran it, per protocol: the released robot CPG's active branch adds the residuals to the IK's
angles (honey_badger_ros/ros_connection/cpg.py); the text averages the two joint angles (§4.3 item 2, §6.3)."""
CPG_ROBOT_PARAMS = ("apex_m", "frequency_hz")
"""The constant-frequency CPGs' parameters the on-robot conditions set (conditions.py), sweepable like any other."""
# The released code's CPG stance: foot targets (0.05, +-0.02, -0.25) m in its IK's leg frames,
# rear legs 0.02 m further back (C/control_functions/inverse_kinematics.py).
THESIS_CODE_STANCE = np.stack([0.05 - 0.02 * (robot.HB40.front_sign < 0), 0.02 * robot.HB40.left_sign,
                               np.full(4, -0.25)], axis=-1).astype(np.float32)


class CPGActionState(NamedTuple):
    cpg: cpg.CPGState
    feet: jnp.ndarray  # (4, 3) the last commanded foot positions in the hip frames (thesis-text)
    offsets: jnp.ndarray  # (12,) the last scaled action offsets (thesis-code's observation)
    heights: jnp.ndarray  # (2,) the last swing heights of the two leg pairs (thesis-code's observation)


def central_pattern(dt: float, variable_frequency: bool = False, residual: str | None = None,
                    protocol: Protocol = protocols.THESIS_CODE, spec: robot.RobotSpec = robot.HB40,
                    apex_m: float = cpg.APEX_HEIGHT, frequency_hz: float = CPG_FREQUENCY_HZ) -> ActionSpace:
    """CPG (§4.3): trot foot heights + predicted offsets, through inverse kinematics.

    thesis-text: offsets on the foot positions around the nominal stance, then our IK.
    thesis-code: the released code's IK of its own stance plus swing height, then the offsets
    added to the joint angles.
    `apex_m` is the swing's apex height, `frequency_hz` the gait frequency unless
    `variable_frequency` adds a 13th action, the frequency in [1, 4] Hz (CPG-VF).
    `residual` adds 12 residual joint angles around the nominal pose (CPG-RT), combined with
    the CPG's joint angles by one of RESIDUAL_MODES:
      torque-average  tau = (tau_cpg + tau_residual) / 2 from two PD controllers (thesis text, simulation)
      angle-average   phi = (phi_cpg + phi_residual) / 2 (what the real robot ran)
      angle-sum       phi = phi_cpg + residual, clipped to the joint ranges
      average-d-bug   the released code: tau = [tau_cpg + Kp (nominal + residual - q) + Kd (offset - qdot)] / 2,
                      the offset standing in for a velocity target; one PD on the average target
                      with the feed-forward Kd offset / 2 folded into it
    """
    if residual is not None and residual not in RESIDUAL_MODES:
        raise ValueError(f"residual mode {residual!r} is not one of {RESIDUAL_MODES}")
    code = protocol.cpg_action == "joint-offsets"
    nominal = jnp.asarray(robot.nominal_pose(spec))
    nominal_feet = jnp.asarray(kinematics.nominal_feet(spec))
    stance = jnp.asarray(THESIS_CODE_STANCE)
    lower, upper = (limit.reshape(-1) for limit in robot.joint_limits(spec))
    low, high = CPG_FREQUENCY_RANGE_HZ
    size = spec.num_joints + int(variable_frequency) + (spec.num_joints if residual else 0)
    kp, kd = protocol.cpg_pd_gains

    def step(state, action):
        action = jnp.clip(action, -1.0, 1.0)
        frequency = low + (high - low) * 0.5 * (action[12] + 1.0) if variable_frequency else frequency_hz
        advanced = cpg.advance(state.cpg, frequency, dt)
        # The released code reads the heights before it advances the phase (beat.py).
        phase = state.cpg.phase if protocol.cpg_heights_before_advance else advanced.phase
        heights = cpg.foot_heights(phase, apex_m, spec=spec)
        lift = jnp.zeros((4, 3)).at[:, 2].set(heights)
        if code:
            offsets = action[:12] * JOINT_OFFSET_SCALE
            feet = stance + lift
            angles = kinematics.thesis_code_ik(feet, spec).reshape(-1) + offsets
        else:
            offsets = action[:12] * FOOT_OFFSET_SCALE
            feet = nominal_feet + offsets.reshape(4, 3) + lift
            angles = kinematics.inverse(feet, spec).reshape(-1)
        if residual is None:
            ctrl = angles
        else:
            residual_target = nominal + action[-12:] * RESIDUAL_SCALE
            if residual == "torque-average":
                ctrl = jnp.concatenate([angles, residual_target])
            elif residual == "angle-average":
                ctrl = 0.5 * (angles + residual_target)
            elif residual == "average-d-bug":
                ctrl = 0.5 * (angles + residual_target) + 0.5 * kd * offsets / kp
            else:
                ctrl = jnp.clip(angles + action[-12:] * RESIDUAL_SCALE, lower, upper)
        pair_heights = jnp.stack([heights[0], heights[1]])
        return CPGActionState(advanced, feet, offsets, pair_heights), ctrl

    def observe(state):
        if code:
            return state.offsets, state.heights
        return (state.feet - nominal_feet).reshape(-1), cpg.progress(state.cpg.phase)

    def init():
        # The released code's first CPG observation is literally [0, pi] (environment.py).
        return CPGActionState(cpg.init(), nominal_feet, jnp.zeros(12), jnp.array([0.0, jnp.pi]))

    return ActionSpace(name="cpg", size=size, init=init, step=step, observe=observe,
                       predicted_name="joint_angle" if code else "feet_position", extra_size=2,
                       split_pd=residual == "torque-average", spec=spec)


class Approach(NamedTuple):
    """A registered action space: what it is, how figures show it, and how to build it."""

    name: str
    kind: str
    """'jt' (joint targets) or 'cpg' (central pattern generator): the protocol's gains and rate per kind."""
    label: str
    """Display name in figures and tables."""
    color: str
    """Matplotlib colour in figures."""
    build: Callable
    """(dt, protocol, spec, **params) -> ActionSpace."""
    params: tuple = ()
    """Names of the keyword parameters `build` takes (sweepable values such as a filter cutoff)."""


KINDS = ("jt", "cpg")
APPROACHES: dict = {}


def register(approach: Approach) -> Approach:
    """Add `approach` to APPROACHES (replacing one of the same name)."""
    if approach.kind not in KINDS:
        raise ValueError(f"approach {approach.name!r}: kind {approach.kind!r} is not one of {KINDS}")
    APPROACHES[approach.name] = approach
    return approach


def filter_params(make: Callable) -> tuple:
    """The keyword parameters of a filter factory after its control period."""
    return tuple(inspect.signature(make).parameters)[1:]


def filter_approach(name: str, label: str, color: str, make: Callable) -> Approach:
    """A JT approach whose filter is `make(dt, **params)`: a new filter is one `register(filter_approach(...))`."""
    build = lambda dt, protocol, spec, **params: joint_targets(make(dt, **params), spec)
    return Approach(name, "jt", label, color, build, filter_params(make))


def is_cpg(approach: str) -> bool:
    """Whether `approach` drives the legs through the central pattern generator."""
    return APPROACHES[approach].kind == "cpg"


def check_robot(approach: str, spec: robot.RobotSpec, protocol: Protocol):
    """Raise ValueError if `approach` cannot drive `spec`: the released code's CPG IK is the HB40's own."""
    # Which parts touch the floor does not change the legs the IK is built for.
    legs = dataclasses.replace(spec, floor_contacts=robot.HB40.floor_contacts)
    if is_cpg(approach) and protocol.cpg_action == "joint-offsets" and legs != robot.HB40:
        raise ValueError(f"the released code's CPG (cpg_action 'joint-offsets') runs on the {robot.HB40.name} only, "
                         f"not on {spec.name}; its foot-offsets CPG runs on any robot")


def check_params(approach: str, params: dict):
    """Raise ValueError for a parameter `approach` does not take, naming the ones it does."""
    unknown = sorted(set(params) - set(APPROACHES[approach].params))
    if unknown:
        takes = ", ".join(APPROACHES[approach].params) or "no parameters"
        raise ValueError(f"approach {approach!r} takes {takes}, not {', '.join(unknown)}")


def _jt(kind: str):
    return lambda dt, protocol, spec, **params: joint_targets(jt_filter(kind, dt, protocol, **params), spec)


def _cpg(**fixed):
    return lambda dt, p, spec, **params: central_pattern(dt, protocol=p, spec=spec, **fixed, **params)


for _approach in (
    Approach("jt-nf", "jt", "JT-NF", "tab:red", _jt("none")),
    Approach("jt-lpf", "jt", "JT-LPF", "tab:blue", _jt("lowpass"), ("cutoff_hz",)),
    Approach("jt-oef", "jt", "JT-OEF", "tab:green", _jt("one_euro"), ("min_cutoff", "beta", "d_cutoff")),
    Approach("cpg-d", "cpg", "CPG-D", "tab:purple", _cpg(), CPG_ROBOT_PARAMS),
    Approach("cpg-vf", "cpg", "CPG-VF", "tab:orange", _cpg(variable_frequency=True), ("apex_m",)),
    Approach("cpg-rt", "cpg", "CPG-RT", "tab:brown",
             lambda dt, p, spec, **params: central_pattern(dt, residual=p.cpg_residual, protocol=p, spec=spec,
                                                           **params), CPG_ROBOT_PARAMS),
    Approach("cpg-rt-avg", "cpg", "CPG-RT-avg", "tab:pink", _cpg(residual="angle-average"), CPG_ROBOT_PARAMS),
    Approach("cpg-rt-sum", "cpg", "CPG-RT-sum", "tab:gray", _cpg(residual="angle-sum"), CPG_ROBOT_PARAMS),
):
    register(_approach)


def on_robot(approach: str, protocol: Protocol, conditions) -> tuple[Protocol, dict]:
    """(protocol, params) of `approach` as the robot of `conditions` (conditions.py) runs it: CPG-RT's mix and the
    CPG's swing apex and frequency where the conditions set them; a parameter the run sets itself comes later."""
    if conditions is None or not is_cpg(approach):
        return protocol, {}
    if conditions.robot_cpg_residual:
        protocol = protocol.replace(cpg_residual=ROBOT_RESIDUAL.get(protocol.name, "angle-average"))
    takes = APPROACHES[approach].params
    params = {"apex_m": conditions.cpg_swing_height_m, "frequency_hz": conditions.cpg_frequency_hz}
    return protocol, {k: v for k, v in params.items() if v is not None and k in takes}


def make_action_space(approach: str, dt: float, protocol: Protocol = protocols.THESIS_CODE,
                      spec: robot.RobotSpec = robot.HB40, conditions=None, **params) -> ActionSpace:
    """The action pipeline of `approach` at control period `dt` under `protocol`, on the robot `spec`, as the robot
    of `conditions` runs it (None: the simulation's)."""
    check_robot(approach, spec, protocol)
    check_params(approach, params)
    protocol, robot_params = on_robot(approach, protocol, conditions)
    return APPROACHES[approach].build(dt, protocol, spec, **{**robot_params, **params})._replace(name=approach)
