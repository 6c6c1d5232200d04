"""The on-robot training loop: one robot, wall-clock control, the learner updating concurrently.

Main thread, every control period: read the sensors, estimate the trunk velocity, build the
observation, score the last action, check safety, act and send the joint targets, store the
transition, sleep to the next deadline. Learner thread: sample the replay buffer and update
the agent, at most `updates_per_step` times per learning step (or flat out, to measure what
the machine sustains). Both run the trainer's own pure functions, `agent.act` and
`agent.update`, jitted once at batch size 1; the observation and reward are the
environment's and the task's. A safety trip damps the motors first, ends the episode, counts
a fall and waits for the (manual) reset, which is not training time. Ctrl-C damps the robot,
then saves policy, optimiser state and replay buffer; the next run with the same settings
resumes from them.

Timing in the results (this session's periods): the period runs from one tick's start to the
next; wake is how long after its deadline a tick started (the scheduler and the GIL); work
runs from a tick's start to its sleep (read, estimate, act, command, store); a missed
deadline is a tick whose work ran past the next tick's start, so that its command was late.
"""

import dataclasses
import functools
import gc
import json
import signal
import sys
import threading
import time
from pathlib import Path

import flax.serialization
import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger import cpg, protocols, results, robot, tasks
from mjx_badger.actions import APPROACHES
from mjx_badger.agents import ALGORITHMS, AgentConfig, make_agent
from mjx_badger.agents.losses import Transition
from mjx_badger.env import EnvConfig, HB40Env
from mjx_badger.realtime import safety, scheduling
from mjx_badger.realtime.estimation import KalmanConfig, VelocityEstimator, leg_odometry
from mjx_badger.realtime.interface import Robot, Sensors, roll_pitch, rotation_matrix

SCHEMA = "mjx_badger.realtime/1"
LOG_EVERY_STEPS = 200
"""Steps per row of the results document (5 s at 40 Hz)."""
TRACE = ("step", "train_s", "estimated_vx", "estimated_vy", "true_vx", "true_vy", "reward", "fall")
"""Columns of the per-step trace saved beside the results document (<name>.trace.npy)."""


@dataclasses.dataclass(frozen=True)
class RealtimeConfig:
    """One on-robot training run."""

    approach: str = "jt-oef"
    algo: str = "crossq"
    task: str = "forward"
    target_velocity: float = 0.25
    """Forward task only: the thesis's office and outdoor runs asked for 0.25 m/s (§5.2)."""
    steps: int = 20_000
    warmup_steps: int = 1_000
    control_hz: float | None = None
    """None: the algorithm's rate (Table 4.3: 40 Hz CrossQ, 20 Hz the others)."""
    episode_seconds: float = 20.0
    planned_contacts: bool = False
    """Leg odometry from the CPG's planned stance legs instead of all four (CPG approaches only)."""
    updates_per_step: float | None = None
    """Learner cap in updates per learning step; None: the algorithm's replay ratio."""
    unthrottled: bool = False
    """The learner runs flat out (benchmarks: the most updates per step the machine sustains)."""
    eval_seconds: float = 10.0
    """Deterministic run after training, as the thesis's evaluation runs (0 skips it)."""
    seed: int = 0
    agent: AgentConfig | None = None
    """Agent settings; None means ALGORITHMS[algo]()."""

    @property
    def agent_config(self) -> AgentConfig:
        return ALGORITHMS[self.algo]() if self.agent is None else self.agent

    @property
    def hz(self) -> float:
        return self.agent_config.control_hz if self.control_hz is None else self.control_hz

    @property
    def utd(self) -> float:
        return self.agent_config.updates_per_step if self.updates_per_step is None else self.updates_per_step

    @property
    def name(self) -> str:
        return f"{self.approach}_{self.algo}_{self.task}"

    def validate(self) -> None:
        """Raise ValueError naming what is wrong, before anything compiles or moves."""
        if self.approach not in APPROACHES:
            raise ValueError(f"approach {self.approach!r} is not one of {sorted(APPROACHES)}")
        if self.approach == "cpg-rt":
            raise ValueError("cpg-rt averages two PD torques per joint, which only the simulator can do; "
                             "on a robot use cpg-rt-avg (averaged joint angles, what the thesis's robot ran) "
                             "or cpg-rt-sum")
        if self.algo not in ALGORITHMS:
            raise ValueError(f"algorithm {self.algo!r} is not one of {sorted(ALGORITHMS)}")
        if self.task not in tasks.TASKS:
            raise ValueError(f"task {self.task!r} is not one of {sorted(tasks.TASKS)}")
        if self.planned_contacts and not self.approach.startswith("cpg"):
            raise ValueError("planned contacts come from the CPG's phase; the joint-target approaches have none")
        physics_hz = round(1.0 / robot.HB40.physics_dt)
        if not 1.0 <= self.hz <= physics_hz:
            raise ValueError(f"control rate {self.hz} Hz must lie in [1, {physics_hz}] Hz")
        if self.steps < 1 or self.warmup_steps < 0:
            raise ValueError("steps must be positive and warm-up steps not negative")


