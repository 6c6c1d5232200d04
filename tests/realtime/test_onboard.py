"""An exported policy on the robot's computer, without JAX: the joint targets of the on-robot loop's JAX tick."""

import json
import subprocess
import sys
import time
from pathlib import Path

import jax.numpy as jnp
import mujoco
import numpy as np
import pytest

from mjx_badger.control import actions, filters
from mjx_badger.learning.config import TrainConfig
from mjx_badger.outputs import onnx_export
from mjx_badger.protocol import protocols
from mjx_badger.realtime import control, safety
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.estimation import VelocityEstimator
from mjx_badger.realtime.interface import Sensors
from mjx_badger.realtime.onboard import CentralPattern, Filter, OnboardPolicy
from mjx_badger.realtime.onboard_estimator import Legs
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from mjx_badger.robot import motors

REFERENCE = Path(__file__).resolve().parents[2] / "figures" / "data" / "quick" / "thesis-text" / "real-outdoor"
APPROACHES = ("jt-nf", "jt-oef", "cpg-vf")
"""Committed thesis-text CrossQ policies (forward at 0.25 m/s, outdoor conditions, 40 Hz)."""
STEPS = 200
TOLERANCE = 1e-5
"""rad between the onboard and the JAX tick's joint targets over STEPS steps (measured on 2 CPU cores: JT-NF
1.8e-6, JT-OEF 3e-7, CPG-VF 4.4e-6, the float32 rounding of two implementations)."""


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("onboard")
    return {a: onnx_export.export(REFERENCE / f"{a}_crossq_forward.json", None, folder / f"{a}.onnx")
            for a in APPROACHES}


def walk(policy: OnboardPolicy, steps: int = STEPS):
    """The simulated HB40 (noisy sensors, 200 Hz physics) driven by the onboard policy at its rate, as the robot
    server drives the robot: every reading, every target, the seconds of every step, the robot."""
    bot = SimulatedHB40(seed=3)
    motors.set_pd_gains(bot.model, policy.kp, policy.kd)
    substeps = round(policy.control_dt / bot.physics_dt)
    command = policy.settings["task"]["command"]
    policy.reset()
    readings, targets, seconds = [bot.read()], [], []
    for _ in range(steps):
        s = readings[-1]
        start = time.perf_counter()
        target, _, _ = policy.step(s.joint_angle, s.joint_velocity, s.joint_torque, s.acceleration,
                                   s.angular_velocity, s.orientation, command)
        seconds.append(time.perf_counter() - start)
        targets.append(target.copy())
        for _ in range(substeps):
            bot.data.ctrl[:] = target
            mujoco.mj_step(bot.model, bot.data)
            reading = bot._measure()  # the sensor model reads at the physics rate, as the robot's thread does
        readings.append(reading)
    return readings[:-1], np.array(targets), np.array(seconds), bot


@pytest.mark.parametrize("approach", APPROACHES)
def test_the_onboard_policy_sends_the_targets_of_the_on_robot_loops_jax_tick(exported, approach):
    """200 steps (5 s) of a simulated robot walking with the onboard policy; the same readings through the loop's
    VelocityEstimator and evaluate_tick (the saved actor in its JAX agent) give the same joint targets."""
    policy = OnboardPolicy(exported[approach])
    readings, targets, seconds, bot = walk(policy)
    _, config, actor = onnx_export.saved(REFERENCE / f"{approach}_crossq_forward.json", None)
    realtime = RealtimeConfig(approach=approach, algo="crossq", control_hz=policy.settings["control_hz"],
                              agent=config.agent_config)
    env, _, agent, _, evaluate_tick, _ = control.build(realtime)
    state = onnx_export.agent_state(agent, actor)
    estimator, action_state = VelocityEstimator(), env.action_space.init()
    command, prev_gyro, expected = np.float32(policy.settings["task"]["command"]), readings[0].angular_velocity, []
    for s in readings:
        velocity = estimator.update(s, policy.control_dt)
        measured = control.measured_step(s, prev_gyro, velocity)
        action_state, target = evaluate_tick(state, action_state, command, measured)
        prev_gyro = s.angular_velocity
        expected.append(np.asarray(target))
    difference = np.abs(targets - np.array(expected)).max()
    print(f"{approach}: onboard vs JAX tick, max |target difference| {difference:.2e} rad over {STEPS} steps; "
          f"one step {1e3 * np.median(seconds):.2f} ms median, {1e3 * seconds.max():.2f} ms max")
    assert difference <= TOLERANCE
    assert bot.data.qpos[2] > 0.15 and np.ptp(targets, axis=0).max() > 0.05  # it stood and moved its legs
    assert np.median(seconds) < 0.025  # a 40 Hz period; measured about 0.3 ms


