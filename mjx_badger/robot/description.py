"""The HB40 robot description: every figure of the robot in one frozen spec, the registry of robots, and
their poses (the MuJoCo model built from a spec: mjcf.py).

The figures are those of the thesis's released code's model (`gait_in_eight`, plane.xml, as
docs/thesis-code.md §1 records them), rebuilt by us with primitive geoms. Joint-zero convention
(theirs): hip 0 = leg in the trunk's x-z plane; thigh 0 = thigh pointing straight backward,
horizontal; knee 0 = folded back onto the thigh with 13.3 degrees between the links. The
joint axes are mirrored so that one set of angles means the same posture on every leg up to
sign: front hips turn about +x and rear hips about -x; left thighs and knees about +y, right
ones about -y. In that convention the thesis's nominal pose [0.1, 0.6, -1.2] reads
FL (0.1, -0.6, 1.2), FR (-0.1, 0.6, -1.2), RL (-0.1, -0.6, 1.2), RR (0.1, 0.6, -1.2): hips
0.1 rad outward, thighs 55.6 degrees behind vertical, knees 82 degrees between the links,
each foot 0.252 m below and 0.102 m outboard of its hip.
"""

import dataclasses
import functools

import numpy as np


def roll_pitch(rot, xp=np):
    """Roll and pitch (rad) of a body-to-world rotation matrix (3, 3); `xp` is numpy or jax.numpy."""
    return xp.arctan2(rot[2, 1], rot[2, 2]), xp.arcsin(xp.clip(-rot[2, 0], -1.0, 1.0))


@dataclasses.dataclass(frozen=True)
class RobotSpec:
    """Every figure of a quadruped of the HB40's layout; lengths in m, masses in kg, inertias in kg m^2."""

    name: str = "hb40"
    legs: tuple = ("FL", "FR", "RL", "RR")
    """Leg names, F(ront) or R(ear) then L(eft) or R(ight): the order of every per-leg array."""
    joints_per_leg: tuple = ("hip", "thigh", "knee")
    hip_x: float = 0.1375
    """Hip (abduction) joints at (+-hip_x, +-hip_y, 0) in the trunk frame (plane.xml)."""
    hip_y: float = 0.064
    thigh_offset_x: float = 0.0555
    """Thigh joint: this far forward (front legs) or backward (rear legs) of the hip joint ..."""
    thigh_offset_y: float = 0.0125
    """... and this far outboard."""
    thigh_length: float = 0.2
    knee_outboard: float = 0.0584
    """Lateral offset of the knee from the thigh joint (plane.xml)."""
    calf_length: float = 0.2
    foot_outboard: float = 0.0054
    """Lateral offset of the foot-sphere centre from the knee (plane.xml)."""
    foot_radius: float = 0.02
    thigh_zero_behind_vertical_deg: float = 90.0
    """Thigh direction at thigh angle 0 (their zero: thigh horizontal, pointing backward)."""
    knee_zero_interior_deg: float = 13.3
    """Angle between thigh and calf at knee angle 0 (their zero: folded)."""
    trunk_mass: float = 5.423
    trunk_inertia: tuple = (0.6228, 0.4899, 0.1946)
    """Diagonal, trunk frame (plane.xml: 10-50x a uniform solid of the trunk's size; it is what ran)."""
    hip_mass: float = 0.645
    hip_inertia: tuple = (0.0093, 0.0065, 0.0052)
    thigh_mass: float = 0.827
    thigh_inertia: tuple = (0.033, 0.0286, 0.0077)
    """Diagonal, in a frame whose z axis runs along the link (plane.xml)."""
    calf_mass: float = 0.118
    calf_inertia: tuple = (0.0213, 0.0212, 0.0002)
    trunk_half_size: tuple = (0.135, 0.089, 0.05)
    """Trunk collision box half-sizes."""
    thigh_motor_radius: float = 0.05
    """Collision cylinder of the thigh motor, coaxial with the thigh joint (plane.xml 'thigh' geom)."""
    thigh_motor_half_length: float = 0.055
    calf_radius: float = 0.015
    """Collision capsule along the calf (plane.xml: a cylinder of radius 0.015)."""
    hip_range: float = 1.57
    thigh_range: float = 1.57
    knee_range: tuple = (0.0, 2.53)
    """Left knees' range from the folded zero (right knees mirrored)."""
    joint_damping: float = 0.1
    joint_armature: float = 0.013122
    joint_frictionloss: float = 0.48
    torque_limit: float = 16.0
    joint_velocity_limit: float = 25.0
    """rad/s; the released code clips joint velocities to this after every physics step."""
    nominal: tuple = (0.1, 0.6, -1.2)
    """Thesis §4.1 nominal [hip, thigh, knee], read in this robot's joint convention by `nominal_pose`."""
    jt_action_scale: tuple = (0.2, 0.4, 0.4)
    """Thesis §4.1: joint-target actions stay within +-these (rad) of the nominal pose."""
    home_height: float = 0.316
    """Trunk height at reset (released code: a 4.4 cm drop onto the feet)."""
    pd_gains: tuple = (60.0, 3.0)
    """The robot's own joint controller as the on-robot loop drives it: the scripts' Kp 60 / Kd 3."""
    damping_gains: tuple = (0.0, 3.0)
    """The safety stop: the motors only damp, Kp 0 / Kd 3 (§5.2)."""
    fall_tilt_rad: float = 0.8
    """The robot has fallen past this roll or pitch (about 46 degrees): thesis-text's rule and the safety monitor's."""
    fall_height: float = 0.15
    """... or with the trunk centre below this (trunk or hips at the floor): thesis-text's rule."""
    physics_dt: float = 0.005
    friction: float = 1.1
    contact_solref: tuple = (-1000.0, -80.0)
    """Direct contact stiffness and damping (plane.xml)."""
    contact_solimp: float = 0.9999
    """plane.xml's solimp '1.2 1.1' clamps to this impedance."""
    impratio: float = 100.0
    solver_iterations: int = 50
    """Most Newton iterations per physics step (plane.xml: 100). The solver stops at its tolerance, so
    50 costs MJX about what 10 does, and unlike 10 it keeps MJX close to native MuJoCo through the reset
    drop onto the stiff, impratio-100 contacts (benchmarks/bench_contacts.py times the contacts)."""
    solver_ls_iterations: int = 10
    floor_contacts: tuple = ("trunk", "thigh", "calf", "foot")
    """Parts that collide with the floor (plane.xml: all of them); ("foot",) is the first version's feet-only model."""

    @property
    def joint_names(self) -> tuple:
        """Joint (and actuator) names, leg by leg: FL_hip, FL_thigh, FL_knee, FR_hip, ..."""
        return tuple(f"{leg}_{joint}" for leg in self.legs for joint in self.joints_per_leg)

    @property
    def num_joints(self) -> int:
        return len(self.legs) * len(self.joints_per_leg)

    @property
    def foot_geoms(self) -> tuple:
        return tuple(f"{leg}_foot" for leg in self.legs)

    @functools.cached_property
    def front_sign(self) -> np.ndarray:
        """Per leg: +1 front, -1 rear."""
        return np.array([1.0 if leg[0] == "F" else -1.0 for leg in self.legs])

    @functools.cached_property
    def left_sign(self) -> np.ndarray:
        """Per leg: +1 left, -1 right."""
        return np.array([1.0 if leg[1] == "L" else -1.0 for leg in self.legs])

    @functools.cached_property
    def hip_positions(self) -> np.ndarray:
        """Hip (abduction) joints in the trunk frame (legs, 3); a foot in the trunk frame is this + kinematics.forward()."""
        return np.stack([self.front_sign * self.hip_x, self.left_sign * self.hip_y, np.zeros(len(self.legs))], axis=-1)


