"""The SAC family: Table 4.3 configs, losses by hand, Polyak targets, dropout, update counts, smoke runs."""


import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
from tests.conftest import seed_keys


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


def test_protocols_configure_crossq_and_the_many_update_algorithms():
    code, text = TrainConfig(algo="crossq").agent_config, TrainConfig(algo="crossq", protocol="thesis-text").agent_config
    assert (code.policy_delay, code.renorm_warmup_steps, code.actor_batch_renorm, code.target_entropy) == (
        1, 1000, True, -6.0)
    assert (text.policy_delay, text.renorm_warmup_steps, text.actor_batch_renorm, text.target_entropy) == (
        3, 100_000, False, None)
    assert TrainConfig(algo="droq").agent_config.actor_updates_per_step == 1
    assert TrainConfig(algo="droq", protocol="thesis-text").agent_config.actor_updates_per_step is None


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


def test_crossq_config_is_thesis_table_4_3():
    cfg = ALGORITHMS["crossq"]()
    assert (cfg.learning_rate, cfg.batch_size, cfg.hidden, cfg.ensemble_size, cfg.gamma) == (
        0.005, 128, (256, 256), 2, 0.99)
    assert cfg.target_entropy_per_action == -0.5 and cfg.updates_per_step == 1 and cfg.control_hz == 40
    assert cfg.batch_renorm and not cfg.target_network  # CrossQ: no target network
