"""What the env observes: the protocol's blocks and scales, and under on-robot conditions the robot's own estimate."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.control import actions
from mjx_badger.estimation import estimators, sensors
from mjx_badger.learning.config import TrainConfig
from mjx_badger.outputs.estimator_figures import replay
from mjx_badger.protocol import conditions, protocols
from mjx_badger.records import results
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.sim.observation import observation_layout


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
    again = replay(estimators.make("kinematic-kalman"), readings, np.zeros(len(a), bool), sensing_env.control_dt)
    np.testing.assert_allclose(again, np.array([e for _, e, _ in a]), atol=1e-5)


def test_without_sensing_nothing_changes_in_the_env_or_its_results_document():
    env = HB40Env("jt-oef", "forward")
    assert "estimated_forward_velocity" not in env._metric_names()
    assert "sensing" not in results.config_dict(TrainConfig())["env"]
    assert "estimate" not in jax.eval_shape(env.reset, jax.random.PRNGKey(0)).info


OFFICE_TRUE_VELOCITY = conditions.OFFICE.replace(estimate_in_loop=False)


def _walk(env, steps=25, key=0):
    step = jax.jit(env.step)
    state = jax.jit(env.reset)(jax.random.PRNGKey(key))
    for i in range(steps):
        state = step(state, 0.4 * jnp.sin(0.4 * i + jnp.arange(env.action_size)))
    return jax.device_get(state)


def test_the_estimate_not_the_truth_reaches_the_reward_and_the_observation(office):
    state = _walk(office)
    estimate, truth = state.info["estimate"], state.metrics["forward_velocity"]
    assert abs(estimate[0] - truth) > 1e-3  # they differ, so the test can tell them apart
    assert state.reward == pytest.approx(float(estimate[0]), abs=1e-6)
    layout = [name for name, size, _ in office.observation_layout for _ in range(size)]
    velocity = [i for i, name in enumerate(layout) if name == "trunk_linear_velocity"]
    np.testing.assert_allclose(state.obs[velocity], estimate, atol=1e-6)  # thesis-code scales velocity by 1
    # Swapped back to the truth, the reward is the true forward velocity.
    swapped = _walk(HB40Env("jt-oef", office.task, EnvConfig(conditions=OFFICE_TRUE_VELOCITY)))  # the same probe
    assert swapped.reward == pytest.approx(float(swapped.metrics["forward_velocity"]), abs=1e-6)


CODE, TEXT = protocols.THESIS_CODE, protocols.THESIS_TEXT


def test_the_observed_acceleration_is_the_codes_qacc_or_the_texts_accelerometer(env, env_fns):
    """At reset the robot drops from 0.316 m: qacc reads free fall (-9.81 m/s^2 up), an accelerometer 0."""
    code = env_fns[0](jax.random.PRNGKey(0)).obs[36:39]
    text = jax.jit(HB40Env("jt-nf", "forward", EnvConfig(protocol=TEXT)).reset)(jax.random.PRNGKey(0)).obs[36:39]
    np.testing.assert_allclose(code, [0.0, 0.0, -9.81], atol=1e-4)
    np.testing.assert_allclose(text, [0.0, 0.0, 0.0], atol=1e-4)


def test_observation_scales_follow_the_protocol():
    code = {n: s for n, _, s in observation_layout(actions.make_action_space("jt-nf", 0.02, CODE), CODE)}
    text = {n: s for n, _, s in observation_layout(actions.make_action_space("jt-nf", 0.02, TEXT), TEXT)}
    assert code["joint_angle"] == pytest.approx(1 / 3.14) and code["joint_velocity"] == pytest.approx(1 / 25)
    assert code["trunk_angular_velocity"] == pytest.approx(0.1)
    assert text["joint_angle"] == 1.0 and text["joint_velocity"] == 0.1