class HostReplay:
    """Replay buffer in host memory: the control thread adds while the learner samples."""

    def __init__(self, capacity: int, obs_size: int, action_size: int):
        self.obs = np.zeros((capacity, obs_size), np.float32)
        self.action = np.zeros((capacity, action_size), np.float32)
        self.reward = np.zeros(capacity, np.float32)
        self.next_obs = np.zeros((capacity, obs_size), np.float32)
        self.discount = np.zeros(capacity, np.float32)
        self.size = 0
        self._lock = threading.Lock()

    def add(self, obs, action, reward, next_obs, discount) -> None:
        with self._lock:
            i = self.size % len(self.reward)
            self.obs[i], self.action[i], self.reward[i] = obs, action, reward
            self.next_obs[i], self.discount[i] = next_obs, discount
            self.size += 1

    def sample(self, rng: np.random.Generator, batch_size: int) -> Transition:
        with self._lock:
            index = rng.integers(0, min(self.size, len(self.reward)), batch_size)
            return Transition(self.obs[index], self.action[index], self.reward[index], self.next_obs[index],
                              self.discount[index])

    def save(self, path: Path) -> None:
        with self._lock:
            np.savez(path, obs=self.obs, action=self.action, reward=self.reward, next_obs=self.next_obs,
                     discount=self.discount, size=self.size)

    def load(self, path: Path) -> None:
        with np.load(path) as stored:
            for name in ("obs", "action", "reward", "next_obs", "discount"):
                getattr(self, name)[:] = stored[name]
            self.size = int(stored["size"])


class Learner(threading.Thread):
    """Updates the agent from the replay buffer while the robot walks; `state` is the latest agent."""

    def __init__(self, update, state, buffer: HostReplay, batch_size: int, key, allowed, updates: int = 0):
        super().__init__(name="learner", daemon=True)
        self.update, self.state, self.buffer = update, state, buffer
        self.batch_size, self.key, self.allowed = batch_size, key, allowed
        self.updates = updates
        self.metrics = {}
        self.halt = threading.Event()
        self.new_step = threading.Event()
        self._rng = np.random.default_rng(int(jax.random.randint(key, (), 0, 2**31 - 1)))

    def stop(self):
        self.halt.set()
        self.new_step.set()
        self.join()

    def run(self):
        while not self.halt.is_set():
            if not self.allowed(self.updates):
                # Sleep until the control thread stores a step: polling would take the GIL
                # thousands of times a second from the thread that must wake on time.
                self.new_step.wait(0.1)
                self.new_step.clear()
                continue
            batch = self.buffer.sample(self._rng, self.batch_size)
            state, metrics = self.update(self.state, batch, jax.random.fold_in(self.key, self.updates),
                                         jnp.int32(self.updates))
            self.state = jax.block_until_ready(state)
            self.metrics = metrics
            self.updates += 1


class Progress:
    """Counters of the run, kept in the checkpoint so a resumed run continues them."""

    def __init__(self, steps: int):
        self.step = 0
        self.falls = 0
        self.episodes = 0
        self.train_seconds = 0.0
        self.reset_seconds = 0.0
        self.rows: list[dict] = []
        # One TRACE row per step, preallocated: a growing list of tuples would be more objects for
        # every garbage collection pass to walk while the robot waits.
        self.trace = np.full((steps, len(TRACE)), np.nan)
        self.task_state = None
        self.key = None
        self.action_state = None


