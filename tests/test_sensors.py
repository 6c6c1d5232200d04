"""The robot's senses: the sensor model, the env's readings and estimate, and the learned estimator's files."""

import dataclasses
import json

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest
from mujoco import mjx

from mjx_badger import estimators, learned_estimator, mjcf, results, robot, sensors
from mjx_badger.env import EnvConfig, HB40Env

DT = 0.025


def _truth(acceleration=(0.0, 0.0, 9.81)):
    pose = jnp.asarray(robot.nominal_pose())
    return sensors.Truth(pose, jnp.zeros(12), jnp.zeros(12), jnp.asarray(acceleration), jnp.zeros(3), jnp.eye(3),
                         jnp.ones(4))


def test_the_exact_model_reads_the_truth_and_the_default_one_quantises_the_encoders():
    truth = _truth()
    _, exact = sensors.read(sensors.EXACT, sensors.init(sensors.EXACT), truth, sensors.draw(jax.random.PRNGKey(0)), DT)
    for got, want in zip(exact[:5], (truth.joint_angle, truth.joint_velocity, truth.acceleration,
                                     truth.angular_velocity, truth.rotation)):
        np.testing.assert_allclose(got, want, atol=1e-6)
    model = sensors.SensorModel()
    _, noisy = sensors.read(model, sensors.init(model), truth, sensors.no_draws(), DT)
    steps = np.asarray(noisy.joint_angle) / model.encoder_resolution
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-3)  # whole encoder counts
    assert np.max(np.abs(np.asarray(noisy.joint_angle) - np.asarray(truth.joint_angle))) <= model.encoder_resolution / 2


def test_white_noise_has_its_density_and_the_bias_walks_as_the_square_root_of_time():
    """Per reading over dt the accelerometer's white noise has std density / sqrt(2 dt): 1.7e-3 / sqrt(0.05) = 0.0076;
    a bias walk of 1e-3 m/s^2/sqrt(s) is off by std 1e-3 sqrt(100) = 0.01 after 100 s (4000 readings)."""
    model = dataclasses.replace(sensors.EXACT, accelerometer_noise_density=1.7e-3, accelerometer_bias_walk=1e-3)
    keys = jax.random.split(jax.random.PRNGKey(1), 2000)
    one = jax.vmap(lambda k: sensors.read(model, sensors.init(sensors.EXACT), _truth(), sensors.draw(k), DT))
    state, reading = one(keys)
    assert np.std(np.asarray(reading.acceleration[:, 0])) == pytest.approx(1.7e-3 / np.sqrt(2 * DT), rel=0.1)

    def walk(key):
        def step(state, k):
            return sensors.read(model, state, _truth(), sensors.draw(k), DT)[0], None
        return jax.lax.scan(step, sensors.init(sensors.EXACT), jax.random.split(key, 4000))[0].accelerometer_bias
    biases = jax.jit(jax.vmap(walk))(jax.random.split(jax.random.PRNGKey(2), 400))
    assert np.std(np.asarray(biases)) == pytest.approx(1e-3 * np.sqrt(4000 * DT), rel=0.15)


def test_numpy_and_jax_read_alike_from_the_same_draws():
    model = sensors.SensorModel()
    draws = sensors.draw_numpy(np.random.default_rng(0))
    state = sensors.init(model, rng=np.random.default_rng(1))
    truth = jax.tree.map(np.asarray, _truth((0.3, -0.1, 9.7)))
    _, with_numpy = sensors.read(model, state, truth, draws, DT, xp=np)
    _, with_jax = sensors.read(model, jax.tree.map(jnp.asarray, state), jax.tree.map(jnp.asarray, truth),
                               jax.tree.map(jnp.asarray, draws), DT)
    for a, b in zip(with_numpy, with_jax):
        np.testing.assert_allclose(a, b, atol=1e-5)


