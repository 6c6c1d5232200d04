"""HB40 locomotion environment on MJX: pure `reset(key)` / `step(state, action)`.

Follows brax's `Env` / `State` conventions (state.pipeline_state is the `mjx.Data`,
`state.info` a dict of per-episode variables), so brax's own wrappers and trainers can
drive it. The environment knows nothing of agents: it sees only actions and returns
observations.

Observation for the joint-target approaches (thesis Table 4.1, 54 values, trunk frame):
    [0:12]  joint angle - nominal pose (rad)           order FL, FR, RL, RR x hip, thigh, knee
    [12:24] joint velocity (rad/s) x 0.1
    [24:36] predicted joint angle: applied target - nominal pose (rad)
    [36:39] trunk linear acceleration, IMU accelerometer (m/s^2, includes gravity) x 0.1
    [39:42] trunk angular acceleration, gyro difference over a control period (rad/s^2) x 0.01
    [42:45] trunk linear velocity (m/s)
    [45:48] trunk angular velocity, IMU gyro (rad/s)
    [48:51] target velocities [vx, vy, yaw rate]
    [51:54] projected gravity (unit vector)
The scale factors only bring each block to order one; they are listed in OBS_LAYOUT.
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

from mjx_badger import actions, robot, tasks

OBS_LAYOUT = (
    ("joint_angle", 12, 1.0),
    ("joint_velocity", 12, 0.1),
    ("predicted_joint_angle", 12, 1.0),
    ("trunk_linear_acceleration", 3, 0.1),
    ("trunk_angular_acceleration", 3, 0.01),
    ("trunk_linear_velocity", 3, 1.0),
    ("trunk_angular_velocity", 3, 1.0),
    ("target_velocity", 3, 1.0),
    ("projected_gravity", 3, 1.0),
)
OBS_SCALE = np.concatenate([np.full(size, scale) for _, size, scale in OBS_LAYOUT]).astype(np.float32)


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

    def __init__(self, approach: str = "jt-nf", task: str = "forward", config: EnvConfig | None = None):
        self.config = EnvConfig() if config is None else config
        self.action_space = actions.make_action_space(approach, self.config.control_dt)
        self.task = tasks.make_task(task)
        self.mj_model = robot.load_model()
        self.mjx_model = mjx.put_model(self.mj_model)
        self._trunk = self.mj_model.body("trunk").id
        self._accel = _sensor_slice(self.mj_model, "accelerometer")
        self._gyro = _sensor_slice(self.mj_model, "gyro")
        data = mujoco.MjData(self.mj_model)
        data.qpos[:] = robot.standing_qpos(self.mj_model)
        data.ctrl[:] = robot.NOMINAL_POSE
        mujoco.mj_forward(self.mj_model, data)
        self._init_data = mjx.put_data(self.mj_model, data)
        self._nominal = jnp.asarray(robot.NOMINAL_POSE)
        self._obs_scale = jnp.asarray(OBS_SCALE)

    @property
    def observation_size(self) -> int:
        return int(OBS_SCALE.size)

    @property
    def action_size(self) -> int:
        return self.action_space.size

    @property
    def backend(self) -> str:
        return "mjx"

    def reset(self, rng: jax.Array) -> State:
        """A new episode: robot standing in the nominal pose, a fresh command."""
        key, command_key = jax.random.split(rng)
        data = self._init_data
        command = self.task.command(command_key)
        gyro = data.sensordata[self._gyro]
        obs, _ = self._observe(data, self._nominal, command, gyro)
        info = {
            "rng": key,
            "action_state": self.action_space.init(),
            "target": self._nominal,
            "command": command,
            "prev_gyro": gyro,
            "step": jnp.int32(0),
            "falls": jnp.int32(0),
            "terminated": jnp.bool_(False),
            "truncated": jnp.bool_(False),
            "next_obs": obs,
        }
        metrics = {name: jnp.float32(0.0) for name in self._metric_names()}
        return State(data, obs, jnp.float32(0.0), jnp.float32(0.0), metrics, info)

    def step(self, state: State, action: jax.Array) -> State:
        """One control step: filter the action, run the delayed PD physics, score, auto-reset."""
        info = state.info
        key, delay_key, reset_key = jax.random.split(info["rng"], 3)
        action_state, target = self.action_space.step(info["action_state"], action)
        delay_steps = self._delay_steps(delay_key)
        previous_target = info["target"]

        def physics_step(data, i):
            # The new target reaches the motors only after the sampled delay (Table 5.1).
            ctrl = jnp.where(i < delay_steps, previous_target, target)
            return mjx.step(self.mjx_model, data.replace(ctrl=ctrl)), None

        data, _ = jax.lax.scan(physics_step, state.pipeline_state, jnp.arange(self.config.substeps))
        obs, motion = self._observe(data, target, info["command"], info["prev_gyro"])
        reward, contributions = self.task.reward(motion, info["command"])

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

        metrics = {f"reward/{name}": value for name, value in contributions.items()}
        metrics.update(
            forward_velocity=motion.linear_velocity[0],
            lateral_velocity=motion.linear_velocity[1],
            yaw_rate=motion.angular_velocity[2],
            height=height,
        )
        info = dict(
            info,
            rng=key,
            action_state=action_state,
            target=target,
            prev_gyro=data.sensordata[self._gyro],
            step=step,
            falls=info["falls"] + terminated.astype(jnp.int32),
            terminated=terminated,
            truncated=truncated,
            next_obs=obs,
        )
        state = State(data, obs, reward, done.astype(jnp.float32), metrics, info)
        return self._auto_reset(state, reset_key)

    def _auto_reset(self, state: State, key: jax.Array) -> State:
        """Replace a finished episode by a fresh one; `info['next_obs']` keeps its last observation."""
        fresh = self.reset(key)
        done = state.done > 0
        pick = lambda new, old: jax.tree.map(lambda a, b: jnp.where(done, a, b), new, old)
        keep = ("rng", "falls", "terminated", "truncated", "next_obs")
        info = {k: (v if k in keep else pick(fresh.info[k], v)) for k, v in state.info.items()}
        return state.replace(pipeline_state=pick(fresh.pipeline_state, state.pipeline_state),
                             obs=pick(fresh.obs, state.obs), info=info)

    def _delay_steps(self, key):
        """Physics steps before a new target takes effect, capped at one control period."""
        if not self.config.action_delay:
            return 0
        delay = jnp.abs(self.config.delay_mean_s + self.config.delay_std_s * jax.random.normal(key))
        return jnp.clip(jnp.round(delay / robot.PHYSICS_DT), 0, self.config.substeps).astype(jnp.int32)

    def _observe(self, data, target, command, prev_gyro):
        """Observation vector (54,) and the raw trunk motion the reward needs."""
        rot = data.xmat[self._trunk]  # body-to-world
        linear_velocity = rot.T @ data.qvel[:3]
        gyro = data.sensordata[self._gyro]
        gravity = rot.T @ jnp.array([0.0, 0.0, -1.0])
        roll = jnp.arctan2(rot[2, 1], rot[2, 2])
        pitch = jnp.arcsin(jnp.clip(-rot[2, 0], -1.0, 1.0))
        obs = jnp.concatenate([
            data.qpos[7:] - self._nominal,
            data.qvel[6:],
            target - self._nominal,
            data.sensordata[self._accel],
            (gyro - prev_gyro) / self.config.control_dt,
            linear_velocity,
            gyro,
            command,
            gravity,
        ]) * self._obs_scale
        motion = tasks.Motion(linear_velocity, gyro, roll, pitch, data.actuator_force)
        return obs, motion

    def _metric_names(self):
        names = [f"reward/{name}" for name in self.task.weights]
        return names + ["forward_velocity", "lateral_velocity", "yaw_rate", "height"]


def _sensor_slice(model: mujoco.MjModel, name: str) -> slice:
    sensor = model.sensor(name)
    return slice(int(sensor.adr[0]), int(sensor.adr[0] + sensor.dim[0]))