@functools.lru_cache(maxsize=4)
def build(config: RealtimeConfig):
    """Environment (observation, action pipeline, task), agent and the two jitted functions."""
    config.validate()
    task = tasks.forward(config.target_velocity) if config.task == "forward" else tasks.make_task(config.task)
    # The on-robot loop observes as a robot can (IMU with gravity, gyro differences): the thesis-text protocol.
    protocol = protocols.THESIS_TEXT.replace(episode_seconds=config.episode_seconds)
    env = HB40Env(config.approach, task, EnvConfig(control_hz=config.hz, protocol=protocol))
    agent = make_agent(config.agent_config, env.observation_size, env.action_size)
    has_cpg = config.approach.startswith("cpg")

    @jax.jit
    def tick(agent_state, action_state, task_state, command, joint_angle, joint_velocity, acceleration, gyro,
             prev_gyro, velocity, gravity, roll, pitch, torque, key, explore):
        """Observation and reward of the reading, then the next action and its joint targets."""
        obs = env.observation(joint_angle, joint_velocity, action_state, acceleration, gyro, prev_gyro, velocity,
                              command, gravity)
        motion = tasks.Motion(velocity, gyro, roll, pitch, torque)
        reward, _ = task.reward(motion, command)
        task_state = task.update(task_state, command, motion)
        act_key, explore_key = jax.random.split(key)
        action = jnp.where(explore, jax.random.uniform(explore_key, (env.action_size,), minval=-1.0, maxval=1.0),
                           agent.act(agent_state, obs, act_key, deterministic=False))
        action_state, target = env.action_space.step(action_state, action)
        # The legs the CPG plans on the ground, for the estimator's optional contact model.
        stance = cpg.foot_heights(action_state.cpg.phase) <= 1e-6 if has_cpg else jnp.ones(4, bool)
        return obs, reward, task_state, action, action_state, target, stance

    @jax.jit
    def evaluate_tick(agent_state, action_state, command, joint_angle, joint_velocity, acceleration, gyro,
                      prev_gyro, velocity, gravity):
        """The deterministic policy's joint targets (evaluation runs)."""
        obs = env.observation(joint_angle, joint_velocity, action_state, acceleration, gyro, prev_gyro, velocity,
                              command, gravity)
        return env.action_space.step(action_state, agent.act(agent_state, obs, None, deterministic=True))

    return env, task, agent, tick, evaluate_tick, jax.jit(agent.update)


class _Reading:
    """The numbers one sensor reading gives the loop."""

    def __init__(self, sensors, estimator: VelocityEstimator, dt: float, contacts):
        rotation = rotation_matrix(sensors.orientation)
        self.sensors = sensors
        self.velocity = estimator.update(sensors, dt, contacts)
        self.gravity = rotation.T @ np.array([0.0, 0.0, -1.0])
        self.roll, self.pitch = roll_pitch(rotation)


