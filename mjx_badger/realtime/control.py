"""The control side: the jitted tick, one training episode at the wall clock, the evaluation run."""

import dataclasses
import functools
import threading
import time
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.losses import Transition
from mjx_badger.control import cpg
from mjx_badger.control.actions import is_cpg
from mjx_badger.realtime import report, safety, scheduling
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.estimation import VelocityEstimator, leg_odometry
from mjx_badger.realtime.host_replay import HostReplay
from mjx_badger.realtime.interface import LinkLost, Robot, RobotTripped, Sensors, rotation_matrix
from mjx_badger.realtime.learner import Learner
from mjx_badger.realtime.operator import Operator
from mjx_badger.realtime.view import View
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.sim.observation import roll_pitch
from mjx_badger.tasks import locomotion as tasks


class Measured(NamedTuple):
    """What a control step knows of the robot: one sensor reading, the gyro before it, the estimated velocity."""

    joint_angle: np.ndarray
    joint_velocity: np.ndarray
    joint_torque: np.ndarray
    acceleration: np.ndarray
    gyro: np.ndarray
    prev_gyro: np.ndarray
    """The gyro of the previous control step (the observation's angular acceleration is the difference)."""
    velocity: np.ndarray
    """Trunk-frame trunk velocity (m/s), estimated."""
    rotation: np.ndarray
    """Trunk-to-world rotation (3, 3) of the IMU's orientation."""


def measured_step(sensors: Sensors, prev_gyro: np.ndarray, velocity: np.ndarray) -> Measured:
    """What a control step knows of the robot, from one reading, the gyro before it and the estimated velocity."""
    return Measured(sensors.joint_angle, sensors.joint_velocity, sensors.joint_torque, sensors.acceleration,
                    sensors.angular_velocity, prev_gyro, velocity, rotation_matrix(sensors.orientation))


def true_velocity(bot: Robot):
    """The robot's true trunk-frame velocity (3,) for the logs, NaN where it has no ground truth."""
    truth = bot.truth()
    return truth["linear_velocity"] if truth is not None else (np.nan,) * 3


def observe(env: HB40Env, action_state, command, measured: Measured):
    """The environment's observation of a measured step, gravity projected into the trunk frame as the env does."""
    gravity = measured.rotation.T @ jnp.array([0.0, 0.0, -1.0])
    return env.observation(measured.joint_angle, measured.joint_velocity, action_state, measured.acceleration,
                           measured.gyro, measured.prev_gyro, measured.velocity, command, gravity)


@functools.lru_cache(maxsize=4)
def build(config: RealtimeConfig):
    """Environment (observation, action pipeline, task), agent and the two jitted functions."""
    config.validate()
    protocol = config.protocol_spec.replace(episode_seconds=config.episode_seconds)
    task = config.make_task()
    # The conditions' robot runs the CPG its way (swing, frequency, CPG-RT's mix); the loop senses for itself.
    env = HB40Env(config.approach, task, EnvConfig(control_hz=config.hz, protocol=protocol,
                                                   conditions=config.conditions_spec), config.robot_spec,
                  config.approach_params)
    # A learning-rate schedule (XQC, SimbaV2) runs over the updates the loop is allowed to make.
    updates = max(1, round((config.steps - config.warmup_steps) * config.utd))
    agent = make_agent(config.agent_config, env.observation_size, env.action_size, total_updates=updates)
    has_cpg = is_cpg(config.approach)

    @jax.jit
    def tick(agent_state, action_state, task_state, command, measured: Measured, key, explore):
        """Observation and reward of the reading, then the next action and its joint targets."""
        obs = observe(env, action_state, command, measured)
        roll, pitch = roll_pitch(measured.rotation)
        motion = tasks.Motion(measured.velocity, measured.gyro, roll, pitch, measured.joint_torque)
        reward, _ = task.reward(motion, command)
        task_state = task.update(task_state, command, motion)
        act_key, explore_key = jax.random.split(key)
        action = jnp.where(explore, jax.random.uniform(explore_key, (env.action_size,), minval=-1.0, maxval=1.0),
                           agent.act(agent_state, obs, act_key, deterministic=False))
        action_state, target = env.action_space.step(action_state, action)
        # The legs the CPG plans on the ground, for the estimator's optional contact model.
        stance = (cpg.foot_heights(action_state.cpg.phase, spec=env.spec) <= 1e-6 if has_cpg
                  else jnp.ones(len(env.spec.legs), bool))
        return obs, reward, task_state, action, action_state, target, stance

    @jax.jit
    def evaluate_tick(agent_state, action_state, command, measured: Measured):
        """The deterministic policy's joint targets (evaluation runs)."""
        obs = observe(env, action_state, command, measured)
        return env.action_space.step(action_state, agent.act(agent_state, obs, None, deterministic=True))

    return env, task, agent, tick, evaluate_tick, jax.jit(agent.update)


