"""HB40 locomotion environment on MJX: pure `reset(key)` / `step(state, action)`.

Follows brax's `Env` / `State` conventions (state.pipeline_state is the `mjx.Data`,
`state.info` a dict of per-episode variables), so brax's own wrappers and trainers can
drive it. The environment knows nothing of agents: it sees only actions and returns
observations.

Observation (thesis Table 4.1, trunk frame): 54 values for the joint-target approaches,
56 for the CPG approaches:
    [0:12]  joint angle - nominal pose (rad)           order FL, FR, RL, RR x hip, thigh, knee
    [12:24] joint velocity (rad/s) x 0.1
    [24:36] JT: predicted joint angle, the applied target - nominal pose (rad)
            CPG: predicted feet position, commanded foot positions - nominal ones (m) x 5
    [36:39] trunk linear acceleration, IMU accelerometer (m/s^2, includes gravity) x 0.1
    [39:42] trunk angular acceleration, gyro difference over a control period (rad/s^2) x 0.01
    [42:45] trunk linear velocity (m/s)
    [45:48] trunk angular velocity, IMU gyro (rad/s)
    [48:51] target velocities [vx, vy, yaw rate]
    [51:54] projected gravity (unit vector)
    [54:56] CPG only: CPG progress, the phase as (1 + sin, 1 + cos) / 2
The scale factors only bring each block to order one; `observation_layout` lists them.
"""

import contextlib
import dataclasses
import io

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

# mjx (also imported by brax) prints a note on stdout when its optional GPU backend, warp,
# is absent; this suite is CPU-first and keeps stdout for its own output.
with contextlib.redirect_stdout(io.StringIO()):
    from brax.envs.base import Env, State
    from mujoco import mjx

from mjx_badger import actions, rewards, robot, tasks

def observation_layout(action_space: actions.ActionSpace) -> tuple:
    """(name, size, scale) of every observation block for an approach's action space."""
    predicted = (("predicted_joint_angle", 12, 1.0) if action_space.predicted_name == "joint_angle"
                 else ("predicted_feet_position", 12, 5.0))
    layout = (
        ("joint_angle", 12, 1.0),
        ("joint_velocity", 12, 0.1),
        predicted,
        ("trunk_linear_acceleration", 3, 0.1),
        ("trunk_angular_acceleration", 3, 0.01),
        ("trunk_linear_velocity", 3, 1.0),
        ("trunk_angular_velocity", 3, 1.0),
        ("target_velocity", 3, 1.0),
        ("projected_gravity", 3, 1.0),
    )
    return layout + ((("cpg_progress", action_space.extra_size, 1.0),) if action_space.extra_size else ())


# A foot touches the floor when its sphere centre is within this of the sphere radius (flat ground).
CONTACT_TOLERANCE_M = 0.003


@dataclasses.dataclass(frozen=True)
class EnvConfig:
    """Static settings of the environment (thesis Table 5.1)."""

    control_hz: float = 40.0
    """Policy rate; physics runs at 200 Hz, so 40 Hz is 5 physics steps per action."""
    episode_seconds: float = 20.0
    """Episode length in simulated seconds (800 steps at 40 Hz, 400 at 20 Hz)."""
    action_delay: bool = True
    """Apply the Table 5.1 action delay |0.03 + e| s, e ~ N(0, 0.05^2), per control step."""
    delay_mean_s: float = 0.03
    delay_std_s: float = 0.05
    fall_tilt_rad: float = 0.8
    """A fall: roll or pitch beyond this (about 46 degrees) ..."""
    fall_height_m: float = 0.15
    """... or the trunk centre below this height (trunk or hips at the floor; standing is 0.34 m)."""

    @property
    def substeps(self) -> int:
        """Physics steps per control step."""
        return int(round(1.0 / (self.control_hz * robot.PHYSICS_DT)))

    @property
    def control_dt(self) -> float:
        return self.substeps * robot.PHYSICS_DT

    @property
    def episode_steps(self) -> int:
        return int(round(self.episode_seconds / self.control_dt))


