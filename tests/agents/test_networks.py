"""The shared networks: batch renormalisation, the tanh-Gaussian policy's log-probability and action, dropout."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.agents.losses import actor_variables
from mjx_badger.agents.networks import Actor, BatchRenorm, Critic, hashed_keep_mask, sample_action
from tests.agents.conftest import ACT, OBS


def test_batch_renorm_train_uses_batch_statistics_eval_uses_running_ones():
    layer = BatchRenorm(momentum=0.9)
    x = 3.0 + 2.0 * jax.random.normal(jax.random.PRNGKey(0), (512, 4))
    variables = layer.init(jax.random.PRNGKey(1), x, train=False)
    y, updated = layer.apply(variables, x, train=True, mutable=["batch_stats"])
    np.testing.assert_allclose(y.mean(0), 0.0, atol=1e-4)
    np.testing.assert_allclose(y.std(0), 1.0, atol=1e-3)
    # running mean moved 10 % of the way from 0 towards the batch mean (about 3)
    np.testing.assert_allclose(updated["batch_stats"]["mean"], 0.1 * x.mean(0), rtol=1e-5)
    assert int(updated["batch_stats"]["steps"]) == 1
    # evaluation with the initial running stats (mean 0, var 1) is nearly the identity
    y_eval = layer.apply(variables, x, train=False)
    np.testing.assert_allclose(y_eval, x / np.sqrt(1 + 1e-3), rtol=1e-5)


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


def test_hashed_dropout_mask_keeps_the_right_fraction_and_varies_with_the_key():
    a = np.asarray(hashed_keep_mask(jax.random.PRNGKey(0), (256, 256), 0.1))
    b = np.asarray(hashed_keep_mask(jax.random.PRNGKey(1), (256, 256), 0.1))
    assert abs(a.mean() - 0.9) < 0.005 and abs(b.mean() - 0.9) < 0.005
    # Independent masks agree on about 0.9^2 + 0.1^2 = 82 % of the entries.
    assert abs((a == b).mean() - 0.82) < 0.01
    # No structure along rows or columns.
    assert np.abs(a.mean(axis=0) - 0.9).max() < 0.1 and np.abs(a.mean(axis=1) - 0.9).max() < 0.1