def compile_all(env, tick, evaluate_tick, update, agent_state, task_state, batch_size):
    """Trace and compile every jitted function before the robot moves, so the first period is on time."""
    zeros = np.zeros(env.spec.num_joints, np.float32)
    three = np.zeros(3, np.float32)
    measured = Measured(zeros, zeros, zeros, three, three, three, three, np.eye(3, dtype=np.float32))
    command = np.zeros(3, np.float32)
    key = jax.random.PRNGKey(0)
    for explore in (True, False):
        jax.block_until_ready(tick(agent_state, env.action_space.init(), task_state, command, measured, key, explore))
    leg_odometry(Sensors(0.0, zeros, zeros, zeros, three, three, np.array([1.0, 0.0, 0.0, 0.0])), env.spec)
    jax.block_until_ready(evaluate_tick(agent_state, env.action_space.init(), command, measured))
    batch = Transition(np.zeros((batch_size, env.observation_size), np.float32),
                       np.zeros((batch_size, env.action_size), np.float32), np.zeros(batch_size, np.float32),
                       np.zeros((batch_size, env.observation_size), np.float32), np.zeros(batch_size, np.float32))
    jax.block_until_ready(update(agent_state, batch, key, jnp.int32(0)))


class Progress:
    """Counters of the run, kept in the checkpoint so a resumed run continues them."""

    def __init__(self, steps: int):
        self.step = 0
        self.falls = 0
        self.episodes = 0
        self.train_seconds = 0.0
        self.reset_seconds = 0.0
        self.gaps = 0
        """Episodes the link ended (no reply in time, or the robot damped itself on its watchdog or rule)."""
        self.gap_seconds = 0.0
        self.rows: list[dict] = []
        # One TRACE row per step, preallocated: a growing list of tuples would be more objects for
        # every garbage collection pass to walk while the robot waits.
        self.trace = np.full((steps, len(report.TRACE)), np.nan)
        # Where the last episode left off, for the next one.
        self.task_state = None
        self.key = None
        self.action_state = None


@dataclasses.dataclass
class Session:
    """What every episode of a run works with."""

    config: RealtimeConfig
    bot: Robot
    env: HB40Env
    tick: Callable
    learner: Learner
    buffer: HostReplay
    progress: Progress
    estimator: VelocityEstimator
    timing: dict
    """report.timing_log's record, appended to every tick."""
    view: View
    stop: threading.Event
    operator: Operator


def episode(session: Session, task_state, command, key, fresh: bool) -> bool:
    """One episode, to a safety trip (returns True: the robot was reset) or the time limit (False: it walks on).

    Every control period: read the sensors, estimate the trunk velocity, observe and score the last
    action, check safety, act and send the joint targets, store the transition, sleep to the deadline.
    A safety trip damps the motors first, ends the episode, counts a fall and waits for the (manual)
    reset, which is not training time. A lost link (LinkLost) ends the episode where it is: the step whose
    outcome was not seen is not stored, and the wait for the robot is neither training nor reset time.
    The operator's pause or collapse ends it at the next period.
    """
    config, bot, progress = session.config, session.bot, session.progress
    period = 1.0 / config.hz
    episode_steps = int(round(config.episode_seconds * config.hz))
    if fresh:
        session.estimator.reset()
        action_state = session.env.action_space.init()
    else:
        action_state = progress.action_state
    at = {"task_state": task_state, "key": key, "action_state": action_state, "since": time.perf_counter()}
    lost = trip = None
    try:
        trip = _ticks(session, command, at, episode_steps, period)
    except LinkLost as error:
        lost = error
    task_state, key, action_state = at["task_state"], at["key"], at["action_state"]
    # A lost link's gap began when its unanswered request went out: that wait is not training time either.
    ended = max(getattr(lost, "since", time.perf_counter()), at["since"])
    progress.train_seconds += ended - at["since"]
    progress.episodes += 1
    if lost is not None:
        progress.gaps += 1
        session.view.note(f"step {progress.step}: link lost ({lost}); waiting for the robot")
        pause = ended
        wait_for_robot(session)
        progress.gap_seconds += time.perf_counter() - pause
        trip = True  # a fresh episode follows, as after a fall
    elif trip:
        progress.falls += 1
        session.view.note(f"step {progress.step}: safety stop ({trip}), fall {progress.falls}; waiting for the reset")
        pause = time.perf_counter()
        if session.operator.operator_resets:
            session.operator.become("waiting_reset")
            while session.operator.wait_while(("waiting_reset",), 0.2) == "waiting_reset" and not session.stop.is_set():
                session.view.show()
        if session.operator.state == "learning":
            bot.reset()
        progress.reset_seconds += time.perf_counter() - pause
    progress.task_state, progress.key, progress.action_state = task_state, key, action_state
    return bool(trip)


def wait_for_robot(session: Session) -> None:
    """After a lost link: until the robot answers and stands again (or the run is stopped)."""
    bot = session.bot
    while not session.stop.is_set():
        reachable = getattr(bot, "reachable", None)
        if reachable is None or reachable():
            try:
                bot.reset()
                return
            except LinkLost:
                pass
        time.sleep(0.2)


