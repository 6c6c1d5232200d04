"""HB40 locomotion environment on MJX: pure `reset(key)` / `step(state, action)`.

Follows brax's `Env` / `State` conventions (state.pipeline_state is the `mjx.Data`,
`state.info` a dict of per-episode variables). brax's own trainers drive it through
`brax_compat.wrap` (the env ends and resets its own episodes; brax_compat says why). The
environment knows nothing of agents: it sees only actions and returns observations. Everything on which the thesis's code and text differ comes from the
protocol in `EnvConfig` (protocols.py).

Its observation is observation.py's (Table 4.1), its termination termination.py's; both are mixed into
HB40Env here, with the physics, the reward, the metrics and the resets.
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


from mjx_badger.control import actions
from mjx_badger.estimation import estimators, sensors
from mjx_badger.protocol import protocols
from mjx_badger.protocol.conditions import SIM, Conditions
from mjx_badger.protocol.protocols import Protocol
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf, motors, terrain
from mjx_badger.sim.observation import Observing, observation_layout
from mjx_badger.sim.termination import Terminating
from mjx_badger.tasks import locomotion as tasks
from mjx_badger.tasks import rewards

# A foot touches the floor when its sphere centre is within this of the sphere radius (flat ground).
CONTACT_TOLERANCE_M = 0.003


@dataclasses.dataclass(frozen=True)
class EnvConfig:
    """Static settings of the environment: the protocol and the control rate it gives an approach."""

    control_hz: float | None = None
    """Policy rate; None: the protocol's rate for the approach, trained by CrossQ. Physics runs at 200 Hz."""
    protocol: Protocol = protocols.THESIS_CODE
    """Every choice on which the thesis's code and text differ (protocols.py)."""
    sensing: sensors.Sensing | None = None
    """The robot's own senses: noisy sensors and its velocity estimate, reported beside the truth (None: the
    conditions' own)."""
    conditions: Conditions | None = None
    """On-robot conditions (conditions.py: office, outdoor); None is `sim`, the simulation chapter's."""

    def rate(self, approach: str) -> float:
        """The control rate of `approach` under this configuration."""
        if self.control_hz is not None:
            return self.control_hz
        return self.protocol.control_hz(actions.is_cpg(approach), "crossq")