def test_mjx_and_native_mujoco_read_the_same_imu():
    """Ten physics steps of a robot dropped onto its feet with random joint targets, both engines."""
    model = mjcf.load_model()
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    rng = np.random.default_rng(0)
    data.ctrl[:] = robot.nominal_pose() + rng.uniform(-0.2, 0.2, 12)
    mujoco.mj_forward(model, data)
    mx, dx = mjx.put_model(model), mjx.put_data(model, data)
    step = jax.jit(mjx.step)
    for _ in range(10):
        mujoco.mj_step(model, data)
        dx = step(mx, dx)
    for name, tolerance in (("accelerometer", 0.05), ("gyro", 1e-3), ("orientation", 1e-4)):
        where = mjcf.sensor_slice(model, name)
        np.testing.assert_allclose(np.asarray(dx.sensordata[where]), data.sensordata[where], atol=tolerance,
                                   err_msg=name)


@pytest.fixture(scope="module")
def sensing_env():
    return HB40Env("jt-oef", "forward", EnvConfig(sensing=sensors.Sensing()))


def _steps(env, key, n=30):
    step = jax.jit(env.step)
    state = jax.jit(env.reset)(key)
    out = []
    for i in range(n):
        state = step(state, 0.5 * jnp.sin(0.3 * i + jnp.arange(env.action_size)))
        out.append(jax.device_get((state.info["reading"], state.info["estimate"], state.metrics)))
    return out


def test_the_env_reads_noisy_sensors_reproducibly_from_its_key_and_reports_the_estimate(sensing_env):
    a, b, c = (_steps(sensing_env, jax.random.PRNGKey(k)) for k in (0, 0, 1))
    np.testing.assert_array_equal(a[-1][0].acceleration, b[-1][0].acceleration)
    assert not np.allclose(a[-1][0].acceleration, c[-1][0].acceleration)
    reading, estimate, metrics = a[-1]
    assert metrics["estimated_forward_velocity"] == estimate[0]
    # The estimate is the shared estimator's, replayed on the same readings.
    readings = jax.tree.map(lambda *x: np.stack(x), *[r for r, _, _ in a])
    from mjx_badger.estimator_figures import replay
    again = replay(estimators.make("kinematic-kalman"), readings, np.zeros(len(a), bool), sensing_env.control_dt)
    np.testing.assert_allclose(again, np.array([e for _, e, _ in a]), atol=1e-5)


def test_without_sensing_nothing_changes_in_the_env_or_its_results_document():
    env = HB40Env("jt-oef", "forward")
    assert "estimated_forward_velocity" not in env._metric_names()
    from mjx_badger.train import TrainConfig
    assert "sensing" not in results.config_dict(TrainConfig())["env"]
    assert "estimate" not in jax.eval_shape(env.reset, jax.random.PRNGKey(0)).info


def _dataset(robot_name="hb40", steps=60, envs=5, seed=0):
    """A synthetic dataset: the velocity a known function of the readings, so a fit can learn it."""
    rng = np.random.default_rng(seed)
    arrays = {name: rng.normal(size=(steps, envs, size)).astype(np.float32) for name, size in learned_estimator.FIELDS}
    arrays["velocity"] = np.stack([0.3 * arrays["acceleration"][..., 0], 0.1 * arrays["joint_angle"][..., 1],
                                   np.zeros((steps, envs))], -1).astype(np.float32)
    arrays["done"] = rng.random((steps, envs)) < 0.05
    meta = {"robot": robot_name, "fields": [list(f) for f in learned_estimator.FIELDS], "policy": "synthetic",
            "steps": steps, "envs": envs, "task": "none", "control_hz": 40.0}
    return meta, arrays


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    meta, arrays = _dataset()
    config = learned_estimator.FitConfig(epochs=8, batch_size=32)
    document = learned_estimator.fit(meta, arrays, learned_estimator.INPUTS["rich"], config)
    return learned_estimator.save(tmp_path_factory.mktemp("estimator") / "rich.estimator.npz", document)


