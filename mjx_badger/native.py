"""A policy evaluated on native MuJoCo, or on MJX for comparison, under one fixed command.

Native MuJoCo runs the env's own model file (`env.mj_model`, its gains set by the protocol),
its action pipeline, observation and fall rule (the same jitted functions the MJX env uses),
and steps the physics with `mujoco.mj_step` as the env's control step does with `mjx.step`:
the new targets after the protocol's action delay, joint velocities clipped where the
protocol clips them. Both engines report the same figures: the velocity along and across the
command and the yaw rate, measured from the trunk's positions and heading over the run (a
fall's reset starts a new stretch), falls, and the gait frequency of the foot contacts.
"""

import dataclasses
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger import analysis, robot
from mjx_badger.env import CODE_POWER_LIMIT_W, CONTACT_TOLERANCE_M, HB40Env


class _Data(NamedTuple):
    """The fields of MjData the env's observation and fall rule read, shaped as mjx.Data has them."""

    qpos: np.ndarray
    qvel: np.ndarray
    qacc: np.ndarray
    sensordata: np.ndarray
    xmat: np.ndarray
    xpos: np.ndarray
    qfrc_actuator: np.ndarray


def _view(data: mujoco.MjData) -> _Data:
    return _Data(data.qpos.copy(), data.qvel.copy(), data.qacc.copy(), data.sensordata.copy(),
                 data.xmat.reshape(-1, 3, 3).copy(), data.xpos.copy(), data.qfrc_actuator.copy())


def _yaw(qpos) -> float:
    w, x, y, z = qpos[3:7]
    return float(np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))


class _Track:
    """Trunk positions and headings per control step, split into stretches at resets; contacts at the physics rate."""

    def __init__(self):
        self.displacement, self.turn, self.contacts, self.falls = np.zeros(2), 0.0, [], 0

    def step(self, before, after, fell: bool):
        if not fell:  # a fall's reset moves the trunk back to the start: no displacement of its own
            self.displacement += np.asarray(after[:2] - before[:2])
            self.turn += np.angle(np.exp(1j * (_yaw(after) - _yaw(before))))
        self.falls += int(fell)

    def summary(self, command, seconds: float, physics_dt: float) -> dict:
        direction = np.asarray(command[:2]) / max(np.linalg.norm(command[:2]), 1e-9)
        if not np.any(command[:2]):
            direction = np.array([1.0, 0.0])  # no command: report forward and sideways
        velocity = self.displacement / seconds
        return {"seconds": seconds, "command": [float(c) for c in command],
                "velocity_along_command": float(velocity @ direction),
                "velocity_across_command": float(velocity @ np.array([-direction[1], direction[0]])),
                "yaw_rate": float(self.turn / seconds), "falls": self.falls,
                "gait_hz": analysis.gait_frequency(np.asarray(self.contacts), physics_dt)}


def evaluation_env(config, seconds: float) -> HB40Env:
    """The env of a run's TrainConfig with one episode as long as the evaluation (only a fall resets it)."""
    env_config = config.env_config
    protocol = env_config.protocol.replace(episode_seconds=seconds + 1.0)
    return HB40Env(config.approach, config.make_task(), dataclasses.replace(env_config, protocol=protocol),
                   config.robot_spec, config.approach_params)


def run_mjx(env: HB40Env, act: Callable, command, seconds: float, seed: int = 0) -> dict:
    """`act(observation) -> action` for `seconds` on the MJX env under `command`."""
    step = jax.jit(env.traced_step)
    state = env.reset(jax.random.PRNGKey(seed), jnp.asarray(command, jnp.float32))
    track = _Track()
    for _ in range(int(round(seconds / env.control_dt))):
        before = np.asarray(state.pipeline_state.qpos)
        state, (contacts, _) = step(state, jnp.asarray(act(np.asarray(state.obs))))
        track.step(before, np.asarray(state.pipeline_state.qpos), bool(state.info["terminated"]))
        track.contacts.extend(np.asarray(contacts))
    return track.summary(np.asarray(command), seconds, env.spec.physics_dt)


def run_native(env: HB40Env, act: Callable, command, seconds: float, seed: int = 0,
               on_step: Callable | None = None) -> dict:
    """`act(observation) -> action` for `seconds` on native MuJoCo, the env's model and pipelines, under `command`.

    `on_step(model, data)` sees the physics after every control step (videos draw from it).
    """
    model, spec, protocol = env.mj_model, env.spec, env.protocol
    data = mujoco.MjData(model)
    command = jnp.asarray(command, jnp.float32)
    observe = jax.jit(env._observe)
    fall = jax.jit(env._fall_rule)
    pipeline = jax.jit(env.action_space.step)
    rng = np.random.default_rng(seed)
    feet = np.array([model.geom(name).id for name in spec.foot_geoms])

    def fresh():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = robot.standing_qpos(model, spec)
        data.ctrl[:] = np.asarray(env.action_space.rest_ctrl())
        mujoco.mj_forward(model, data)
        action_state = env.action_space.init()
        gyro = data.sensordata[env._gyro].copy()
        obs, _ = observe(_view(data), action_state, command, gyro, jnp.zeros(12))
        return action_state, np.asarray(env.action_space.rest_ctrl()), gyro, obs, 0

    action_state, previous_target, gyro, obs, power_steps = fresh()
    track = _Track()
    for _ in range(int(round(seconds / env.control_dt))):
        before = data.qpos.copy()
        action_state, target = pipeline(action_state, jnp.asarray(act(np.asarray(obs))))
        target = np.asarray(target)
        delay = (int(np.clip(round(abs(0.03 + 0.05 * rng.normal()) / spec.physics_dt), 0, env.substeps))
                 if protocol.action_delay else 0)
        for i in range(env.substeps):
            ctrl = previous_target if i < delay else target
            torque = env._kp * (ctrl[:12] - data.qpos[7:]) - env._kd * data.qvel[6:]
            data.ctrl[:] = ctrl
            mujoco.mj_step(model, data)
            if protocol.joint_velocity_clip is not None:
                data.qvel[6:] = np.clip(data.qvel[6:], -protocol.joint_velocity_clip, protocol.joint_velocity_clip)
            track.contacts.append(data.geom_xpos[feet, 2] <= spec.foot_radius + CONTACT_TOLERANCE_M)
        previous_target = target
        view = _view(data)
        obs, motion = observe(view, action_state, command, gyro, jnp.asarray(torque))
        gyro = view.sensordata[env._gyro]
        power_steps = power_steps + 1 if np.sum(np.abs(torque * data.qvel[6:])) > CODE_POWER_LIMIT_W else 0
        fallen = bool(fall(view, motion, power_steps)) and env.terminates
        track.step(before, data.qpos.copy(), fallen)
        if on_step is not None:
            on_step(model, data)
        if fallen:
            action_state, previous_target, gyro, obs, power_steps = fresh()
    return track.summary(np.asarray(command), seconds, spec.physics_dt)
