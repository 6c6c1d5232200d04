"""A policy evaluated on native MuJoCo, or on MJX for comparison, under one fixed command.

`NativeEnv` runs the env's own model file (`env.mj_model`, its gains set by the protocol), its
reset and its own `begin_step` / `end_step` (action pipeline and delay; observation, reward,
termination and task), and steps the physics with `mujoco.mj_step` as the env's control step does
with `mjx.step`: the new targets after the action delay, joint velocities clipped where the
protocol clips them. The Gymnasium env (gym_env.py) is a thin shell around it. Both engines
report the same figures, from the trunk's positions and heading over the run (a fall's reset starts
a new stretch): the velocity in the heading frame (as training measures it) and in the world along
and across the command, the heading change and yaw rate, the path's verdict (a policy that circles
walks fast in its own frame and gets nowhere), falls, and the gait frequency of the foot contacts.
"""

import dataclasses
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf
from mjx_badger.sim.env import CONTACT_TOLERANCE_M, HB40Env
from mjx_badger.sim.gait import gait_frequency


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


TURNING_DEG = 30.0
"""Heading change past the command's own (its yaw rate x the seconds) from which a path is 'turning': past the
'good' yaw control of the real-world tables."""
CIRCLING_DEG = 180.0
"""From here on it is 'circling': it has walked at least half a circle, so its world displacement no longer shows
how fast it walks."""
DRIFTING_DEG = 15.0
"""Its heading held, a path more than this off the command's direction is 'drifting' (sideways or at an angle)."""
MOVING = 0.05
"""m/s: below this in both frames a policy stands, and has no path to judge."""


def path_verdict(command, heading_velocity, world_velocity, heading_change: float, seconds: float) -> tuple:
    """('standing' | 'straight' | 'drifting' | 'turning' | 'circling', one sentence saying why) of a run that walked
    `heading_velocity` in its heading frame and `world_velocity` along and across the command, its heading changing by
    `heading_change` rad against the command's own yaw rate."""
    unasked = np.degrees(abs(heading_change - command[2] * seconds))
    along, across = world_velocity
    heading_speed = float(np.linalg.norm(heading_velocity))
    walked = (f"it walked {heading_speed:.2f} m/s in its heading frame and {along:.2f} m/s along the command, "
              f"{across:.2f} across it")
    if heading_speed < MOVING and np.hypot(along, across) < MOVING:
        return "standing", f"standing: under {MOVING} m/s in both frames"
    if unasked >= CIRCLING_DEG:
        return "circling", f"circling: it turned {unasked:.0f} deg more than asked in {seconds:g} s; {walked}"
    if unasked >= TURNING_DEG:
        return "turning", f"turning: it turned {unasked:.0f} deg more than asked in {seconds:g} s; {walked}"
    # Off the command's direction in its own frame (crabbing), or, where the command holds the heading, in the world.
    asked = np.arctan2(command[1], command[0]) if np.any(command[:2]) else 0.0
    crab = np.degrees(abs(np.angle(np.exp(1j * (np.arctan2(heading_velocity[1], heading_velocity[0]) - asked)))))
    off = max(crab, np.degrees(abs(np.arctan2(across, along))) if command[2] == 0 else 0.0)
    if off > DRIFTING_DEG:
        return "drifting", f"drifting: its path runs {off:.0f} deg off the command; {walked}"
    return "straight", f"straight: within {TURNING_DEG:g} deg of its heading and {DRIFTING_DEG:g} of the command"


