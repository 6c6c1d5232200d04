"""The on-robot loop: estimator, safety monitor, the loop end to end, stop and resume."""

import dataclasses
import json
import os
import resource
import signal
import threading
import time

import jax
import mujoco
import numpy as np
import pytest

import conftest
from mjx_badger import kinematics, mjcf, robot
from mjx_badger.agents import ALGORITHMS
from mjx_badger.realtime import control, safety, scheduling
from mjx_badger.realtime import figure as realtime_figure
from mjx_badger.realtime.estimation import VelocityEstimator, leg_odometry
from mjx_badger.realtime.interface import Sensors
from mjx_badger.realtime.loop import Learner, RealtimeConfig, run
from mjx_badger.realtime.simulated import SimulatedHB40

LEVEL = np.array([1.0, 0.0, 0.0, 0.0])


def standing_trajectory(velocity, dt, seconds, swinging_leg=None, noise=0.0, seed=0):
    """Sensor readings of a level trunk moving at velocity(t) (3,) over feet fixed on the ground.

    `swinging_leg` moves that foot forward at 0.3 m/s in the world instead (a swing the
    all-feet contact assumption does not know about).
    """
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, seconds, dt)
    fine = 20  # integrate the trunk position more finely than the control period
    feet_world = robot.HB40.hip_positions + kinematics.nominal_feet()
    readings, truth, position = [], [], np.zeros(3)

    def angles_at(position, t):
        feet = feet_world - position
        if swinging_leg is not None:
            feet[swinging_leg, 0] += 0.3 * t
        return np.asarray(kinematics.inverse(feet - robot.HB40.hip_positions)).reshape(-1)

    for t in times:
        v = velocity(t)
        eps = 1e-4
        acceleration = (velocity(t + eps) - velocity(t - eps)) / (2 * eps)
        q = angles_at(position, t)
        q_next = angles_at(position + v * eps, t + eps)
        q_prev = angles_at(position - v * eps, t - eps)
        qd = (q_next - q_prev) / (2 * eps)
        readings.append(Sensors(
            time=t, joint_angle=q, joint_velocity=qd + rng.normal(0, noise, 12), joint_torque=np.zeros(12),
            acceleration=acceleration + [0.0, 0.0, 9.81] + rng.normal(0, 10 * noise, 3),
            angular_velocity=np.zeros(3), orientation=LEVEL))
        truth.append(v)
        for k in range(fine):
            position = position + velocity(t + k * dt / fine) * dt / fine
    return readings, np.asarray(truth)


def test_leg_odometry_of_a_still_robot_is_zero():
    sensors = Sensors(0.0, np.asarray(robot.nominal_pose()), np.zeros(12), np.zeros(12), np.array([0, 0, 9.81]),
                      np.zeros(3), LEVEL)
    np.testing.assert_allclose(leg_odometry(sensors), 0.0, atol=1e-7)


def test_estimator_tracks_a_known_velocity():
    # Swaying 0.3 m/s forward and back, 0.1 m/s sideways (the feet stay within reach); 40 Hz,
    # noisy encoders and IMU.
    velocity = lambda t: np.array([0.3 * np.cos(3 * t), 0.1 * np.cos(2 * t), 0.0])
    readings, truth = standing_trajectory(velocity, 0.025, 4.0, noise=0.02)
    estimator = VelocityEstimator()
    estimates = np.array([estimator.update(s, 0.025) for s in readings])
    settled = slice(20, None)  # after 0.5 s
    error = estimates[settled] - truth[settled]
    assert np.sqrt(np.mean(error**2)) < 0.03
    assert np.max(np.abs(error)) < 0.1


def test_all_feet_contact_assumption_biases_low_and_planned_contacts_fix_it():
    # At 0.2 m/s, one foot swings forward at 0.3 m/s: assumed on the ground it implies -0.1 m/s,
    # so the four-feet mean reads (3 x 0.2 - 0.1) / 4 = 0.125; told it swings, the estimator ignores it.
    velocity = lambda t: np.array([0.2, 0.0, 0.0])
    readings, truth = standing_trajectory(velocity, 0.025, 1.0, swinging_leg=0)
    assumed, planned = VelocityEstimator(), VelocityEstimator(name="kinematic-kalman-contact")
    stance = np.array([False, True, True, True])
    all_feet = np.array([assumed.update(s, 0.025) for s in readings])[20:, 0]
    known = np.array([planned.update(s, 0.025, stance) for s in readings])[20:, 0]
    assert abs(np.mean(all_feet) - 0.125) < 0.02
    np.testing.assert_allclose(known, 0.2, atol=0.02)


