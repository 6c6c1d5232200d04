"""The shared networks: the tanh-Gaussian policy's log-probability and action, dropout in the critic."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.agents.losses import actor_variables
from mjx_badger.agents.networks import Actor, Critic, sample_action
from tests.agents.conftest import ACT, OBS


def test_tanh_gaussian_log_prob_matches_change_of_variables():
    mean, log_std = jnp.array([[0.3, -0.2]]), jnp.array([[-0.5, 0.1]])
    action, log_prob = sample_action(mean, log_std, jax.random.PRNGKey(0))
    raw = jnp.arctanh(action)
    std = jnp.exp(log_std)
    gauss = -0.5 * ((raw - mean) / std) ** 2 - log_std - 0.5 * jnp.log(2 * jnp.pi)
    expected = jnp.sum(gauss - jnp.log(1 - action**2), axis=-1)
    np.testing.assert_allclose(log_prob, expected, rtol=1e-4)


def test_deterministic_action_is_tanh_of_mean_and_in_bounds(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    obs = jax.random.normal(jax.random.PRNGKey(1), (5, OBS)) * 10
    a = crossq.act(state, obs, None, deterministic=True)
    b = crossq.act(state, obs, jax.random.PRNGKey(2))
    mean, _ = Actor(ACT).apply(actor_variables(state.actor_params, state.actor_stats), obs)
    np.testing.assert_allclose(np.asarray(a), np.tanh(np.asarray(mean)), atol=1e-6)
    assert a.shape == b.shape == (5, ACT) and float(jnp.abs(b).max()) <= 1.0


def test_dropout_is_active_only_in_training():
    cfg = ALGORITHMS["droq"]()
    critic = Critic(hidden=(64, 64), dropout_rate=cfg.dropout_rate * 10, layer_norm=True)
    obs, action = jnp.ones((5, 54)), jnp.ones((5, 12))
    variables = critic.init(jax.random.PRNGKey(0), obs, action)
    eval_a = critic.apply(variables, obs, action, train=False, rngs={"dropout": jax.random.PRNGKey(1)})
    eval_b = critic.apply(variables, obs, action, train=False, rngs={"dropout": jax.random.PRNGKey(2)})
    train_a = critic.apply(variables, obs, action, train=True, rngs={"dropout": jax.random.PRNGKey(1)})
    train_b = critic.apply(variables, obs, action, train=True, rngs={"dropout": jax.random.PRNGKey(2)})
    np.testing.assert_array_equal(eval_a, eval_b)
    assert not np.allclose(train_a, train_b)
    assert not np.allclose(train_a, eval_a)
