"""Analytic leg kinematics of the HB40: foot position in the hip frame <-> [hip, thigh, knee].

The hip frame of a leg sits at its hip (abduction) joint with the trunk's axes: x forward,
y left, z up. The geometry and joint convention are the robot spec's (description.py). In a leg's
sagittal plane the thigh points `alpha` behind vertical and the calf `gamma`; with the spec's
zeros, alpha = phi0 + a and gamma = alpha + kappa0 + b, where a and b are the thigh and knee
angles turned into one physical sense (x the leg's left sign) and phi0, kappa0 the spec's zero angles.
All functions take the robot spec (default the HB40), work on all legs (4, 3) or (12,) and are
jit/vmap friendly.

`thesis_code_ik` is the other inverse kinematics: the one the released code's CPG uses, with
its own link lengths, in its own leg frames, whose angles go to the joints unchanged.
"""

import functools
import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from mjx_badger.robot import description as robot
from mjx_badger.robot.description import HB40, RobotSpec


class Leg(NamedTuple):
    """The figures of a spec the leg kinematics read, per leg where they differ."""

    phi0: float
    kappa0: float
    l1: float
    l2: float
    thigh_x: float
    lateral: float
    """Outboard distance of the foot from the hip joint in the leg's own (unabducted) frame."""
    front: np.ndarray
    left: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


@functools.cache
def leg(spec: RobotSpec = HB40) -> Leg:
    """The leg kinematics' figures of `spec` (computed once per spec)."""
    lower, upper = robot.joint_limits(spec)
    return Leg(math.radians(spec.thigh_zero_behind_vertical_deg), math.radians(spec.knee_zero_interior_deg),
               spec.thigh_length, spec.calf_length, spec.thigh_offset_x,
               spec.thigh_offset_y + spec.knee_outboard + spec.foot_outboard,
               spec.front_sign, spec.left_sign, lower, upper)


def forward(angles, spec: RobotSpec = HB40):
    """Foot positions (4, 3) in the hip frames from joint angles (4, 3) or (12,)."""
    g = leg(spec)
    q = jnp.reshape(angles, (len(spec.legs), 3))
    a = g.left * q[:, 1]
    b = g.left * q[:, 2]
    alpha = g.phi0 + a
    gamma = alpha + g.kappa0 + b
    x = g.front * g.thigh_x - g.l1 * jnp.sin(alpha) + g.l2 * jnp.sin(gamma)
    z = -g.l1 * jnp.cos(alpha) + g.l2 * jnp.cos(gamma)
    y = g.left * g.lateral
    hip = g.front * q[:, 0]  # the rear hips turn about -x
    c, s = jnp.cos(hip), jnp.sin(hip)
    return jnp.stack([x, c * y - s * z, s * y + c * z], axis=-1)


def inverse(feet, spec: RobotSpec = HB40):
    """Joint angles (4, 3) reaching foot positions (4, 3) in the hip frames, knee bent backward.

    Unreachable points give the nearest stretched or folded leg, and every angle is clipped
    to its joint range, so the result is always finite.
    """
    g = leg(spec)
    p = jnp.reshape(feet, (len(spec.legs), 3))
    px, py, pz = p[:, 0], p[:, 1], p[:, 2]
    side = g.left * g.lateral
    # The leg's drop below the hip in its own abducted plane.
    height = jnp.sqrt(jnp.maximum(py**2 + pz**2 - side**2, 1e-8))
    psi = jnp.arctan2(pz, py) - jnp.arctan2(-height, side)
    psi = jnp.arctan2(jnp.sin(psi), jnp.cos(psi))
    xs = px - g.front * g.thigh_x
    reach = jnp.sqrt(xs**2 + height**2)
    l1, l2 = g.l1, g.l2
    interior = jnp.arccos(jnp.clip((l1**2 + l2**2 - reach**2) / (2 * l1 * l2), -1.0, 1.0))
    at_thigh = jnp.arccos(jnp.clip((l1**2 + reach**2 - l2**2) / (2 * l1 * jnp.maximum(reach, 1e-6)), -1.0, 1.0))
    foot_line = jnp.arctan2(-xs, height)  # foot direction, behind vertical
    a = foot_line + at_thigh - g.phi0
    b = interior - g.kappa0
    angles = jnp.stack([g.front * psi, g.left * a, g.left * b], axis=-1)
    return jnp.clip(angles, g.lower, g.upper)


@functools.cache
def nominal_feet(spec: RobotSpec = HB40) -> np.ndarray:
    """Foot positions (4, 3) of the nominal standing pose, the thesis-text CPG's stance reference."""
    return np.asarray(forward(robot.nominal_pose(spec), spec))


# The released code's CPG inverse kinematics (C/control_functions/inverse_kinematics.py): its
# own link lengths (not the model's 0.2 / 0.2), a 0.335 m reach clamp, and its own leg frames.
THESIS_IK_HIP_TO_THIGH = 0.0525
THESIS_IK_FEMUR = 0.18
THESIS_IK_TIBIA = 0.177
THESIS_IK_REACH = 0.335


def thesis_code_ik(targets, spec: RobotSpec = HB40):
    """Joint angles (4, 3) the released code's IK gives for foot targets (4, 3) in its leg frames.

    Its angles are relative to a folded knee and a horizontal thigh, so they land on the
    model's joints with the model's own 13.3-degree knee fold added: that is how the
    released CPG stands with its feet 0.30 m below the hips though it asks for 0.25 m.
    Per leg, left legs mirror y and the sagittal angles, rear legs the hip angle once more.
    """
    p = jnp.reshape(targets, (4, 3))
    norm = jnp.linalg.norm(p, axis=-1, keepdims=True)
    p = jnp.where(norm > THESIS_IK_REACH, p / norm * THESIS_IK_REACH, p)
    x = p[:, 0] - THESIS_IK_HIP_TO_THIGH
    y = -spec.left_sign * p[:, 1]
    z = p[:, 2]
    l_zy = jnp.sqrt(y**2 + z**2)
    hip = jnp.arcsin(jnp.clip(y / l_zy, -1.0, 1.0))
    reach = jnp.sqrt(l_zy**2 + x**2)
    f, t = THESIS_IK_FEMUR, THESIS_IK_TIBIA
    knee = -jnp.arccos(jnp.clip((reach**2 - f**2 - t**2) / (-2.0 * f * t), -1.0, 1.0))
    thigh = (jnp.pi / 2 + jnp.arcsin(jnp.clip(x / reach, -1.0, 1.0))
             - jnp.arccos(jnp.clip((t**2 - f**2 - reach**2) / (-2.0 * f * reach), -1.0, 1.0)))
    mirror = -spec.left_sign  # left legs flip every angle ...
    hip = hip * mirror * spec.front_sign  # ... and rear legs their hip once more
    return jnp.stack([hip, thigh * mirror, knee * mirror], axis=-1)