class HB40Env(Observing, Terminating, Env):
    """The HB40 on flat ground with one approach (action pipeline) and one task."""

    def __init__(self, approach: str = "jt-nf", task: "str | tasks.Task" = "forward", config: EnvConfig | None = None,
                 spec: robot.RobotSpec = robot.HB40, approach_params: tuple = ()):
        self.config = EnvConfig() if config is None else config
        self.protocol = self.config.protocol
        self.spec = spec
        self.control_hz = self.config.rate(approach)
        self.substeps = int(round(1.0 / (self.control_hz * spec.physics_dt)))
        self.control_dt = self.substeps * spec.physics_dt
        self.episode_steps = int(round(self.protocol.episode_seconds / self.control_dt))
        self.is_cpg = actions.is_cpg(approach)
        self.terminates = self.protocol.cpg_terminates or not self.is_cpg
        self.conditions = self.config.conditions or SIM
        self.conditions.validate()
        self.action_space = actions.make_action_space(approach, self.control_dt, self.protocol, spec,
                                                      self.conditions, **dict(approach_params))  # as on its robot
        if isinstance(task, str):
            task = tasks.make_task(task, self.protocol.rewards, self.protocol.curriculum)
        self.task = task
        self.observation_layout = observation_layout(self.action_space, self.protocol)
        self.ground = self.conditions.ground
        self.mj_model = mjcf.load_model(spec, split_pd=self.action_space.split_pd, ground=self.ground)
        motors.set_pd_gains(self.mj_model, *self.protocol.pd_gains(self.is_cpg), split_pd=self.action_space.split_pd)
        # Under jax.distributed, on this process's own device: mjx's default, jax.devices()[0], is process 0's.
        local = jax.local_devices()[0] if jax.process_count() > 1 else None
        self.mjx_model = mjx.put_model(self.mj_model, device=local)
        self._kp, self._kd = self.protocol.pd_gains(self.is_cpg)
        self._trunk = self.mj_model.body("trunk").id
        self._feet = np.array([self.mj_model.geom(name).id for name in spec.foot_geoms])
        self._accel = mjcf.sensor_slice(self.mj_model, "accelerometer")
        self._gyro = mjcf.sensor_slice(self.mj_model, "gyro")
        self.sensing = self.config.sensing or self.conditions.sensing
        # Only what the conditions change enters the program: under `sim` it is the one it always was.
        self._varies_friction = self.ground.friction != (spec.friction, spec.friction)
        self._pushes = self.conditions.push_newtons > 0
        if self.sensing is not None:
            self._estimator = estimators.make(self.sensing.estimator, self.sensing.kalman, spec,
                                              self.sensing.estimator_file)
        self._trunk_half = jnp.asarray(spec.trunk_half_size)
        data = mujoco.MjData(self.mj_model)
        data.qpos[:] = robot.standing_qpos(self.mj_model, spec)
        data.ctrl[:] = self.action_space.rest_ctrl()
        mujoco.mj_forward(self.mj_model, data)
        self._init_data = mjx.put_data(self.mj_model, data, device=local)
        self._nominal = jnp.asarray(robot.nominal_pose(spec))
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

    def reset(self, rng: jax.Array, command: jax.Array | None = None, task_state=None) -> State:
        """A new episode: robot above its nominal pose at the home height, a command from the task (or `command`).

        `task_state` carries a curriculum over from earlier episodes (native.py's resets); None starts it afresh."""
        key, command_key = jax.random.split(rng)
        task_state, drawn = self.task.command(self.task.init() if task_state is None else task_state, command_key)
        command = drawn if command is None else jnp.asarray(command, dtype=jnp.float32)
        if self._varies_friction or self._pushes:
            key, ground_key = jax.random.split(key)
            data, obs, episode = self._fresh_episode(command, ground_key)
        else:
            data, obs, episode = self._fresh_episode(command)
        if self.sensing is not None:
            # The IMU's biases are the robot's: drawn once, carried across its episodes.
            key, bias_key = jax.random.split(key)
            episode["sensor_state"] = sensors.init(self.sensing.sensors, bias_key)
        info = {
            "rng": key,
            **episode,
            "task_state": task_state,
            "falls": jnp.int32(0),
            "would_falls": jnp.int32(0),
            **self.stop_counts(),
            "blowups": jnp.int32(0),
            "blew_up": jnp.bool_(False),
            "fallen": jnp.bool_(False),
            "terminated": jnp.bool_(False),
            "truncated": jnp.bool_(False),
            "next_obs": obs,
        }
        metrics = {name: jnp.float32(0.0) for name in self._metric_names()}
        return State(data, obs, jnp.float32(0.0), jnp.float32(0.0), metrics, info)

    def step(self, state: State, action: jax.Array) -> State:
        """One control step: act, run the PD physics, score, auto-reset."""
        return self.traced_step(state, action)[0]

    def traced_step(self, state: State, action: jax.Array):
        """`step`, also returning the physics-rate trace: foot contacts (substeps, 4), forward velocity (substeps,)."""
        keys, action_state, target, delay_steps = self.begin_step(state.info, action)
        previous_target = state.info["target"]
        clip = self.protocol.joint_velocity_clip

        model, push = self._ground_model(state.info), self._push(state.info)

        def physics_step(carry, i):
            data, _ = carry
            # The new target reaches the motors only after the sampled delay (Table 5.1).
            ctrl = jnp.where(i < delay_steps, previous_target, target)
            torque = self.pd_torque(ctrl, data.qpos, data.qvel)
            data = data.replace(ctrl=ctrl) if push is None else data.replace(ctrl=ctrl, xfrc_applied=push)
            with jax.named_scope("mjx_step"):  # op names only: benchmarks/bench_compile.py counts the copies
                data = mjx.step(model, data)
            if clip is not None:
                data = data.replace(qvel=data.qvel.at[6:].set(jnp.clip(data.qvel[6:], -clip, clip)))
            imu = data.sensordata[self._accel] if self.sensing is not None else None
            return (data, torque), (self._trace(data), imu)

        # The torque carry starts from `target` so that under vmap it is batched from the start: an unbatched
        # carry that turns batched makes vmap batch the whole MJX step a second time (seconds of tracing).
        (data, torque), (trace, imu) = jax.lax.scan(physics_step, (state.pipeline_state, 0.0 * target[:12]),
                                                    jnp.arange(self.substeps))
        acceleration = None if imu is None else jnp.mean(imu, axis=0)
        state = self.end_step(state, data, action_state, target, torque, keys[0], acceleration)
        return self._auto_reset(state, keys[1]), trace

    def _ground_model(self, info: dict):
        """The MJX model with this episode's ground friction on every floor pair (the model itself if it never varies)."""
        if not self._varies_friction:
            return self.mjx_model
        friction = self.mjx_model.pair_friction.at[:, :2].set(info["friction"])
        return self.mjx_model.replace(pair_friction=friction)

    def _push(self, info: dict):
        """(bodies, 6) external wrench: the episode's wind on the trunk (None without wind)."""
        if not self._pushes:
            return None
        return jnp.zeros((self.mj_model.nbody, 6)).at[self._trunk, :3].set(info["push"])

    def begin_step(self, info: dict, action: jax.Array):
        """A control step before its physics: (next key, reset key), the action pipeline's state and new
        target, and the physics steps the target waits (the action delay). Native MuJoCo shares it."""
        key, delay_key, reset_key = jax.random.split(info["rng"], 3)
        action_state, target = self.action_space.step(info["action_state"], action)
        return (key, reset_key), action_state, target, self._delay_steps(delay_key)

    def pd_torque(self, ctrl, qpos, qvel):
        """The PD torque before the motor limit: what the released code's power rule and energy term see."""
        return self._kp * (ctrl[:12] - qpos[7:]) - self._kd * qvel[6:]

    def end_step(self, state: State, data, action_state, target, torque, key: jax.Array, acceleration=None) -> State:
        """A control step after its physics, before any reset: observe, score, terminate, count and report.

        `data` is the mjx.Data, or native MuJoCo's view of the same fields (native.py); `acceleration` the
        accelerometer's mean over the step's physics (only read when the env senses)."""
        info = state.info
        senses = self._sense(info, data, acceleration, key) if self.sensing is not None else {}
        command = info["command"]
        obs, motion = self._observe(data, action_state, command, info["prev_gyro"], torque, senses)
        obs, reward, contributions, sensed, finite = self._score(obs, motion, senses, command)
        task_state = self.task.update(info["task_state"], command, sensed)
        power_steps = self._power_steps(info, data, torque)
        fallen, terminated, truncated = self._terminate(info, data, motion, senses, power_steps, finite)
        done = terminated | truncated
        metrics = self._metrics(state.metrics, data, motion, command, contributions, task_state, senses)
        info = dict(
            info,
            rng=key,
            action_state=action_state,
            target=target,
            prev_gyro=senses["reading"].angular_velocity if senses else data.sensordata[self._gyro],
            power_steps=power_steps,
            step=info["step"] + 1,
            task_state=task_state,
            falls=info["falls"] + (terminated & finite).astype(jnp.int32),
            # A would-be fall is counted when the rule starts firing, not for every step it keeps firing.
            would_falls=info["would_falls"] + (fallen & ~info["fallen"]).astype(jnp.int32),
            fallen=fallen & ~done,
            blowups=info["blowups"] + (~finite).astype(jnp.int32),
            blew_up=~finite,
            terminated=terminated,
            truncated=truncated,
            next_obs=obs,
            **senses,
            **self.stop_counts(info, data, fallen),  # §6.4: the robot's stops that came before any fall
        )
        return State(data, obs, reward, done.astype(jnp.float32), metrics, info)

    def _score(self, obs, motion, senses: dict, command):
        """The reward and its terms, the observation and reward cleaned of a blow-up's NaNs, the motion the task
        sees (on the robot the estimate, §5.2; the metrics keep the truth) and whether the step stayed finite."""
        sensed = motion._replace(linear_velocity=senses["estimate"]) if self.conditions.estimate_in_loop else motion
        reward, contributions = self.task.reward(sensed, command)
        # A physics blow-up (non-finite state) ends the episode under any protocol, and its NaNs must
        # not reach the replay buffer: a NaN next observation poisons the critic's target even at
        # discount 0. It is stored as zeros and counted in `blowups`.
        finite = jnp.all(jnp.isfinite(obs)) & jnp.isfinite(reward)
        obs, reward = jnp.where(finite, obs, 0.0), jnp.where(finite, reward, 0.0)
        return obs, reward, contributions, sensed, finite

    def _metrics(self, metrics: dict, data, motion, command, contributions: dict, task_state, senses: dict) -> dict:
        """The step's metrics (`_metric_names`): reward terms, true motion, the task's progress and, where the env
        senses, the estimate's. Keys a wrapper added (brax's evaluator adds `reward`) are kept: a scan's carry
        keeps its structure."""
        along, lateral = rewards.along_and_lateral(motion.linear_velocity[:2], command[:2])
        metrics = dict(metrics, **{f"reward/{name}": value for name, value in contributions.items()})
        metrics.update(
            forward_velocity=motion.linear_velocity[0],
            lateral_velocity=motion.linear_velocity[1],
            yaw_rate=motion.angular_velocity[2],
            height=data.qpos[2],
            desired_velocity=along,
            command_lateral_velocity=lateral,
            desired_error=jnp.abs(along - jnp.linalg.norm(command[:2])),
            **self.task.progress(task_state),
        )
        if senses:
            metrics.update(estimated_forward_velocity=senses["estimate"][0],
                           estimated_lateral_velocity=senses["estimate"][1],
                           estimated_desired_velocity=rewards.along_and_lateral(senses["estimate"][:2], command[:2])[0])
        return metrics

    def _fresh_episode(self, command, key=None):
        """Initial physics data, observation and per-episode info of an episode under `command`; `key` draws
        the episode's ground friction and wind where the conditions vary them."""
        data = self._init_data
        action_state = self.action_space.init()
        gyro = data.sensordata[self._gyro]
        obs, _ = self._observe(data, action_state, command, gyro, jnp.zeros(12))
        episode = {"action_state": action_state, "target": self.action_space.rest_ctrl(), "command": command,
                   "prev_gyro": gyro, "step": jnp.int32(0), "power_steps": jnp.int32(0)}
        if self._varies_friction:
            low, high = self.ground.friction
            episode["friction"] = jax.random.uniform(jax.random.fold_in(key, 0), minval=low, maxval=high)
        if self._pushes:
            heading = jax.random.uniform(jax.random.fold_in(key, 1), maxval=2 * jnp.pi)
            episode["push"] = self.conditions.push_newtons * jnp.array([jnp.cos(heading), jnp.sin(heading), 0.0])
        if self.sensing is not None:  # a reset recalibrates the estimator: standing still, and sure of it
            truth = sensors.truth(data, self._trunk, data.sensordata[self._accel], gyro, jnp.zeros(12))
            _, reading = sensors.read(sensors.EXACT, sensors.init(sensors.EXACT), truth, sensors.no_draws(),
                                      self.control_dt)
            episode.update(estimator_state=self._estimator.init(), estimate=jnp.zeros(3), reading=reading)
        return data, obs, episode

    def _auto_reset(self, state: State, key: jax.Array) -> State:
        """Replace a finished episode by a fresh one; the task state (curriculum), fall counts and
        `info['next_obs']` (the finished episode's last observation) carry over."""
        done = state.done > 0
        if self._varies_friction or self._pushes:
            key, ground_key = jax.random.split(key)
            task_state, command = self.task.command(state.info["task_state"], key)
            data, obs, episode = self._fresh_episode(command, ground_key)
        else:
            task_state, command = self.task.command(state.info["task_state"], key)
            data, obs, episode = self._fresh_episode(command)
        pick = lambda new, old: jax.tree.map(lambda a, b: jnp.where(done, a, b), new, old)
        info = dict(state.info, **pick(episode, {k: state.info[k] for k in episode}),
                    task_state=pick(task_state, state.info["task_state"]))
        return state.replace(pipeline_state=pick(data, state.pipeline_state), obs=pick(obs, state.obs), info=info)

    def _delay_steps(self, key):
        """Physics steps before a new target takes effect (Table 5.1), capped at one control period."""
        if not self.protocol.action_delay:
            return 0
        delay = jnp.abs(0.03 + 0.05 * jax.random.normal(key))
        return jnp.clip(jnp.round(delay / self.spec.physics_dt), 0, self.substeps).astype(jnp.int32)

    def _trace(self, data):
        """Foot contact flags (4,) and trunk-frame forward velocity at one physics step."""
        feet = data.geom_xpos[self._feet]
        floor = terrain.height_at(self.ground, feet[:, 0]) if self.ground.incline_deg else 0.0
        relief = self.ground.relief_m if self.ground.terrain != "flat" else 0.0
        contact = feet[:, 2] - floor <= self.spec.foot_radius + CONTACT_TOLERANCE_M + relief
        forward = data.xmat[self._trunk][:, 0] @ data.qvel[:3]
        return contact, forward

    def _metric_names(self):
        names = [f"reward/{name}" for name in self.task.weights]
        names += ["forward_velocity", "lateral_velocity", "yaw_rate", "height", "desired_velocity",
                  "command_lateral_velocity", "desired_error"]
        if self.sensing is not None:
            names += ["estimated_forward_velocity", "estimated_lateral_velocity", "estimated_desired_velocity"]
        return names + list(self.task.progress(self.task.init()))