def run(config: RealtimeConfig, bot: Robot, out_dir: Path = Path("results/realtime"), resume: bool = True,
        view: bool = True, kalman: KalmanConfig = KalmanConfig(), lock_memory: bool = True) -> dict:
    """Train on `bot` for `config.steps` control steps (or until Ctrl-C); returns the results document.

    `lock_memory=False` leaves the pages to the kernel (to measure what locking them buys).
    """
    env, task, agent, tick, evaluate_tick, update = build(config)
    out_dir = Path(out_dir)
    checkpoint = out_dir / f"{config.name}.checkpoint"
    key = jax.random.PRNGKey(config.seed)
    key, agent_key, learner_key = jax.random.split(key, 3)
    agent_state = agent.init(agent_key)
    task_state = task.init()
    buffer = HostReplay(config.steps, env.observation_size, env.action_size)
    progress = Progress(config.steps)
    learner_updates = 0
    if resume and (checkpoint / "state.msgpack").exists():
        agent_state, task_state, key, learner_updates = _load(checkpoint, config, agent_state, task_state, key,
                                                              buffer, progress)
        finished = out_dir / f"{config.name}.json"
        if progress.step >= config.steps and finished.exists():
            _say(view, f"{config.name} is complete ({progress.step} steps): {finished}; --restart trains again")
            return json.loads(finished.read_text())
        _say(view, f"resuming {config.name} at step {progress.step} ({progress.falls} falls so far)")

    compile_start = time.perf_counter()
    _compile(env, tick, evaluate_tick, update, agent_state, task_state, buffer, config.agent_config.batch_size)
    compile_s = time.perf_counter() - compile_start
    # What is built by now (JAX, flax, MuJoCo: ~200k objects) lives as long as the run. Freeze it
    # out of the collector's reach: a full collection over it holds the GIL ~100 ms on this CPU,
    # four control periods.
    gc.collect()
    gc.freeze()

    def allowed(updates):
        learning_steps = progress.step - config.warmup_steps
        return learning_steps > 0 and (config.unthrottled or updates < config.utd * learning_steps)

    learner = Learner(update, agent_state, buffer, config.agent_config.batch_size, learner_key, allowed,
                      learner_updates)
    stop = threading.Event()
    estimator = VelocityEstimator(kalman)
    period = 1.0 / config.hz
    episode_steps = int(round(config.episode_seconds * config.hz))
    started = results.now()
    with scheduling.control_thread(lock_memory) as (realtime, locked):
        timing = {"periods": [], "wake": [], "at_step": [], "at_time": [], "work": [], "late": 0, "ticks": 0,
                  "scheduling": "SCHED_FIFO" if realtime else "ordinary, compute threads niced",
                  "memory_locked": locked, "major_page_faults": scheduling.major_page_faults()}
        previous_handler = signal.signal(signal.SIGINT, lambda *_: stop.set()) if _main_thread() else None
        bot.start()
        learner.start()
        scheduling.nice_compute_threads()
        view_line = _View(view, config, progress, learner, timing, bot)
        try:
            fresh = True
            while progress.step < config.steps and not stop.is_set():
                key, command_key = jax.random.split(key)
                task_state, command = task.command(task_state, command_key)
                fresh = _episode(config, bot, env, tick, learner, buffer, progress, estimator, task_state, command,
                                 key, fresh, episode_steps, period, stop, timing, view_line)
                task_state, key = progress.task_state, progress.key
        finally:
            bot.damp()  # safety first: motors soft before anything is saved
            learner.stop()
            timing["major_page_faults"] = scheduling.major_page_faults() - timing["major_page_faults"]
            gc.unfreeze()
            if previous_handler is not None:
                signal.signal(signal.SIGINT, previous_handler)
            view_line.close()
        try:
            complete = progress.step >= config.steps
            evaluation = _evaluate(config, bot, env, evaluate_tick, learner.state, task, key, estimator) if (
                complete and config.eval_seconds > 0) else None
        finally:
            bot.stop()
    _save(checkpoint, config, learner.state, task_state, key, learner.updates, buffer, progress)
    document = _document(config, progress, timing, learner, compile_s, started, complete, evaluation)
    results.write(out_dir / f"{config.name}.json", document)
    np.save(out_dir / f"{config.name}.trace.npy", progress.trace[:progress.step].astype(np.float32))
    _say(view, f"{'finished' if complete else 'stopped'} at step {progress.step}: {out_dir / config.name}.json"
               + ("" if complete else f"; run again to resume from {checkpoint}"))
    return document


