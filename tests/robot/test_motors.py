"""The motors: a split PD model averages two clipped PD torques."""

import mujoco
import numpy as np
import pytest

from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf, motors


def test_split_pd_model_averages_two_clipped_pd_torques():
    """Two actuators per joint at half gains and half limit: the joint torque is the mean of two PD torques."""
    model = mjcf.load_model(split_pd=True)
    assert model.nu == 24
    data = mujoco.MjData(model)
    motors.set_pd_gains(model, 60.0, 3.0, split_pd=True)
    data.qpos[:] = robot.standing_qpos(model)
    first = robot.nominal_pose() + 0.05
    second = robot.nominal_pose() - 1.0  # saturates: -60 rad^-1 x 1 rad is beyond 16 N m
    data.ctrl[:] = np.concatenate([first, second])
    mujoco.mj_forward(model, data)
    q = data.qpos[7:]
    limit = robot.HB40.torque_limit
    pd = lambda target: np.clip(60.0 * (target - q), -limit, limit)
    np.testing.assert_allclose(data.qfrc_actuator[6:], 0.5 * (pd(first) + pd(second)), atol=1e-9)
    with pytest.raises(ValueError, match="24 actuators for 12 joints, not 1 per joint"):
        motors.set_pd_gains(model, 60.0, 3.0)  # the split is said, not guessed from the shapes