class _Track:
    """Trunk displacement per control step in the world and in the heading frame, split into stretches at resets;
    contacts at the physics rate."""

    def __init__(self):
        self.displacement, self.heading_displacement, self.turn = np.zeros(2), np.zeros(2), 0.0
        self.contacts, self.falls = [], 0
        self.estimates = []
        """The robot's own velocity estimate (trunk frame, x and y) per control step, where the env senses."""

    def step(self, before, after, fell: bool):
        if not fell:  # a fall's reset moves the trunk back to the start: no displacement of its own
            step = np.asarray(after[:2] - before[:2])
            turned = np.angle(np.exp(1j * (_yaw(after) - _yaw(before))))
            # Into the heading frame at the step's middle heading: forward and sideways as the body walked them.
            middle = _yaw(before) + turned / 2
            cos, sin = np.cos(middle), np.sin(middle)
            self.heading_displacement += np.array([cos * step[0] + sin * step[1], -sin * step[0] + cos * step[1]])
            self.displacement += step
            self.turn += turned
        self.falls += int(fell)

    def summary(self, command, seconds: float, physics_dt: float) -> dict:
        direction = np.asarray(command[:2]) / max(np.linalg.norm(command[:2]), 1e-9)
        if not np.any(command[:2]):
            direction = np.array([1.0, 0.0])  # no command: report forward and sideways
        across = np.array([-direction[1], direction[0]])
        velocity, heading_velocity = self.displacement / seconds, self.heading_displacement / seconds
        world = (float(velocity @ direction), float(velocity @ across))
        path, why = path_verdict(command, heading_velocity, world, self.turn, seconds)
        report = {"seconds": seconds, "command": [float(c) for c in command],
                  # As training measures it: the body's own forward and sideways speed, projected on the command
                  # (a body-frame command), whatever the heading does.
                  "heading_velocity_along_command": float(heading_velocity @ direction),
                  "heading_velocity_across_command": float(heading_velocity @ across),
                  "forward_velocity": float(heading_velocity[0]), "lateral_velocity": float(heading_velocity[1]),
                  # Where it got to: the world displacement along and across the command's first direction.
                  "velocity_along_command": world[0], "velocity_across_command": world[1],
                  "heading_change_deg": float(np.degrees(self.turn)),
                  "yaw_rate": float(self.turn / seconds), "path": path, "path_note": why, "falls": self.falls,
                  "gait_hz": gait_frequency(np.asarray(self.contacts), physics_dt)}
        if self.estimates:  # what the robot believed, beside what it walked (the thesis judged by video)
            report["estimated_velocity_along_command"] = float(np.mean(np.asarray(self.estimates) @ direction))
        return report


def evaluation_env(config, seconds: float, sensing=None) -> HB40Env:
    """The env of a run's TrainConfig with one episode as long as the evaluation (only a fall resets it), sensing
    with `sensing` (sensors.Sensing) if given."""
    env_config = config.env_config
    protocol = env_config.protocol.replace(episode_seconds=seconds + 1.0)
    sensing = env_config.sensing if sensing is None else sensing
    return HB40Env(config.approach, config.make_task(), dataclasses.replace(env_config, protocol=protocol, sensing=sensing),
                   config.robot_spec, config.approach_params)


def run_mjx(env: HB40Env, act: Callable, command, seconds: float, seed: int = 0) -> dict:
    """`act(observation) -> action` for `seconds` on the MJX env under `command`."""
    # A step's output is committed to its device and a reset's is not: committed alike, the step compiles once.
    reset = lambda key, command: jax.device_put(env.reset(key, command), jax.devices()[0])
    step = jax.jit(env.traced_step)
    state = reset(jax.random.PRNGKey(seed), jnp.asarray(command, jnp.float32))
    track = _Track()
    for _ in range(int(round(seconds / env.control_dt))):
        before = np.asarray(state.pipeline_state.qpos)
        state, (contacts, _) = step(state, jnp.asarray(act(np.asarray(state.obs))))
        track.step(before, np.asarray(state.pipeline_state.qpos), bool(state.info["terminated"]))
        track.contacts.extend(np.asarray(contacts))
        if bool(state.info["terminated"]):  # the env's own reset drew the task's command: start again under this one
            state = reset(jax.random.PRNGKey(seed + track.falls), jnp.asarray(command, jnp.float32))
    return track.summary(np.asarray(command), seconds, env.spec.physics_dt)