def _episode(config, bot, env, tick, learner, buffer, progress, estimator, task_state, command, key, fresh,
             episode_steps, period, stop, timing, view_line) -> bool:
    """One episode, to a safety trip (returns True: the robot was reset) or the time limit (False: it walks on)."""
    if fresh:
        estimator.reset()
        action_state = env.action_space.init()
    else:
        action_state = progress.action_state
    sensors = bot.read()
    prev_gyro = sensors.angular_velocity
    previous = None  # (obs, action) of the last step, waiting for its outcome
    stance = None
    last_start = None
    deadline = time.perf_counter()
    episode_start = deadline
    for episode_step in range(episode_steps + 1):
        start = time.perf_counter()
        if last_start is not None:
            timing["periods"].append(start - last_start)
            timing["wake"].append(start - deadline)  # past the deadline slept to: scheduler and GIL
            timing["at_step"].append(progress.step)
            timing["at_time"].append(start)
        last_start = start
        timing["ticks"] += 1
        reading = _Reading(bot.read(), estimator, period, stance if config.planned_contacts else None)
        s = reading.sensors
        key, step_key = jax.random.split(key)
        out = tick(learner.state, action_state, task_state, command, s.joint_angle, s.joint_velocity,
                   s.acceleration, s.angular_velocity, prev_gyro, reading.velocity, reading.gravity, reading.roll,
                   reading.pitch, s.joint_torque, step_key, progress.step < config.warmup_steps)
        obs, reward, task_state, action, next_action_state, target, stance_out = out
        trip = safety.check(s)
        stepping = previous is not None
        last = episode_step == episode_steps or progress.step + stepping >= config.steps or stop.is_set()
        if trip:
            bot.damp()
        elif not last:
            bot.command(np.asarray(target), *robot.ROBOT_PD_GAINS)
        obs, reward = np.asarray(obs), float(reward)
        if stepping:
            buffer.add(previous[0], previous[1], reward, obs, 0.0 if trip else 1.0)
            progress.step += 1
            learner.new_step.set()
            truth = bot.truth()["linear_velocity"] if hasattr(bot, "truth") else (np.nan,) * 3
            progress.trace[progress.step - 1] = (progress.step, progress.train_seconds + time.perf_counter()
                                                 - episode_start, reading.velocity[0], reading.velocity[1], truth[0],
                                                 truth[1], reward, bool(trip))
            if progress.step % LOG_EVERY_STEPS == 0:
                progress.train_seconds += time.perf_counter() - episode_start
                episode_start = time.perf_counter()
                progress.rows.append(_row(progress, learner))
            view_line.show()
        if trip or last:
            break
        previous = (obs, np.asarray(action))
        action_state = next_action_state
        stance = np.asarray(stance_out)
        prev_gyro = s.angular_velocity
        deadline += period
        timing["work"].append(time.perf_counter() - start)
        if not scheduling.sleep_until(deadline):
            timing["late"] += 1  # the work of this period overran the next tick's start
            deadline = time.perf_counter()
    progress.train_seconds += time.perf_counter() - episode_start
    progress.episodes += 1
    if trip:
        progress.falls += 1
        view_line.note(f"step {progress.step}: safety stop ({trip}), fall {progress.falls}; waiting for the reset")
        pause = time.perf_counter()
        bot.reset()
        progress.reset_seconds += time.perf_counter() - pause
    progress.task_state, progress.key, progress.action_state = task_state, key, action_state
    return bool(trip)


def _row(progress: Progress, learner: Learner) -> dict:
    """One results row: means over the last LOG_EVERY_STEPS steps."""
    recent = progress.trace[max(progress.step - LOG_EVERY_STEPS, 0):progress.step]
    return {"step": progress.step, "train_minutes": progress.train_seconds / 60,
            "estimated_velocity": float(recent[:, 2].mean()), "true_velocity": float(np.nanmean(recent[:, 4]))
            if np.isfinite(recent[:, 4]).any() else None,
            "reward": float(recent[:, 6].mean()), "falls": progress.falls, "updates": learner.updates}


def _evaluate(config, bot, env, evaluate_tick, agent_state, task, key, estimator) -> dict:
    """The evaluation run: deterministic policy from a fresh stand, no learning, for eval_seconds."""
    bot.reset()
    estimator.reset()
    _, command = task.command(task.init(), key)
    action_state = env.action_space.init()
    prev_gyro = bot.read().angular_velocity
    period = 1.0 / config.hz
    estimated, true = [], []
    deadline = time.perf_counter()
    fell = None
    for _ in range(int(config.eval_seconds * config.hz)):
        reading = _Reading(bot.read(), estimator, period, None)
        s = reading.sensors
        fell = safety.check(s)
        if fell:
            bot.damp()
            break
        action_state, target = evaluate_tick(agent_state, action_state, command, s.joint_angle, s.joint_velocity,
                                             s.acceleration, s.angular_velocity, prev_gyro, reading.velocity,
                                             reading.gravity)
        bot.command(np.asarray(target), *robot.ROBOT_PD_GAINS)
        prev_gyro = s.angular_velocity
        estimated.append(reading.velocity[0])
        true.append(bot.truth()["linear_velocity"][0] if hasattr(bot, "truth") else np.nan)
        deadline += period
        scheduling.sleep_until(deadline)
    one_second = max(1, int(config.hz))
    true = np.asarray(true)
    peak = (float(np.convolve(true, np.ones(one_second) / one_second, "valid").max())
            if len(true) >= one_second and np.isfinite(true).all() else None)
    return {"seconds": len(true) / config.hz, "fell": fell, "estimated_velocity": float(np.mean(estimated)),
            "true_velocity": float(np.mean(true)) if np.isfinite(true).all() else None, "true_peak_1s": peak}


