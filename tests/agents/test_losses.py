"""The losses by hand: the critic's and actor's and temperature's on constant networks, target updates, CrossQ's descent."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.agents.losses import Transition, make_losses
from mjx_badger.agents.networks import Actor, Critic
from tests.agents.conftest import random_batch


def test_crossq_critic_loss_decreases_on_a_fixed_batch(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    batch = random_batch(jax.random.PRNGKey(1))

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


ALPHA = 0.5


Q_BIASES = (1.0, 2.0)  # the two critics' outputs once every kernel is zero


MEAN_BIAS = 0.5


HAND_BATCH = Transition(obs=jnp.array([[0.1, -0.2], [0.3, 0.4], [-0.5, 0.6]]),
                        action=jnp.array([[0.2], [-0.4], [0.9]]),
                        reward=jnp.array([1.0, 2.0, 3.0]),
                        next_obs=jnp.array([[0.0, 0.1], [0.2, -0.3], [0.4, 0.5]]),
                        discount=jnp.array([1.0, 1.0, 0.0]))
"""Three transitions whose losses are worked out by hand below."""


def _constant_networks(name):
    """Tiny agent (obs 2, action 1, one hidden layer of 4) whose kernels are all zero.

    Then every Q = its output bias (batch renorm of zeros stays zero) and the actor's mean
    and log-std are their biases: mean 0.5, log_std = -10 + 6 (tanh(0) + 1) = -4.
    """
    cfg = ALGORITHMS[name]().replace(hidden=(4,), dropout_rate=0.0)  # the text's actor: no batch renorm
    agent = make_agent(cfg, 2, 1)
    state = agent.init(jax.random.PRNGKey(0))
    zero = lambda tree: jax.tree.map(jnp.zeros_like, tree)
    actor = zero(state.actor_params)
    actor["params"]["Dense_1"]["bias"] = jnp.array([MEAN_BIAS])
    critic = jax.tree_util.tree_map_with_path(
        lambda path, x: jnp.ones_like(x) if "scale" in str(path) else jnp.zeros_like(x), state.critic_params)
    critic["VmapQNetwork_0"]["Dense_1"]["bias"] = jnp.array([[Q_BIASES[0]], [Q_BIASES[1]]])
    return cfg, state.replace(actor_params=actor, critic_params=critic,
                              target_params=critic if cfg.target_network else None,
                              log_alpha=jnp.log(jnp.float32(ALPHA)))


def _hand_log_prob(eps):
    """log pi of tanh(0.5 + e^-4 eps): Gaussian density at raw minus log(1 - tanh(raw)^2)."""
    raw = MEAN_BIAS + math.exp(-4.0) * eps
    return -0.5 * eps**2 + 4.0 - 0.5 * math.log(2 * math.pi) - np.log(1 - np.tanh(raw) ** 2)


@pytest.mark.parametrize("name", ["sac", "crossq"])
def test_critic_loss_by_hand(name):
    cfg, state = _constant_networks(name)
    actor = Actor(action_size=1, hidden=cfg.hidden)
    critic = Critic(hidden=cfg.hidden, batch_renorm=cfg.batch_renorm)
    losses = make_losses(actor, critic, cfg, 1)
    key = jax.random.PRNGKey(7)
    loss, (_, metrics, _) = losses.critic(state.critic_params, state.critic_stats, state.target_params,
                                       state.actor_params, state.actor_stats, state.log_alpha, HAND_BATCH, key)
    # Next actions use the first half of the key; the noise is the only thing not set by hand.
    eps = np.asarray(jax.random.normal(jax.random.split(key)[0], (3, 1)))[:, 0]
    log_prob = _hand_log_prob(eps)
    # target = r + 0.99 d (min(1, 2) - 0.5 log pi); Q1 = 1, Q2 = 2
    target = np.array([1.0, 2.0, 3.0]) + 0.99 * np.array([1, 1, 0]) * (1.0 - ALPHA * log_prob)
    expected = 0.5 * (np.mean((1.0 - target) ** 2) + np.mean((2.0 - target) ** 2))
    assert float(loss) == pytest.approx(expected, rel=1e-5)
    assert float(metrics["q_mean"]) == pytest.approx(1.5)


def test_actor_and_temperature_losses_by_hand():
    cfg, state = _constant_networks("sac")
    losses = make_losses(Actor(action_size=1, hidden=cfg.hidden), Critic(hidden=cfg.hidden), cfg, 1)
    key = jax.random.PRNGKey(3)
    loss, (log_prob, _) = losses.actor(state.actor_params, state.actor_stats, state.critic_params,
                                       state.critic_stats, state.log_alpha, HAND_BATCH.obs, key)
    eps = np.asarray(jax.random.normal(key, (3, 1)))[:, 0]
    hand = _hand_log_prob(eps)
    np.testing.assert_allclose(log_prob, hand, rtol=1e-5)
    # mean(alpha log pi - min(Q1, Q2)) = mean(0.5 log pi - 1)
    assert float(loss) == pytest.approx(np.mean(ALPHA * hand - 1.0), rel=1e-5)
    # J(alpha) = -mean(log alpha (log pi + target entropy)), target entropy = -|A| / 2 = -0.5
    alpha_loss = losses.alpha(state.log_alpha, log_prob)
    assert float(alpha_loss) == pytest.approx(-math.log(ALPHA) * np.mean(hand - 0.5), rel=1e-5)


def test_target_network_moves_by_tau_per_update():
    cfg = ALGORITHMS["sac"]().replace(hidden=(8,))
    agent = make_agent(cfg, 2, 1)
    state = agent.init(jax.random.PRNGKey(0))
    # Start the target away from the critic so the Polyak step is visible.
    state = state.replace(target_params=jax.tree.map(lambda x: x + 1.0, state.target_params))
    new, _ = jax.jit(agent.update)(state, HAND_BATCH, jax.random.PRNGKey(1), 0)
    expected = jax.tree.map(lambda c, t: cfg.tau * c + (1 - cfg.tau) * t, new.critic_params, state.target_params)
    for got, want in zip(jax.tree.leaves(new.target_params), jax.tree.leaves(expected)):
        np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-7)
    # CrossQ keeps no target critic at all: its state carries none and an update leaves it so.
    crossq = make_agent(ALGORITHMS["crossq"]().replace(hidden=(8,), batch_size=4), 2, 1)
    crossq_state = crossq.init(jax.random.PRNGKey(0))
    assert crossq_state.target_params is None
    assert jax.jit(crossq.update)(crossq_state, HAND_BATCH, jax.random.PRNGKey(1), 0)[0].target_params is None