HB40 = RobotSpec()

HB40_FIRST_VERSION = RobotSpec(
    name="hb40-v1",
    knee_outboard=0.0,
    foot_outboard=0.0,
    thigh_zero_behind_vertical_deg=0.0,
    knee_zero_interior_deg=180.0,
    knee_range=(-2.53, 0.0),
    trunk_inertia=(0.01884, 0.03746, 0.04726),
    hip_inertia=(0.000516, 0.0004515, 0.0004515),
    thigh_inertia=(0.00364, 0.00364, 0.000162),
    calf_inertia=(0.000464, 0.000464, 0.0000084),
    nominal=(0.1, -0.6, 1.2),
    home_height=0.36,
)
"""The HB40 of this suite's first version (thesis-text figures, before the released code was read: docs/thesis-code.md): legs in one
plane below the hips, thigh zero pointing down and knee zero straight, the inertias of uniform
solids, and the thesis nominal pose read with thigh 0.6 rad behind vertical and the calf 0.6 rad
ahead of it (feet 0.33 m below the hips). Contacts and solver are the HB40's, so a swap to it
moves geometry and inertia alone (attribution.py's 'robot geometry')."""

ROBOTS: dict = {}


def register(spec: RobotSpec) -> RobotSpec:
    """Add `spec` to ROBOTS under its name (replacing one of the same name)."""
    ROBOTS[spec.name] = spec
    return spec


register(HB40)
register(HB40_FIRST_VERSION)


def joint_signs(spec: RobotSpec = HB40) -> np.ndarray:
    """(4, 3) sign that turns [hip, thigh, knee] of the spec's convention into each leg's joint angles."""
    return np.stack([spec.front_sign * spec.left_sign, -spec.left_sign, -spec.left_sign], axis=-1)


def nominal_pose(spec: RobotSpec = HB40) -> np.ndarray:
    """The nominal joint angles (12,) in order FL, FR, RL, RR x hip, thigh, knee."""
    return (joint_signs(spec) * np.asarray(spec.nominal)).reshape(-1).astype(np.float32)


def jt_action_scale(spec: RobotSpec = HB40) -> np.ndarray:
    """Half-range (12,) of the joint-target actions around the nominal pose."""
    return np.tile(spec.jt_action_scale, len(spec.legs)).astype(np.float32)


def joint_limits(spec: RobotSpec = HB40) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper joint limits (4, 3)."""
    low, high = spec.knee_range
    left, n = spec.left_sign > 0, len(spec.legs)
    upper = np.stack([np.full(n, spec.hip_range), np.full(n, spec.thigh_range), np.where(left, high, -low)], axis=-1)
    lower = np.stack([np.full(n, -spec.hip_range), np.full(n, -spec.thigh_range), np.where(left, low, -high)], axis=-1)
    return lower, upper


def standing_qpos(model, spec: RobotSpec = HB40, pose=None) -> np.ndarray:
    """qpos of `model` (a MuJoCo model of `spec`) at reset: trunk level at the home height, legs in `pose` (default
    the nominal pose)."""
    qpos = np.zeros(model.nq)
    qpos[:3] = [0.0, 0.0, spec.home_height]
    qpos[3] = 1.0
    qpos[7:] = nominal_pose(spec) if pose is None else pose
    return qpos