def test_a_saved_learned_estimator_gives_the_same_velocity_in_numpy_as_in_jax(fitted):
    estimator = learned_estimator.load(fitted)
    curve = estimator.meta["curves"]["train_mae"]
    assert sum(curve[-1]) < sum(curve[0])  # it learned
    meta, arrays = _dataset(seed=3)
    readings = [estimators.Reading(arrays["joint_angle"][t, 0], arrays["joint_velocity"][t, 0],
                                   arrays["acceleration"][t, 0], arrays["angular_velocity"][t, 0],
                                   np.eye(3, dtype=np.float32), arrays["contacts"][t, 0], arrays["joint_torque"][t, 0])
                for t in range(12)]
    runner = estimator.numpy()
    with_numpy = np.array([runner.update(r) for r in readings])
    jax_estimator = estimators.make("learned", path=fitted)
    step = jax.jit(jax_estimator.step)
    state, with_jax = jax_estimator.init(), []
    for r in readings:
        state, velocity = step(state, jax.tree.map(jnp.asarray, r), DT)
        with_jax.append(np.asarray(velocity))
    np.testing.assert_allclose(with_numpy, np.array(with_jax), atol=1e-4)
    assert np.all(with_numpy[:, 2] == 0.0) and np.any(with_numpy[:, 0] != 0.0)


def test_the_windows_of_the_fit_start_afresh_at_every_reset():
    done = np.array([[False], [False], [True], [False], [False]])
    np.testing.assert_array_equal(learned_estimator.since_reset(done)[:, 0], [0, 1, 0, 1, 2])


def _fails(argv, capsys) -> str:
    from mjx_badger import cli
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    return capsys.readouterr().err.strip()


def test_a_dataset_of_another_robot_or_layout_is_refused_with_one_line(tmp_path, capsys):
    other = learned_estimator.save_dataset(tmp_path / "other.npz", *reversed(_dataset("hb40-v1")))
    err = _fails(["estimator", "fit", "--dataset", str(other)], capsys)
    assert err == f"error: {other}: a dataset of robot 'hb40-v1', not 'hb40'"
    meta, arrays = _dataset()
    meta["fields"] = meta["fields"][:-1]
    layout = learned_estimator.save_dataset(tmp_path / "layout.npz", arrays, meta)
    err = _fails(["estimator", "fit", "--dataset", str(layout)], capsys)
    assert err.startswith(f"error: {layout}: its fields") and "\n" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["layout.npz", "other.npz"]  # nothing written


def test_an_unknown_estimator_or_input_set_is_refused(capsys):
    with pytest.raises(ValueError, match="unknown estimator 'ekf'; choose from kinematic-kalman, "
                                         "kinematic-kalman-contact, integration, learned"):
        HB40Env("jt-oef", "forward", EnvConfig(sensing=sensors.Sensing(estimator="ekf")))
    err = _fails(["estimator", "fit", "--inputs", "everything"], capsys)
    assert "everything" in err and "thesis" in err and "rich" in err
    with pytest.raises(ValueError, match="the learned estimator needs its file"):
        estimators.make("learned")
    json.dumps(dataclasses.asdict(sensors.Sensing()))  # a results file can record it


def test_the_on_robot_loops_estimates_are_the_shared_estimators_on_a_recorded_trace():
    """A simulated robot's noisy readings over 2 s of a joint wave, fed to the loop's VelocityEstimator and, as
    Readings, to the shared estimator's scan: the same velocities."""
    from mjx_badger.estimator_figures import replay
    from mjx_badger.realtime import estimation
    from mjx_badger.realtime.simulated import SimulatedHB40

    bot = SimulatedHB40(seed=3)
    trace = []
    for i in range(80):  # 40 Hz: 5 physics steps per reading
        bot.data.ctrl[:] = robot.nominal_pose() + 0.15 * np.sin(0.3 * i + np.arange(12))
        for _ in range(5):
            mujoco.mj_step(bot.model, bot.data)
        trace.append(bot._measure())
    loop = estimation.VelocityEstimator()
    by_loop = np.array([loop.update(s, DT) for s in trace])
    readings = jax.tree.map(lambda *x: np.stack(x), *[estimation.reading(s) for s in trace])
    shared = replay(estimators.make("kinematic-kalman"), readings, np.zeros(len(trace), bool), DT)
    np.testing.assert_allclose(by_loop, shared, atol=1e-5)
    assert np.abs(by_loop).max() > 1e-3  # it moved