def _ticks(session: Session, command, at: dict, episode_steps: int, period: float):
    """The control periods of one episode, keeping `at` (task state, key, action state, since) current;
    the safety trip that ended it, or None."""
    config, bot, progress, timing = session.config, session.bot, session.progress, session.timing
    task_state, key, action_state = at["task_state"], at["key"], at["action_state"]
    prev_gyro = bot.read().angular_velocity
    previous = None  # (obs, action) of the last step, waiting for its outcome
    stance = None
    last_start = None
    deadline = time.perf_counter()
    for episode_step in range(episode_steps + 1):
        start = time.perf_counter()
        if last_start is not None:
            timing["periods"].append(start - last_start)
            timing["wake"].append(start - deadline)  # past the deadline slept to: scheduler and GIL
            timing["at_step"].append(progress.step)
            timing["at_time"].append(start)
        last_start = start
        timing["ticks"] += 1
        sensors = bot.read()
        velocity = session.estimator.update(sensors, period, stance if config.planned_contacts else None)
        key, step_key = jax.random.split(key)
        # A pretrained agent acts with its own policy in the warm-up too: random actions would only
        # knock over a robot that can already walk, and the warm-up is there to fill the buffer.
        explore = progress.step < config.warmup_steps and config.init_from is None
        out = session.tick(session.learner.state, action_state, task_state, command,
                           measured_step(sensors, prev_gyro, velocity), step_key, explore)
        obs, reward, task_state, action, next_action_state, target, stance_out = out
        at["task_state"], at["key"] = task_state, key
        trip = safety.check(sensors, session.env.spec)
        stepping = previous is not None
        last = (episode_step == episode_steps or progress.step + stepping >= config.steps or session.stop.is_set()
                or session.operator.state != "learning")
        if trip:
            bot.damp()
        elif not last:
            try:
                bot.command(np.asarray(target), *session.env.spec.pd_gains)
            except RobotTripped as tripped:  # the robot's own rule, checked between our readings, saw the fall first
                trip = tripped.reason
        obs, reward = np.asarray(obs), float(reward)
        if stepping:
            session.buffer.add(previous[0], previous[1], reward, obs, 0.0 if trip else 1.0)
            progress.step += 1
            session.learner.new_step.set()
            truth = true_velocity(bot)
            progress.trace[progress.step - 1] = (progress.step, progress.train_seconds + time.perf_counter()
                                                 - at["since"], velocity[0], velocity[1], truth[0], truth[1],
                                                 reward, bool(trip))
            if progress.step % report.LOG_EVERY_STEPS == 0:
                progress.train_seconds += time.perf_counter() - at["since"]
                at["since"] = time.perf_counter()
                progress.rows.append(report.row(progress, session.learner.updates))
            session.view.show()
        if trip or last:
            return trip
        previous = (obs, np.asarray(action))
        action_state = at["action_state"] = next_action_state
        stance = np.asarray(stance_out)
        prev_gyro = sensors.angular_velocity
        deadline += period
        timing["work"].append(time.perf_counter() - start)
        if not scheduling.sleep_until(deadline):
            timing["late"] += 1  # the work of this period overran the next tick's start
            deadline = time.perf_counter()
    return None


def evaluate(session: Session, evaluate_tick, agent_state, task, key) -> dict:
    """The evaluation run: deterministic policy from a fresh stand, no learning, for eval_seconds."""
    config, bot, estimator = session.config, session.bot, session.estimator
    bot.reset()
    estimator.reset()
    _, command = task.command(task.init(), key)
    action_state = session.env.action_space.init()
    prev_gyro = bot.read().angular_velocity
    period = 1.0 / config.hz
    estimated, true = [], []
    deadline = time.perf_counter()
    fell = None
    for _ in range(int(config.eval_seconds * config.hz)):
        sensors = bot.read()
        velocity = estimator.update(sensors, period, None)
        fell = safety.check(sensors, session.env.spec)
        if fell:
            bot.damp()
            break
        action_state, target = evaluate_tick(agent_state, action_state, command,
                                             measured_step(sensors, prev_gyro, velocity))
        bot.command(np.asarray(target), *session.env.spec.pd_gains)
        prev_gyro = sensors.angular_velocity
        estimated.append(velocity[0])
        true.append(true_velocity(bot)[0])
        deadline += period
        scheduling.sleep_until(deadline)
    one_second = max(1, int(config.hz))
    true = np.asarray(true)
    peak = (float(np.convolve(true, np.ones(one_second) / one_second, "valid").max())
            if len(true) >= one_second and np.isfinite(true).all() else None)
    return {"seconds": len(true) / config.hz, "fell": fell, "estimated_velocity": float(np.mean(estimated)),
            "true_velocity": float(np.mean(true)) if np.isfinite(true).all() else None, "true_peak_1s": peak}
