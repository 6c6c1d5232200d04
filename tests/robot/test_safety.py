"""The safety rule: a tilt past the fall tilt or a joint past its range (with a margin) stops the robot."""

import jax.numpy as jnp
import numpy as np

from mjx_badger.robot import kinematics, safety
from mjx_badger.robot.description import HB40, nominal_pose


def _rolled(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def test_the_rule_trips_on_tilt_and_on_a_joint_out_of_range_alike_in_numpy_and_jax():
    pose = nominal_pose(HB40)
    tilt = HB40.fall_tilt_rad
    assert not safety.trips(np.eye(3), pose)
    assert not safety.trips(_rolled(tilt - 0.01), pose) and safety.trips(_rolled(tilt + 0.01), pose)
    upper = kinematics.leg(HB40).upper.reshape(-1)
    inside, outside = pose.copy(), pose.copy()
    inside[2] = upper[2] + safety.JOINT_MARGIN_RAD - 0.01  # encoders overshoot the stop a little: allowed
    outside[2] = upper[2] + safety.JOINT_MARGIN_RAD + 0.01
    assert not safety.trips(np.eye(3), inside) and safety.trips(np.eye(3), outside)
    assert bool(safety.trips(jnp.asarray(_rolled(tilt + 0.01)), jnp.asarray(pose), HB40, jnp))