def test_safety_trips_on_tilt_and_joint_limits():
    bot = SimulatedHB40(noise=None)
    assert safety.check(bot.read()) is None
    bot.tip(roll=1.0)
    assert safety.check(bot.read()).startswith("roll")
    bent = bot.read()
    angles = np.asarray(robot.nominal_pose()).copy()
    angles[2] = -0.2  # the FL knee folded past its stop at 0 rad (it opens positively)
    over = Sensors(bent.time, angles, bent.joint_velocity, bent.joint_torque, bent.acceleration,
                   bent.angular_velocity, LEVEL)
    assert "FL_knee" in safety.check(over)


class Recording(SimulatedHB40):
    """The simulated HB40 with a hand that tips it over at `tip_at` reads, and a log of the gains at reset."""

    def __init__(self, tip_at=None, **kwargs):
        super().__init__(**kwargs)
        self.tip_at, self.reads, self.gains_at_reset = tip_at, 0, []

    def read(self):
        self.reads += 1
        if self.reads == self.tip_at:
            self.tip(roll=1.2)
        return super().read()

    def reset(self):
        self.gains_at_reset.append(self.gains)
        super().reset()


# Small and slow enough for a test: 20 Hz, a 32x32 CrossQ, 20 warm-up steps, 1 s evaluation.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=40, warmup_steps=20, control_hz=20.0,
                      eval_seconds=1.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))


def test_the_robot_is_taken_by_its_adapters_name_and_one_without_a_ground_truth_logs_nan():
    from mjx_badger import sensors
    from mjx_badger.realtime import adapters, interface

    bot = adapters.make("simulated", TINY, reset_seconds=0.0, sensor_noise=False)
    assert isinstance(bot, SimulatedHB40) and bot.noise is sensors.EXACT and bot.reset_seconds == 0.0
    np.testing.assert_array_equal(control.true_velocity(bot), np.zeros(3))  # standing, not yet started

    class Blind(interface.Robot):
        """A robot with sensors and motors but no ground truth: `truth` is the protocol's None."""

    assert np.isnan(control.true_velocity(Blind())).all()
    with pytest.raises(ValueError, match="unknown robot adapter 'hb50'; choose from simulated"):
        adapters.make("hb50", TINY)


def granted_in_a_thread(take, give_back) -> bool:
    """Whether `take()` is granted to a fresh thread of this process (given back at once)."""
    granted = []

    def probe():
        granted.append(take())
        if granted[0]:
            give_back()

    worker = threading.Thread(target=probe)
    worker.start()
    worker.join()
    return granted[0]


def fifo_privileged() -> bool:
    """Whether this process may enter SCHED_FIFO at the control priority: CAP_SYS_NICE or a high enough
    rtprio limit (what scheduling.py's docstring says it takes), read apart from the code under test."""
    cap_sys_nice = 1 << 23
    with open("/proc/self/status") as status:
        effective = next((int(line.split()[1], 16) for line in status if line.startswith("CapEff:")), 0)
    rtprio = resource.getrlimit(resource.RLIMIT_RTPRIO)[0]
    return bool(effective & cap_sys_nice) or rtprio == resource.RLIM_INFINITY or rtprio >= scheduling.CONTROL_PRIORITY