def _document(config, progress, timing, learner, compile_s, started, complete, evaluation) -> dict:
    periods = np.asarray(timing["periods"]) * 1000
    work = np.asarray(timing["work"]) * 1000
    wake = np.asarray(timing["wake"]) * 1000
    nominal = 1000 / config.hz
    error = np.abs(periods - nominal) if len(periods) else np.zeros(1)
    worst = np.argsort(error)[::-1][:5] if len(periods) else []
    learning_steps = max(progress.step - config.warmup_steps, 1)
    return {
        "schema": SCHEMA,
        "config": dict(dataclasses.asdict(config), agent=dataclasses.asdict(config.agent_config), hz=config.hz),
        "complete": complete,
        "steps": progress.step,
        "falls": progress.falls,
        "episodes": progress.episodes,
        "train_minutes": progress.train_seconds / 60,
        "minutes_with_resets": (progress.train_seconds + progress.reset_seconds) / 60,
        "updates": learner.updates,
        "updates_per_learning_step": learner.updates / learning_steps,
        "timing": {
            "nominal_period_ms": nominal,
            "period_p50_ms": float(np.percentile(periods, 50)) if len(periods) else None,
            "period_p99_ms": float(np.percentile(periods, 99)) if len(periods) else None,
            "period_error_p50_ms": float(np.percentile(error, 50)),
            "period_error_p99_ms": float(np.percentile(error, 99)),
            "period_error_max_ms": float(error.max()),
            "missed_deadlines": timing["late"],
            "ticks": timing["ticks"],
            "work_p50_ms": float(np.percentile(work, 50)) if len(work) else None,
            "work_p99_ms": float(np.percentile(work, 99)) if len(work) else None,
            "work_max_ms": float(work.max()) if len(work) else None,
            "wake_p99_ms": float(np.percentile(wake, 99)) if len(wake) else None,
            "wake_max_ms": float(wake.max()) if len(wake) else None,
            "worst_periods": [{"step": int(timing["at_step"][i]), "period_ms": float(periods[i]),
                               "wake_ms": float(wake[i]), "unix_time": _unix_time(timing["at_time"][i])}
                              for i in worst],
            "scheduling": timing["scheduling"],
            "memory_locked": timing["memory_locked"],
            "major_page_faults": timing["major_page_faults"],
            "period_histogram": _histogram(periods, nominal),
        },
        "rows": progress.rows,
        "evaluation": evaluation,
        "wall_clock": {"started": started, "updated": results.now(), "compile_s": round(compile_s, 1)},
        "versions": results.versions(),
        "git_commit": results.git_commit(),
        "hardware": results.hardware(),
    }


def _unix_time(perf_counter_time: float) -> float:
    """A time.perf_counter() reading as seconds since the epoch (to line up with other logs)."""
    return time.time() - (time.perf_counter() - perf_counter_time)


def _histogram(periods_ms, nominal_ms, half_width_ms: float = 5.0, bins: int = 80) -> dict:
    """Control periods binned around the nominal one; the outliers counted apart."""
    edges = np.linspace(nominal_ms - half_width_ms, nominal_ms + half_width_ms, bins + 1)
    counts, _ = np.histogram(periods_ms, edges)
    return {"edges_ms": edges.round(4).tolist(), "counts": counts.tolist(),
            "below": int(np.sum(periods_ms < edges[0])), "above": int(np.sum(periods_ms > edges[-1]))}


def load_trace(out_dir: Path, config: RealtimeConfig) -> np.ndarray:
    """The per-step trace of a run, (steps, len(TRACE))."""
    return np.load(Path(out_dir) / f"{config.name}.trace.npy")


def _compile(env, tick, evaluate_tick, update, agent_state, task_state, buffer, batch_size):
    """Trace and compile every jitted function before the robot moves, so the first period is on time."""
    zeros = np.zeros(robot.NUM_JOINTS, np.float32)
    three = np.zeros(3, np.float32)
    command = np.zeros(3, np.float32)
    key = jax.random.PRNGKey(0)
    for explore in (True, False):
        jax.block_until_ready(tick(agent_state, env.action_space.init(), task_state, command, zeros, zeros, three,
                                   three, three, three, three, 0.0, 0.0, zeros, key, explore))
    leg_odometry(Sensors(0.0, zeros, zeros, zeros, three, three, np.array([1.0, 0.0, 0.0, 0.0])))
    jax.block_until_ready(evaluate_tick(agent_state, env.action_space.init(), command, zeros, zeros, three, three,
                                        three, three, three))
    batch = Transition(np.zeros((batch_size, env.observation_size), np.float32),
                       np.zeros((batch_size, env.action_size), np.float32), np.zeros(batch_size, np.float32),
                       np.zeros((batch_size, env.observation_size), np.float32), np.zeros(batch_size, np.float32))
    jax.block_until_ready(update(agent_state, batch, key, jnp.int32(0)))