def test_the_onboard_policy_runs_without_jax(exported):
    """In a process where JAX and flax cannot be imported: the same targets, and no module of the package but its
    own."""
    s = SimulatedHB40(seed=1).read()
    args = [np.asarray(x).tolist() for x in (s.joint_angle, s.joint_velocity, s.joint_torque, s.acceleration,
                                             s.angular_velocity, s.orientation)] + [[0.25, 0.0, 0.0]]
    script = ("import sys; sys.modules['jax'] = None; sys.modules['flax'] = None\n"
              "import json\n"
              "from mjx_badger.realtime.onboard import OnboardPolicy\n"
              f"policy = OnboardPolicy({str(exported['jt-oef'])!r})\n"
              f"targets, kp, kd = policy.step(*{args!r})\n"
              "ours = sorted(m for m in sys.modules if m.split('.')[0] == 'mjx_badger')\n"
              "print(json.dumps([targets.tolist(), kp, kd, ours]))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    targets, kp, kd, modules = json.loads(done.stdout)
    np.testing.assert_allclose(targets, OnboardPolicy(exported["jt-oef"]).step(*args)[0], atol=1e-7)
    assert (kp, kd) == (60.0, 3.0)
    assert modules == ["mjx_badger", "mjx_badger.realtime", "mjx_badger.realtime.onboard",
                       "mjx_badger.realtime.onboard_estimator"]


@pytest.mark.parametrize("name, params", [
    ("none", {}), ("lowpass", {"cutoff_hz": 0.4}), ("butterworth", {"cutoff_hz": 4.0, "design_hz": 40.0}),
    ("butterworth", {"cutoff_hz": 3.0, "design_hz": None}),
    ("one_euro", {"min_cutoff": 2.5, "beta": 0.1, "d_cutoff": 100.0, "start_at_first_input": False}),
    ("one_euro", {"min_cutoff": 1.0, "beta": 0.5, "d_cutoff": 30.0, "start_at_first_input": True})])
def test_every_filter_filters_as_the_jax_one(name, params):
    """Each filter of both protocols (thesis-code's Butterworth and first-input One Euro too), started at a pose."""
    dt, x0 = 0.02, robot.nominal_pose()
    inputs = x0 + np.random.default_rng(0).normal(0.0, 0.3, (30, 12)).astype(np.float32)
    jax_filter, ours = filters.make_filter(name, dt, **params), Filter(name, dt, params)
    state = jax_filter.init(jnp.asarray(x0))
    ours.reset(x0)
    for x in inputs:
        state, expected = jax_filter.step(state, jnp.asarray(x))
        np.testing.assert_allclose(ours(x), expected, atol=2e-5)


@pytest.mark.parametrize("approach", ["cpg-rt-avg", "cpg-rt-sum"])
def test_the_residual_cpgs_step_and_observe_as_the_jax_ones(approach):
    """The CPG-RT modes a robot can run (one PD controller per joint), which no committed policy exercises."""
    settings = {"cpg": onnx_export.cpg_settings(TrainConfig(approach=approach, protocol="thesis-text")),
                "control_dt": 0.025}
    ours = CentralPattern(settings, robot.nominal_pose().astype(np.float64), Legs(onnx_export.leg_figures(robot.HB40)))
    space = actions.make_action_space(approach, 0.025, protocols.THESIS_TEXT)
    state = space.init()
    ours.reset()
    for action in np.random.default_rng(2).uniform(-1.2, 1.2, (8, space.size)).astype(np.float32):
        state, expected = space.step(state, jnp.asarray(action))
        np.testing.assert_allclose(ours.step(action), expected, atol=2e-5)
        for got, want in zip(ours.observe(), space.observe(state)):
            np.testing.assert_allclose(got, want, atol=2e-5)


def test_the_safety_trip_is_the_on_robot_loops(exported):
    policy = OnboardPolicy(exported["jt-nf"])
    standing, zeros = robot.nominal_pose().astype(np.float64), np.zeros(12)
    bent = standing.copy()
    bent[4] = 2.0  # FR thigh past its 1.57 rad
    for angles, quaternion in ((standing, [1.0, 0, 0, 0]), (standing, [np.cos(0.5), np.sin(0.5), 0, 0]),
                               (standing, [np.cos(0.45), 0, np.sin(0.45), 0]), (bent, [1.0, 0, 0, 0])):
        sensors = Sensors(0.0, angles, zeros, zeros, np.zeros(3), np.zeros(3), np.asarray(quaternion))
        assert policy.trip(angles, quaternion) == safety.check(sensors)
    assert policy.trip(bent, [1.0, 0, 0, 0]) == "FR_thigh at +2.00 rad, outside its range"


def test_a_missing_or_foreign_settings_file_is_refused_in_one_line(exported, tmp_path):
    onnx_path = tmp_path / "p.onnx"
    onnx_path.write_bytes(exported["jt-nf"].read_bytes())
    with pytest.raises(ValueError, match="p.onboard.json: cannot read the policy's onboard settings"):
        OnboardPolicy(onnx_path)
    (tmp_path / "p.onboard.json").write_text(json.dumps({"schema": "mjx_badger.results/2"}))
    with pytest.raises(ValueError, match="not a mjx_badger.onboard/1 file"):
        OnboardPolicy(onnx_path)
