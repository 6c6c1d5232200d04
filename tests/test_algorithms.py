"""The SAC family: Table 4.3 configs, losses by hand, Polyak targets, dropout, update counts, smoke runs."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from conftest import seed_keys
from mjx_badger.agents import ALGORITHMS, make_agent
from mjx_badger.agents.losses import Transition, make_losses
from mjx_badger.agents.networks import Actor, Critic
from mjx_badger.train import TrainConfig, make_train

ALPHA = 0.5
Q_BIASES = (1.0, 2.0)  # the two critics' outputs once every kernel is zero
MEAN_BIAS = 0.5


def test_table_4_3():
    expected = {  # lr, batch, updates per step, target network, control Hz
        "sac": (0.003, 256, 1, True, 20.0),
        "sac-utd20": (0.003, 256, 20, True, 20.0),
        "droq": (0.001, 256, 20, True, 20.0),
        "crossq": (0.005, 128, 1, False, 40.0),
    }
    for name, values in expected.items():
        cfg = ALGORITHMS[name]()
        assert (cfg.learning_rate, cfg.batch_size, cfg.updates_per_step, cfg.target_network, cfg.control_hz) == values
        assert cfg.hidden == (256, 256) and cfg.ensemble_size == 2 and cfg.gamma == 0.99
        assert cfg.target_entropy_per_action == -0.5
    droq = ALGORITHMS["droq"]()
    assert droq.dropout_rate > 0 and droq.layer_norm and not droq.batch_renorm


def test_train_config_takes_the_control_rate_from_the_protocol():
    # thesis-text: each algorithm at its Table 4.3 rate; thesis-code: JT at 50 Hz, CPG at 40 Hz, any algorithm.
    text = dict(protocol="thesis-text")
    assert TrainConfig(algo="crossq", **text).env_config.control_hz == 40.0
    assert TrainConfig(algo="droq", **text).env_config.control_hz == 20.0
    assert TrainConfig(algo="droq").env_config.control_hz == 50.0
    assert TrainConfig(algo="sac", approach="cpg-d").env_config.control_hz == 40.0


def test_protocols_configure_crossq_and_the_many_update_algorithms():
    code, text = TrainConfig(algo="crossq").agent_config, TrainConfig(algo="crossq", protocol="thesis-text").agent_config
    assert (code.policy_delay, code.renorm_warmup_steps, code.actor_batch_renorm, code.target_entropy) == (
        1, 1000, True, -6.0)
    assert (text.policy_delay, text.renorm_warmup_steps, text.actor_batch_renorm, text.target_entropy) == (
        3, 100_000, False, None)
    assert TrainConfig(algo="droq").agent_config.actor_updates_per_step == 1
    assert TrainConfig(algo="droq", protocol="thesis-text").agent_config.actor_updates_per_step is None


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


BATCH = Transition(obs=jnp.array([[0.1, -0.2], [0.3, 0.4], [-0.5, 0.6]]),
                   action=jnp.array([[0.2], [-0.4], [0.9]]),
                   reward=jnp.array([1.0, 2.0, 3.0]),
                   next_obs=jnp.array([[0.0, 0.1], [0.2, -0.3], [0.4, 0.5]]),
                   discount=jnp.array([1.0, 1.0, 0.0]))


@pytest.mark.parametrize("name", ["sac", "crossq"])
def test_critic_loss_by_hand(name):
    cfg, state = _constant_networks(name)
    actor = Actor(action_size=1, hidden=cfg.hidden)
    critic = Critic(hidden=cfg.hidden, batch_renorm=cfg.batch_renorm)
    losses = make_losses(actor, critic, cfg, 1)
    key = jax.random.PRNGKey(7)
    loss, (_, metrics) = losses.critic(state.critic_params, state.critic_stats, state.target_params,
                                       state.actor_params, state.actor_stats, state.log_alpha, BATCH, key)
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
                                       state.critic_stats, state.log_alpha, BATCH.obs, key)
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
    new, _ = jax.jit(agent.update)(state, BATCH, jax.random.PRNGKey(1), 0)
    expected = jax.tree.map(lambda c, t: cfg.tau * c + (1 - cfg.tau) * t, new.critic_params, state.target_params)
    for got, want in zip(jax.tree.leaves(new.target_params), jax.tree.leaves(expected)):
        np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-7)
    # CrossQ keeps no target critic at all: its state carries none and an update leaves it so.
    crossq = make_agent(ALGORITHMS["crossq"]().replace(hidden=(8,), batch_size=4), 2, 1)
    crossq_state = crossq.init(jax.random.PRNGKey(0))
    assert crossq_state.target_params is None
    assert jax.jit(crossq.update)(crossq_state, BATCH, jax.random.PRNGKey(1), 0)[0].target_params is None


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
    from mjx_badger.agents.networks import hashed_keep_mask

    a = np.asarray(hashed_keep_mask(jax.random.PRNGKey(0), (256, 256), 0.1))
    b = np.asarray(hashed_keep_mask(jax.random.PRNGKey(1), (256, 256), 0.1))
    assert abs(a.mean() - 0.9) < 0.005 and abs(b.mean() - 0.9) < 0.005
    # Independent masks agree on about 0.9^2 + 0.1^2 = 82 % of the entries.
    assert abs((a == b).mean() - 0.82) < 0.01
    # No structure along rows or columns.
    assert np.abs(a.mean(axis=0) - 0.9).max() < 0.1 and np.abs(a.mean(axis=1) - 0.9).max() < 0.1


TINY = dict(approach="jt-nf", task="forward", total_steps=150, chunk_steps=50, warmup_steps=100, eval_steps=20)


@pytest.mark.parametrize("name", ["sac", "sac-utd20", "droq"])
def test_every_algorithm_trains_a_vmapped_smoke_run(name):
    """Two seeds through warm-up and learning, as a chunk scans them (Trainer.step); the chunk's evaluation is
    algorithm-free and compiled by the CrossQ tests, so here the deterministic action is checked alone."""
    config = TrainConfig(algo=name, **TINY)
    trainer = make_train(config)
    carry = jax.jit(jax.vmap(trainer.init))(seed_keys([0, 1]))
    steps = jnp.arange(config.total_steps)
    scan = jax.jit(jax.vmap(lambda carry: jax.lax.scan(trainer.step, carry, steps)))
    carry, history = scan(carry)
    utd = config.agent_config.updates_per_step
    learning_steps = config.total_steps - config.warmup_steps
    # Updates are counted by the agent itself, step by step.
    np.testing.assert_array_equal(carry.agent_state.updates, [learning_steps * utd] * 2)
    np.testing.assert_array_equal(history["updates"].sum(axis=1), [learning_steps * utd] * 2)
    learning = np.arange(config.total_steps) >= config.warmup_steps
    # Under thesis-code every learning step updates critic and actor (policy delay 1): no NaN by design.
    for metric in ("critic_loss", "actor_loss", "entropy", "alpha"):
        assert np.isfinite(np.asarray(history[metric])[:, learning]).all(), metric
    assert np.isfinite(np.nanmean(np.asarray(history["forward_velocity"])[:, learning], axis=1)).all()  # NaN: blow-up
    for name, values in history.items():
        assert not np.isinf(np.asarray(values)).any(), name
    # What the chunk's divergence check would have caught: any non-finite leaf of the agent.
    for leaf in jax.tree.leaves(carry.agent_state):
        if jnp.issubdtype(leaf.dtype, jnp.inexact):
            assert np.isfinite(np.asarray(leaf)).all()
    agent = make_agent(config.agent_config, trainer.env.observation_size, trainer.env.action_size)
    act = jax.jit(jax.vmap(lambda state, obs: agent.act(state, obs, None, deterministic=True)))
    action = np.asarray(act(carry.agent_state, carry.env_state.obs))
    assert action.shape == (2, trainer.env.action_size) and np.isfinite(action).all() and np.abs(action).max() <= 1
    assert config.env_config.control_hz == 50.0  # thesis-code: JT's rate whatever the algorithm
