"""Running moments, return-based reward scaling and unit-sphere kernels against numbers worked by hand."""

import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import normalisers


def test_moments_merged_batch_by_batch_equal_those_of_all_the_data():
    data = np.random.default_rng(0).normal(3.0, 2.0, (300, 2))
    running = normalisers.moments(2)
    for batch in np.split(data, 3):
        running = normalisers.merge(running, jnp.asarray(batch))
    np.testing.assert_allclose(running.mean, data.mean(axis=0), rtol=1e-3)
    np.testing.assert_allclose(running.var, data.var(axis=0), rtol=1e-3)
    first = normalisers.merge(normalisers.moments(1), jnp.array([[0.0], [2.0]]))
    np.testing.assert_allclose([first.mean[0], first.var[0], first.count], [1.0, 1.0, 2.0], rtol=1e-3)
    np.testing.assert_allclose(normalisers.normalise(first, jnp.array([3.0])), [2.0], rtol=1e-3)


def test_the_return_restarts_at_the_step_that_ends_an_episode():
    scale = normalisers.RewardScale(returns=jnp.array([1.0, 2.0]), moments=normalisers.moments(), largest=0.0)
    after = normalisers.observe_reward(scale, jnp.array([1.0, 1.0]), jnp.array([0.0, 1.0]), 0.99)
    np.testing.assert_allclose(after.returns, [1.99, 1.0])
    assert float(after.largest) == np.float32(1.99)


def test_rewards_are_divided_by_the_returns_spread_or_by_the_largest_return_over_g_max():
    scale = normalisers.RewardScale(returns=jnp.float32(0.0), largest=jnp.float32(30.0),
                                    moments=normalisers.Moments(mean=0.0, var=jnp.float32(4.0), count=10.0))
    assert abs(float(normalisers.reward_divisor(scale, "return-std", 5.0)) - 2.0) < 1e-6
    assert abs(float(normalisers.reward_divisor(scale, "return-std-gmax", 5.0)) - 6.0) < 1e-6  # max(2, 30 / 5)
    assert abs(float(normalisers.reward_divisor(scale, "return-std-gmax", 60.0)) - 2.0) < 1e-6


def test_unit_kernels_puts_each_units_incoming_weights_on_the_sphere_and_leaves_the_rest():
    params = {"Dense_0": {"kernel": jnp.array([[3.0, 0.0], [4.0, 2.0]]), "bias": jnp.array([3.0, 4.0])},
              "scale": jnp.array([2.0, 2.0]), "ensemble": {"kernel": jnp.ones((2, 4, 3))}}
    projected = normalisers.unit_kernels(params)
    np.testing.assert_allclose(projected["Dense_0"]["kernel"], [[0.6, 0.0], [0.8, 1.0]])
    np.testing.assert_allclose(projected["Dense_0"]["bias"], [3.0, 4.0])
    np.testing.assert_allclose(projected["scale"], [2.0, 2.0])
    np.testing.assert_allclose(projected["ensemble"]["kernel"], np.full((2, 4, 3), 0.5))  # per member, per unit
    assert float(normalisers.unit_kernels(jnp.float32(3.0))) == 3.0  # a bare leaf such as log alpha


def test_each_environment_keeps_its_own_return():
    scale = normalisers.reward_scale(3)
    scale = normalisers.observe_reward(scale, jnp.array([1.0, 2.0, 3.0]), jnp.array([0.0, 1.0, 0.0]), 0.5)
    scale = normalisers.observe_reward(scale, jnp.array([1.0, 1.0, 1.0]), jnp.array([0.0, 0.0, 1.0]), 0.5)
    np.testing.assert_allclose(scale.returns, [1.5, 2.0, 1.0])  # the third ended its episode at this step
    assert float(scale.moments.count) > 5.9  # six returns seen