def test_loop_runs_end_to_end_and_a_tip_puts_the_robot_in_damping_mode(tmp_path, monkeypatch):
    fifo = granted_in_a_thread(scheduling.raise_to_realtime, scheduling.back_to_normal)
    lockable = granted_in_a_thread(scheduling.lock_memory, scheduling.unlock_memory)
    # The loop counts major faults at the session's start and end: the report must hold the difference.
    faults = iter((7, 12))
    monkeypatch.setattr(scheduling, "major_page_faults", lambda: next(faults))
    bot = Recording(tip_at=10, reset_seconds=0.1)
    document = run(TINY, bot, tmp_path, resume=False, view=False)
    assert document["complete"] and document["steps"] == TINY.steps
    assert document["falls"] >= 1
    assert bot.gains_at_reset[0] == robot.HB40.damping_gains
    # The learner ran concurrently: one update per learning step, capped by the replay ratio.
    assert 0 < document["updates"] <= TINY.steps - TINY.warmup_steps
    timing = document["timing"]
    assert timing["ticks"] >= TINY.steps
    # The results say what the machine granted: SCHED_FIFO exactly where this process can have it.
    assert timing["scheduling"] == ("SCHED_FIFO" if fifo else "ordinary, compute threads niced")
    assert timing["memory_locked"] is lockable
    # The typical tick fits its period; the worst one is the machine's (a loaded CPU stretches it), and the
    # deadline misses are measured in benchmarks/bench_realtime.py, not asserted here.
    assert 0 < timing["work_p50_ms"] < 1000 / TINY.hz and timing["work_p50_ms"] <= timing["work_max_ms"]
    assert timing["major_page_faults"] == 5
    assert not scheduling.is_realtime()  # the caller's thread is ordinary again afterwards
    assert document["evaluation"]["seconds"] > 0
    trace = np.load(tmp_path / f"{TINY.name}.trace.npy")
    assert trace.shape[0] == TINY.steps and trace[:, 7].sum() == document["falls"]
    assert np.isfinite(trace[:, 2]).all() and np.isfinite(trace[:, 4]).all()
    figure = realtime_figure.draw(document, trace, tmp_path / "run.png")
    assert figure.stat().st_size > 10_000
    # An evaluation that fell before its first second has no best second (it once crashed the drawing).
    fell = dict(document, evaluation={"seconds": 0.5, "fell": "roll -0.81 rad", "estimated_velocity": -0.1,
                                      "true_velocity": 0.14, "true_peak_1s": None})
    assert realtime_figure.draw(fell, trace, tmp_path / "fell.png").stat().st_size > 10_000


class Interrupting(SimulatedHB40):
    """The simulated HB40, and an operator who presses Ctrl-C (or a system that sends SIGTERM) at the `at`-th read."""

    def __init__(self, at, signum=signal.SIGINT, **kwargs):
        super().__init__(**kwargs)
        self.at, self.reads, self.signum = at, 0, signum

    def read(self):
        self.reads += 1
        if self.reads == self.at:
            os.kill(os.getpid(), self.signum)
        return super().read()


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_stop_and_resume_keep_the_replay_buffer_and_step_count(tmp_path, signum):
    config = dataclasses.replace(TINY, steps=60, eval_seconds=0.0)
    bot = Interrupting(at=30, signum=signum, reset_seconds=0.1)
    stopped = run(config, bot, tmp_path, view=False)
    assert not stopped["complete"] and 0 < stopped["steps"] < config.steps
    assert bot.damp_calls >= 1
    checkpoint = tmp_path / f"{config.name}.checkpoint"
    saved = np.load(checkpoint / "replay.npz")
    assert int(saved["size"]) == stopped["steps"]
    first_obs = saved["obs"][: stopped["steps"]].copy()

    resumed = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path, view=False)
    assert resumed["complete"] and resumed["steps"] == config.steps
    after = np.load(checkpoint / "replay.npz")
    assert int(after["size"]) == config.steps
    np.testing.assert_array_equal(after["obs"][: stopped["steps"]], first_obs)
    assert resumed["falls"] >= stopped["falls"] and resumed["updates"] >= stopped["updates"]
    # The same command once more neither trains nor rewrites the finished results.
    again = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path, view=False)
    assert again["wall_clock"] == resumed["wall_clock"] and again["steps"] == config.steps
    with pytest.raises(ValueError, match="other settings"):
        run(dataclasses.replace(config, seed=1), SimulatedHB40(), tmp_path, view=False)
    # A checkpoint cut short is named and refused, before anything compiles; the run's lock is given back.
    replay = checkpoint / "replay.npz"
    replay.write_bytes(replay.read_bytes()[:1000])
    with pytest.raises(ValueError, match=f"{checkpoint} is damaged.*--restart"):
        run(config, SimulatedHB40(), tmp_path, view=False)
    assert not (tmp_path / f"{config.name}.json.lock").exists()


def test_bad_settings_are_refused_before_anything_compiles():
    compiles = len(conftest.COMPILES)
    with pytest.raises(ValueError, match="cpg-rt-avg"):
        RealtimeConfig(approach="cpg-rt").validate()
    with pytest.raises(ValueError, match="planned contacts"):
        RealtimeConfig(approach="jt-oef", planned_contacts=True).validate()
    assert not conftest.COMPILES[compiles:]  # nothing traced, compiled or loaded from the cache


def test_simulated_robot_is_paced_to_the_wall_clock_and_stands():
    bot = SimulatedHB40(noise=None)
    started = time.perf_counter()
    bot.start()
    try:
        time.sleep(1.0)
        reading = bot.read()
        elapsed = time.perf_counter() - started
    finally:
        bot.stop()
    # Free-running, native MuJoCo would simulate ~40 s in this second; paced, it never runs ahead of the
    # wall clock, and it keeps moving (a loaded machine may hold it back, hence the loose lower bound).
    assert 0.1 * elapsed < reading.time <= elapsed + 0.05
    assert safety.check(reading) is None and abs(bot.truth()["height"] - 0.26) < 0.05
    assert bot.gains == robot.HB40.damping_gains  # stop() leaves it damped


