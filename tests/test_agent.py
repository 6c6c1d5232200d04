"""CrossQ: batch renormalisation, the joint forward pass, and learning on a fixed batch."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents import ALGORITHMS, make_agent
from mjx_badger.agents.losses import Transition
from mjx_badger.agents.networks import BatchRenorm, sample_action

OBS, ACT, BATCH = 54, 12, 128


def _batch(key):
    k = jax.random.split(key, 4)
    return Transition(
        obs=jax.random.normal(k[0], (BATCH, OBS)),
        action=jax.random.uniform(k[1], (BATCH, ACT), minval=-1, maxval=1),
        reward=jax.random.uniform(k[2], (BATCH,)) * 10,
        next_obs=jax.random.normal(k[3], (BATCH, OBS)),
        discount=jnp.ones(BATCH),
    )


def test_crossq_config_is_thesis_table_4_3():
    cfg = ALGORITHMS["crossq"]()
    assert (cfg.learning_rate, cfg.batch_size, cfg.hidden, cfg.ensemble_size, cfg.gamma) == (
        0.005, 128, (256, 256), 2, 0.99)
    assert cfg.target_entropy_per_action == -0.5 and cfg.updates_per_step == 1 and cfg.control_hz == 40
    assert cfg.batch_renorm and not cfg.target_network  # CrossQ: no target network


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


@pytest.fixture(scope="module")
def crossq():
    return make_agent(ALGORITHMS["crossq"](), OBS, ACT)


def test_crossq_critic_loss_decreases_on_a_fixed_batch(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    batch = _batch(jax.random.PRNGKey(1))

    @jax.jit
    def run(state):
        def body(state, i):
            state, metrics = crossq.update(state, batch, jax.random.PRNGKey(2), i)
            return state, (metrics["critic_loss"], metrics["actor_loss"])

        return jax.lax.scan(body, state, jnp.arange(150))

    state, (losses, actor_losses) = run(state)
    losses = np.asarray(losses)
    assert np.isfinite(losses).all()
    assert losses[-10:].mean() < 0.5 * losses[:10].mean(), f"critic loss {losses[:10].mean()} -> {losses[-10:].mean()}"
    # Policy delay 3: the actor moved 50 times (a finite actor loss), the critic 150 times.
    assert int(np.isfinite(np.asarray(actor_losses)).sum()) == 50
    assert int(state.updates) == 150


def test_actor_updates_only_every_policy_delay(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    batch = _batch(jax.random.PRNGKey(1))
    update = jax.jit(crossq.update)
    moved = []
    for i in range(6):
        new, metrics = update(state, batch, jax.random.PRNGKey(i), i)
        changed = jax.tree.leaves(jax.tree.map(lambda a, b: bool(jnp.any(a != b)), new.actor_params,
                                               state.actor_params))
        moved.append(any(changed))
        assert np.isnan(metrics["actor_loss"]) != moved[-1]
        state = new
    assert moved == [True, False, False, True, False, False]


def test_deterministic_action_is_tanh_of_mean_and_in_bounds(crossq):
    from mjx_badger.agents.losses import actor_variables
    from mjx_badger.agents.networks import Actor

    state = crossq.init(jax.random.PRNGKey(0))
    obs = jax.random.normal(jax.random.PRNGKey(1), (5, OBS)) * 10
    a = crossq.act(state, obs, None, deterministic=True)
    b = crossq.act(state, obs, jax.random.PRNGKey(2))
    mean, _ = Actor(ACT).apply(actor_variables(state.actor_params, state.actor_stats), obs)
    np.testing.assert_allclose(np.asarray(a), np.tanh(np.asarray(mean)), atol=1e-6)
    assert a.shape == b.shape == (5, ACT) and float(jnp.abs(b).max()) <= 1.0
