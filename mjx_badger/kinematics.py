"""Analytic leg kinematics of the HB40: foot position in the hip frame <-> [hip, thigh, knee].

The hip frame of a leg sits at its hip (abduction) joint with the trunk's axes: x forward,
y left, z up. The geometry is the MJCF's (assets/hb40.xml): the thigh joint is offset
0.0555 m forward (front legs) or backward (rear legs) and 0.0125 m outward of the hip
joint, thigh and calf are 0.2 m, and the foot-sphere centre is the end of the calf.
All functions work on one leg (3,) or all legs (4, 3) and are jit/vmap friendly.
"""

import jax.numpy as jnp
import numpy as np

from mjx_badger import robot

THIGH_LENGTH = 0.2
CALF_LENGTH = 0.2
THIGH_OFFSET_X = 0.0555
THIGH_OFFSET_Y = 0.0125
# Per leg (FL, FR, RL, RR): +1 front / -1 rear, +1 left / -1 right.
FRONT_SIGN = np.array([1.0, 1.0, -1.0, -1.0])
LEFT_SIGN = np.array([1.0, -1.0, 1.0, -1.0])
HIP_X, HIP_Y = 0.1375, 0.064
HIP_POSITIONS = np.stack([FRONT_SIGN * HIP_X, LEFT_SIGN * HIP_Y, np.zeros(4)], axis=-1)
"""Hip (abduction) joints in the trunk frame (4, 3); a foot in the trunk frame is this + forward()."""
JOINT_LOWER = np.tile([-1.57, -1.57, -2.53], 4).reshape(4, 3)
JOINT_UPPER = np.tile([1.57, 1.57, 0.0], 4).reshape(4, 3)


def forward(angles):
    """Foot positions (4, 3) in the hip frames from joint angles (4, 3) or (12,)."""
    q = jnp.reshape(angles, (4, 3))
    hip, thigh, knee = q[:, 0], q[:, 1], q[:, 2]
    # In the frame turned with the hip joint, the leg moves in the x-z plane.
    x = FRONT_SIGN * THIGH_OFFSET_X - THIGH_LENGTH * jnp.sin(thigh) - CALF_LENGTH * jnp.sin(thigh + knee)
    y = LEFT_SIGN * THIGH_OFFSET_Y
    z = -THIGH_LENGTH * jnp.cos(thigh) - CALF_LENGTH * jnp.cos(thigh + knee)
    c, s = jnp.cos(hip), jnp.sin(hip)
    return jnp.stack([x, c * y - s * z, s * y + c * z], axis=-1)


def inverse(feet):
    """Joint angles (4, 3) reaching foot positions (4, 3) in the hip frames, knee bent backward.

    Unreachable points give the nearest stretched or folded leg, and every angle is clipped
    to its joint range, so the result is always finite.
    """
    p = jnp.reshape(feet, (4, 3))
    px, py, pz = p[:, 0], p[:, 1], p[:, 2]
    side = LEFT_SIGN * THIGH_OFFSET_Y
    # Length of the leg's projection on the hip's y-z plane, below the thigh joint.
    height = jnp.sqrt(jnp.maximum(py**2 + pz**2 - side**2, 1e-8))
    hip = jnp.arctan2(pz, py) - jnp.arctan2(-height, side)
    hip = jnp.arctan2(jnp.sin(hip), jnp.cos(hip))
    along = -(px - FRONT_SIGN * THIGH_OFFSET_X)
    reach2 = along**2 + height**2
    cos_knee = (reach2 - THIGH_LENGTH**2 - CALF_LENGTH**2) / (2 * THIGH_LENGTH * CALF_LENGTH)
    knee = -jnp.arccos(jnp.clip(cos_knee, -1.0, 1.0))
    thigh = jnp.arctan2(along, height) - jnp.arctan2(CALF_LENGTH * jnp.sin(knee),
                                                      THIGH_LENGTH + CALF_LENGTH * jnp.cos(knee))
    angles = jnp.stack([hip, thigh, knee], axis=-1)
    return jnp.clip(angles, JOINT_LOWER, JOINT_UPPER)


NOMINAL_FEET = np.asarray(forward(robot.NOMINAL_POSE))
"""Foot positions (4, 3) of the nominal standing pose, the CPG's stance reference."""