def test_realtime_scheduling_is_taken_where_allowed_and_given_back():
    if not fifo_privileged():
        pytest.skip("no CAP_SYS_NICE and an rtprio limit below the control priority: SCHED_FIFO is not allowed here")
    seen = {}

    def thread():
        seen["granted"] = scheduling.raise_to_realtime()
        seen["during"] = scheduling.is_realtime()
        scheduling.back_to_normal()
        seen["after"] = scheduling.is_realtime()

    worker = threading.Thread(target=thread)
    worker.start()
    worker.join()
    assert seen["granted"] and seen["during"] and not seen["after"]


def test_realtime_scheduling_is_refused_without_the_privilege():
    if fifo_privileged():
        pytest.skip("this process may enter SCHED_FIFO; the refusal needs an unprivileged process")
    assert not granted_in_a_thread(scheduling.raise_to_realtime, scheduling.back_to_normal)
    assert not scheduling.is_realtime()


class _RecordedEvent(threading.Event):
    """An Event that records what each wait asked and got: (timeout, woken by set)."""

    def __init__(self):
        super().__init__()
        self.waits = []

    def wait(self, timeout=None):
        woken = super().wait(timeout)
        self.waits.append((timeout, woken))
        return woken


def test_an_idle_learner_sleeps_until_a_step_is_stored():
    """Idle, it waits on the step event with a timeout (never spins); a stored step ends the wait by itself.
    Decided by what the event recorded, not by timing, so a loaded machine cannot fail it."""
    learner = Learner(update=None, state=None, buffer=None, batch_size=1, key=jax.random.PRNGKey(0),
                      allowed=lambda updates: False)
    learner.new_step = _RecordedEvent()
    learner.start()
    deadline = time.perf_counter() + 10.0
    while len(learner.new_step.waits) < 2 and time.perf_counter() < deadline:
        time.sleep(0.01)
    idle = list(learner.new_step.waits)
    assert len(idle) >= 2 and all(timeout == 0.1 and not woken for timeout, woken in idle)  # timed out, asleep
    learner.new_step.set()
    while not any(woken for _, woken in learner.new_step.waits) and time.perf_counter() < deadline:
        time.sleep(0.01)
    learner.stop()
    assert any(woken for _, woken in learner.new_step.waits[len(idle):])  # the stored step woke it


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


def test_the_loop_starts_from_an_agent_trained_in_mjx(tmp_path):
    """--init-from: the MJX run's saved agent of the chosen seed is the loop's first agent, and it learns on."""
    from mjx_badger import checkpoints, runner
    from mjx_badger.realtime import pretrained
    from mjx_badger.train import TrainConfig

    trained = TrainConfig(approach="jt-oef", algo="crossq", protocol="thesis-text", total_steps=200, chunk_steps=100,
                          warmup_steps=100, eval_steps=10, agent=TINY.agent_config)
    path = tmp_path / "mjx" / "jt-oef_crossq_forward.json"
    runner.run(trained, [3, 4], path, progress=False)
    config = dataclasses.replace(TINY, init_from=str(path), init_seed=4, eval_seconds=0.0)
    _, _, agent, *_ = control.build(config)
    start = pretrained.load(config, agent)
    saved = checkpoints.load_agents(path, jax.vmap(agent.init)(jax.random.split(jax.random.PRNGKey(9), 2)))
    for a, b in zip(jax.tree.leaves(start), jax.tree.leaves(saved)):
        np.testing.assert_array_equal(a, b[1])
    assert int(start.updates) == 100  # the MJX run's updates: 200 steps, 100 of them warm-up
    document = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path / "robot", resume=False, view=False)
    assert document["complete"] and document["updates"] > 0
    # A run that observed as the released code does cannot start the robot's loop.
    document = json.loads(path.read_text())
    document["config"]["protocol"] = "thesis-code"
    (tmp_path / "code.json").write_text(json.dumps(document))
    with pytest.raises(ValueError, match="its protocol is 'thesis-code', this run's 'thesis-text'"):
        dataclasses.replace(TINY, init_from=str(tmp_path / "code.json"))
    with pytest.raises(ValueError, match="holds seeds \\[3, 4\\], not 0"):
        dataclasses.replace(TINY, init_from=str(path), init_seed=0)