class NativeEnv:
    """One HB40 on native MuJoCo that steps as HB40Env does: the env's model file, its reset, and its own
    `begin_step` / `end_step` (action pipeline, delay, observation, reward, termination, task) around
    `mujoco.mj_step` in place of `mjx.step`. It does not reset itself: the caller does (Gymnasium's way)."""

    def __init__(self, env: HB40Env):
        self.env, self.model = env, env.mj_model
        self.data = mujoco.MjData(self.model)
        self._reset, self._begin, self._end = jax.jit(env.reset), jax.jit(env.begin_step), jax.jit(env.end_step)
        self._feet = np.array([self.model.geom(name).id for name in env.spec.foot_geoms])
        self._accelerometer = mjcf.sensor_slice(self.model, "accelerometer")
        self.state, self.reset_key, self.contacts = None, None, None

    def reset(self, key: jax.Array, command=None, task_state=None):
        """A new episode (HB40Env.reset); the physics at the env's initial state. Returns the brax State."""
        command = None if command is None else jnp.asarray(command, jnp.float32)
        state = self._reset(key, command, task_state)
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[:] = robot.standing_qpos(self.model, self.env.spec)
        self.data.ctrl[:] = np.asarray(self.env.action_space.rest_ctrl())
        mujoco.mj_forward(self.model, self.data)
        self.state = state.replace(pipeline_state=_view(self.data))
        return self.state

    def step(self, action):
        """One control step; `reset_key` is the key HB40Env's auto-reset would use, `contacts` the feet per substep."""
        env, data = self.env, self.data
        (key, self.reset_key), action_state, target, delay = self._begin(self.state.info, jnp.asarray(action))
        previous, target, delay = jax.device_get((self.state.info["target"], target, delay))  # one transfer
        clip, contacts, imu = env.protocol.joint_velocity_clip, [], np.zeros(3)
        for i in range(env.substeps):
            ctrl = previous if i < delay else target
            torque = env.pd_torque(ctrl, data.qpos, data.qvel)
            data.ctrl[:] = ctrl
            mujoco.mj_step(self.model, data)
            if clip is not None:
                data.qvel[6:] = np.clip(data.qvel[6:], -clip, clip)
            contacts.append(data.geom_xpos[self._feet, 2] <= env.spec.foot_radius + CONTACT_TOLERANCE_M)
            imu += data.sensordata[self._accelerometer]
        self.contacts = np.array(contacts)
        acceleration = jnp.asarray(imu / env.substeps, jnp.float32) if env.sensing is not None else None
        self.state = self._end(self.state, _view(data), action_state, target, jnp.asarray(torque), key, acceleration)
        return self.state


def run_native(env: HB40Env, act: Callable, command, seconds: float, seed: int = 0,
               on_step: Callable | None = None) -> dict:
    """`act(observation) -> action` for `seconds` on native MuJoCo, the env's model and pipelines, under `command`.

    `on_step(model, data)` sees the physics after every control step (videos draw from it).
    """
    native = NativeEnv(env)
    state = native.reset(jax.random.PRNGKey(seed), command)
    track = _Track()
    for _ in range(int(round(seconds / env.control_dt))):
        before = native.data.qpos.copy()
        state = native.step(act(np.asarray(state.obs)))
        track.step(before, native.data.qpos.copy(), bool(state.info["terminated"]))
        track.contacts.extend(native.contacts)
        if "estimate" in state.info:
            track.estimates.append(np.asarray(state.info["estimate"])[:2])
        if on_step is not None:
            on_step(native.model, native.data)
        if state.done:  # a fall (the episode is as long as the evaluation): start again under the same command
            state = native.reset(native.reset_key, command)
    return track.summary(np.asarray(command), seconds, env.spec.physics_dt)
