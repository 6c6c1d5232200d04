"""The jitted tick: the robot observes and is scored as the environment does."""

import jax
import mujoco
import numpy as np

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.realtime import control
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.interface import Sensors
from mjx_badger.robot import mjcf

# Small and slow enough for a test: 20 Hz, a 32x32 CrossQ, 20 warm-up steps, 1 s evaluation.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=40, warmup_steps=20, control_hz=20.0,
                      eval_seconds=1.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))


def test_the_robot_observes_and_scores_as_the_environment_does():
    # A few simulated steps of the loop's own environment, then the same moment as a robot measures it:
    # encoders, IMU specific force, gyro and orientation, and the velocity (here the true one, standing
    # in for the estimate). The tick must give the observation and reward the policy was trained on.
    env, task, agent, tick, _, _ = control.build(TINY)
    step = jax.jit(env.step)
    state = jax.jit(env.reset)(jax.random.PRNGKey(1))
    for action in jax.random.uniform(jax.random.PRNGKey(2), (3, env.action_size), minval=-1.0, maxval=1.0):
        before, state = state, step(state, action)
    assert not state.done  # no auto-reset: state.obs is this step's observation
    data = state.pipeline_state
    # The env reads the trunk's rotation as the last physics step computed it (xmat), the IMU's orientation.
    rotation = np.asarray(data.xmat[env.mj_model.body("trunk").id], np.float64)
    orientation = np.zeros(4)
    mujoco.mju_mat2Quat(orientation, rotation.reshape(-1))
    sensor = lambda name: np.asarray(data.sensordata[mjcf.sensor_slice(env.mj_model, name)])
    sensors = Sensors(0.0, np.asarray(data.qpos[7:]), np.asarray(data.qvel[6:]), np.asarray(data.qfrc_actuator[6:]),
                      sensor("accelerometer"), sensor("gyro"), orientation)
    measured = control.measured_step(sensors, np.asarray(before.info["prev_gyro"]), rotation.T @ np.asarray(data.qvel[:3]))
    obs, reward, *_ = tick(agent.init(jax.random.PRNGKey(0)), state.info["action_state"], task.init(),
                           state.info["command"], measured, jax.random.PRNGKey(3), False)
    # float32 rounding: the robot's rotation passes through a quaternion (measured: 2e-7).
    np.testing.assert_allclose(obs, state.obs, rtol=0, atol=1e-5)
    np.testing.assert_allclose(reward, state.reward, rtol=0, atol=1e-5)