def _settings(config: RealtimeConfig) -> dict:
    """What a checkpoint must match to be resumed."""
    return json.loads(json.dumps(dict(dataclasses.asdict(config), agent=dataclasses.asdict(config.agent_config),
                                      eval_seconds=None)))


def _save(checkpoint: Path, config, agent_state, task_state, key, updates, buffer, progress) -> None:
    """Policy, optimiser state, replay buffer and counters, so a later run resumes."""
    checkpoint.mkdir(parents=True, exist_ok=True)
    state = {"agent": agent_state, "task_state": task_state, "key": key}
    (checkpoint / "state.msgpack").write_bytes(flax.serialization.to_bytes(state))
    buffer.save(checkpoint / "replay.npz")
    np.save(checkpoint / "trace.npy", progress.trace[:progress.step])
    counters = {"settings": _settings(config), "step": progress.step, "falls": progress.falls, "episodes": progress.episodes, "updates": updates,
                "train_seconds": progress.train_seconds, "reset_seconds": progress.reset_seconds,
                "rows": progress.rows}
    (checkpoint / "progress.json").write_text(json.dumps(counters))


def _load(checkpoint: Path, config, agent_state, task_state, key, buffer, progress):
    counters = json.loads((checkpoint / "progress.json").read_text())
    if counters.get("settings") != _settings(config):
        raise ValueError(f"{checkpoint} holds a run with other settings; start over with --restart "
                         "or pick another --out folder")
    template = {"agent": agent_state, "task_state": task_state, "key": key}
    state = flax.serialization.from_bytes(template, (checkpoint / "state.msgpack").read_bytes())
    buffer.load(checkpoint / "replay.npz")
    for name in ("step", "falls", "episodes", "train_seconds", "reset_seconds", "rows"):
        setattr(progress, name, counters[name])
    done = np.load(checkpoint / "trace.npy")
    progress.trace[:len(done)] = done
    return state["agent"], state["task_state"], state["key"], counters["updates"]


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _say(view: bool, text: str) -> None:
    if view:
        print(text, file=sys.stderr, flush=True)


class _View:
    """The live terminal line: steps, velocities, falls, reward, timing, learner rate, ETA."""

    def __init__(self, enabled, config, progress, learner, timing, bot, every_s: float = 0.5):
        self.enabled, self.config, self.progress = enabled, config, progress
        self.learner, self.timing, self.bot = learner, timing, bot
        self.every_s = every_s if sys.stderr.isatty() else 10.0
        self.last = 0.0
        self.start = time.perf_counter()
        self.start_step = progress.step
        self.since = (self.start, learner.updates)  # the learner's rate is shown over the last interval

    def show(self):
        now = time.perf_counter()
        if not self.enabled or now - self.last < self.every_s:
            return
        self.last = now
        updates_per_s = (self.learner.updates - self.since[1]) / max(now - self.since[0], 1e-9)
        self.since = (now, self.learner.updates)
        p = self.progress
        recent = p.trace[max(p.step - int(self.config.hz), 0):p.step]
        periods = np.asarray(self.timing["periods"][-2000:]) * 1000
        rate = (p.step - self.start_step) / max(now - self.start, 1e-9)
        eta = (self.config.steps - p.step) / max(rate, 1e-9)  # resets included: they will recur
        line = (f"step {p.step}/{self.config.steps} | v est {recent[:, 2].mean():+.2f} true {recent[:, 4].mean():+.2f}"
                f" m/s | falls {p.falls} | reward {recent[:, 6].mean():.2f} | period p50 "
                f"{np.percentile(periods, 50):.1f} p99 {np.percentile(periods, 99):.1f} ms, late {self.timing['late']}"
                f" | {updates_per_s:.0f} upd/s | ETA {int(eta // 60)}:{int(eta % 60):02d}")
        if sys.stderr.isatty():
            print("\r\033[K" + line, end="", file=sys.stderr, flush=True)
        else:
            print(line, file=sys.stderr, flush=True)

    def note(self, text):
        if self.enabled:
            print(("\r\033[K" if sys.stderr.isatty() else "") + text, file=sys.stderr, flush=True)

    def close(self):
        if self.enabled and sys.stderr.isatty():
            print(file=sys.stderr)