class HB40Env(Env):
    """The HB40 on flat ground with one approach (action pipeline) and one task."""

    def __init__(self, approach: str = "jt-nf", task: "str | tasks.Task" = "forward", config: EnvConfig | None = None):
        self.config = EnvConfig() if config is None else config
        self.action_space = actions.make_action_space(approach, self.config.control_dt)
        self.task = tasks.make_task(task) if isinstance(task, str) else task
        self.observation_layout = observation_layout(self.action_space)
        self.mj_model = robot.load_model(split_pd=self.action_space.split_pd)
        self.mjx_model = mjx.put_model(self.mj_model)
        self._trunk = self.mj_model.body("trunk").id
        self._feet = np.array([self.mj_model.geom(name).id for name in robot.FOOT_GEOMS])
        self._foot_radius = float(self.mj_model.geom_size[self._feet[0], 0])
        self._accel = robot.sensor_slice(self.mj_model, "accelerometer")
        self._gyro = robot.sensor_slice(self.mj_model, "gyro")
        data = mujoco.MjData(self.mj_model)
        data.qpos[:] = robot.standing_qpos(self.mj_model)
        data.ctrl[:] = self.action_space.rest_ctrl()
        mujoco.mj_forward(self.mj_model, data)
        self._init_data = mjx.put_data(self.mj_model, data)
        self._nominal = jnp.asarray(robot.NOMINAL_POSE)
        self._obs_scale = jnp.asarray(np.concatenate(
            [np.full(size, scale) for _, size, scale in self.observation_layout]).astype(np.float32))

    @property
    def observation_size(self) -> int:
        return int(self._obs_scale.size)

    @property
    def action_size(self) -> int:
        return self.action_space.size

    @property
    def backend(self) -> str:
        return "mjx"

    def reset(self, rng: jax.Array, command: jax.Array | None = None) -> State:
        """A new episode: robot standing in the nominal pose, a command from the task (or `command`)."""
        key, command_key = jax.random.split(rng)
        task_state, drawn = self.task.command(self.task.init(), command_key)
        command = drawn if command is None else jnp.asarray(command, dtype=jnp.float32)
        data, obs, episode = self._fresh_episode(command)
        info = {
            "rng": key,
            **episode,
            "task_state": task_state,
            "falls": jnp.int32(0),
            "terminated": jnp.bool_(False),
            "truncated": jnp.bool_(False),
            "next_obs": obs,
        }
        metrics = {name: jnp.float32(0.0) for name in self._metric_names()}
        return State(data, obs, jnp.float32(0.0), jnp.float32(0.0), metrics, info)

    def step(self, state: State, action: jax.Array) -> State:
        """One control step: act, run the delayed PD physics, score, auto-reset."""
        return self.traced_step(state, action)[0]

    def traced_step(self, state: State, action: jax.Array):
        """`step`, also returning the physics-rate trace: foot contacts (substeps, 4), forward velocity (substeps,)."""
        info = state.info
        key, delay_key, reset_key = jax.random.split(info["rng"], 3)
        action_state, target = self.action_space.step(info["action_state"], action)
        delay_steps = self._delay_steps(delay_key)
        previous_target = info["target"]

        def physics_step(data, i):
            # The new target reaches the motors only after the sampled delay (Table 5.1).
            ctrl = jnp.where(i < delay_steps, previous_target, target)
            data = mjx.step(self.mjx_model, data.replace(ctrl=ctrl))
            return data, self._trace(data)

        data, trace = jax.lax.scan(physics_step, state.pipeline_state, jnp.arange(self.config.substeps))
        command = info["command"]
        obs, motion = self._observe(data, action_state, command, info["prev_gyro"])
        reward, contributions = self.task.reward(motion, command)
        task_state = self.task.update(info["task_state"], command, motion)

        height = data.qpos[2]
        terminated = (
            (jnp.abs(motion.roll) > self.config.fall_tilt_rad)
            | (jnp.abs(motion.pitch) > self.config.fall_tilt_rad)
            | (height < self.config.fall_height_m)
            | ~jnp.all(jnp.isfinite(obs))
        )
        step = info["step"] + 1
        truncated = (step >= self.config.episode_steps) & ~terminated
        done = terminated | truncated

        along, lateral = rewards.along_and_lateral(motion.linear_velocity[:2], command[:2])
        metrics = {f"reward/{name}": value for name, value in contributions.items()}
        metrics.update(
            forward_velocity=motion.linear_velocity[0],
            lateral_velocity=motion.linear_velocity[1],
            yaw_rate=motion.angular_velocity[2],
            height=height,
            desired_velocity=along,
            command_lateral_velocity=lateral,
            desired_error=jnp.abs(along - jnp.linalg.norm(command[:2])),
            **self.task.progress(task_state),
        )
        info = dict(
            info,
            rng=key,
            action_state=action_state,
            target=target,
            prev_gyro=data.sensordata[self._gyro],
            step=step,
            task_state=task_state,
            falls=info["falls"] + terminated.astype(jnp.int32),
            terminated=terminated,
            truncated=truncated,
            next_obs=obs,
        )
        state = State(data, obs, reward, done.astype(jnp.float32), metrics, info)
        return self._auto_reset(state, reset_key), trace

    def _fresh_episode(self, command):
        """Initial physics data, observation and per-episode info of an episode under `command`."""
        data = self._init_data
        action_state = self.action_space.init()
        gyro = data.sensordata[self._gyro]
        obs, _ = self._observe(data, action_state, command, gyro)
        episode = {"action_state": action_state, "target": self.action_space.rest_ctrl(), "command": command,
                   "prev_gyro": gyro, "step": jnp.int32(0)}
        return data, obs, episode

    def _auto_reset(self, state: State, key: jax.Array) -> State:
        """Replace a finished episode by a fresh one; the task state (curriculum), fall count and
        `info['next_obs']` (the finished episode's last observation) carry over."""
        done = state.done > 0
        task_state, command = self.task.command(state.info["task_state"], key)
        data, obs, episode = self._fresh_episode(command)
        pick = lambda new, old: jax.tree.map(lambda a, b: jnp.where(done, a, b), new, old)
        info = dict(state.info, **pick(episode, {k: state.info[k] for k in episode}),
                    task_state=pick(task_state, state.info["task_state"]))
        return state.replace(pipeline_state=pick(data, state.pipeline_state), obs=pick(obs, state.obs), info=info)

    def _delay_steps(self, key):
        """Physics steps before a new target takes effect, capped at one control period."""
        if not self.config.action_delay:
            return 0
        delay = jnp.abs(self.config.delay_mean_s + self.config.delay_std_s * jax.random.normal(key))
        return jnp.clip(jnp.round(delay / robot.PHYSICS_DT), 0, self.config.substeps).astype(jnp.int32)

    def _trace(self, data):
        """Foot contact flags (4,) and trunk-frame forward velocity at one physics step."""
        contact = data.geom_xpos[self._feet, 2] <= self._foot_radius + CONTACT_TOLERANCE_M
        forward = data.xmat[self._trunk][:, 0] @ data.qvel[:3]
        return contact, forward

    def _observe(self, data, action_state, command, prev_gyro):
        """Observation vector and the raw trunk motion the reward needs."""
        rot = data.xmat[self._trunk]  # body-to-world
        linear_velocity = rot.T @ data.qvel[:3]
        gyro = data.sensordata[self._gyro]
        gravity = rot.T @ jnp.array([0.0, 0.0, -1.0])
        roll = jnp.arctan2(rot[2, 1], rot[2, 2])
        pitch = jnp.arcsin(jnp.clip(-rot[2, 0], -1.0, 1.0))
        obs = self.observation(data.qpos[7:], data.qvel[6:], action_state, data.sensordata[self._accel], gyro,
                               prev_gyro, linear_velocity, command, gravity)
        motion = tasks.Motion(linear_velocity, gyro, roll, pitch, data.qfrc_actuator[6:])
        return obs, motion

    def observation(self, joint_angle, joint_velocity, action_state, acceleration, angular_velocity,
                    prev_angular_velocity, linear_velocity, command, gravity):
        """The Table 4.1 observation from measured quantities; the on-robot loop builds it the same way."""
        predicted, extra = self.action_space.observe(action_state)
        return jnp.concatenate([
            joint_angle - self._nominal,
            joint_velocity,
            predicted,
            acceleration,
            (angular_velocity - prev_angular_velocity) / self.config.control_dt,
            linear_velocity,
            angular_velocity,
            command,
            gravity,
            extra,
        ]) * self._obs_scale

    def _metric_names(self):
        names = [f"reward/{name}" for name in self.task.weights]
        names += ["forward_velocity", "lateral_velocity", "yaw_rate", "height", "desired_velocity",
                  "command_lateral_velocity", "desired_error"]
        return names + list(self.task.progress(self.task.init()))
