"""The pure vmapped training loop: one trace, determinism, a smoke run, results files."""


import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.learning import train
from tests.conftest import TINY_TRAIN, run_all_chunks, seed_keys


def test_smoke_training_run(train_fns):
    carry, history = run_all_chunks(train_fns, [0, 1])
    assert int(carry.buffer.size[0]) == TINY_TRAIN.total_steps
    updates = sum(m["train/updates"] for m in history)
    # One update per step after warm-up, counted inside the compiled program.
    np.testing.assert_array_equal(updates, [TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps] * 2)
    assert int(carry.agent_state.updates[0]) == TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps
    last = history[-1]
    for name in ("train/critic_loss", "train/actor_loss", "train/alpha", "train/forward_velocity",
                 "eval/desired_velocity", "eval/forward/desired_velocity", "eval/desired_mae", "eval/return",
                 "reward/velocity", "reward/energy"):
        assert np.isfinite(last[name]).all(), name
    assert np.isnan(history[0]["train/critic_loss"]).all()  # the first chunk is all warm-up
    # Seeds differ from each other.
    assert not np.allclose(last["train/forward_velocity"][0], last["train/forward_velocity"][1])


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_whole_train_program_matches_chunked_runs(trainer, train_fns):
    """`train(key)` (all chunks in one scan) runs the same program as the host's chunk loop.

    The warm-up chunk is bit-identical; once learning starts the two differently compiled
    programs differ in float rounding, which the chaotic rollouts amplify, so later chunks
    are only checked for sanity.
    """
    _, chunked = run_all_chunks(train_fns, [3, 4])
    _, stacked = jax.jit(jax.vmap(trainer.train))(seed_keys([3, 4]))
    for name in chunked[0]:
        np.testing.assert_array_equal(stacked[name][0, 0], chunked[0][name][0], err_msg=name)
    assert stacked["train/updates"][0].sum() == TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps
    assert np.isfinite(stacked["train/critic_loss"][0, 1:]).all()


def test_a_diverging_seed_is_frozen_and_marked_while_the_others_go_on(train_fns):
    """A NaN put into seed 1's actor freezes seed 1 at its carry from before the chunk; seed 0 trains on."""
    init, chunk = train_fns
    carry = init(seed_keys([0, 1]))
    poison = lambda x: x.at[1].set(jnp.nan) if jnp.issubdtype(x.dtype, jnp.floating) else x
    carry = carry.replace(agent_state=carry.agent_state.replace(
        actor_params=jax.tree.map(poison, carry.agent_state.actor_params)))
    before = jax.device_get(carry)
    history = []
    for index in range(TINY_TRAIN.num_chunks):
        carry, metrics = chunk(carry, index * TINY_TRAIN.chunk_steps)
        history.append(jax.device_get(metrics))
    np.testing.assert_array_equal(carry.diverged_at, [-1, TINY_TRAIN.chunk_steps])
    after = jax.device_get(carry)
    jax.tree.map(lambda old, new: np.testing.assert_array_equal(old[1], new[1]),
                 before.replace(diverged_at=after.diverged_at), after)
    assert int(after.buffer.size[0]) == TINY_TRAIN.total_steps and int(after.buffer.size[1]) == 0
    for metrics in history:
        assert np.isnan(metrics["train/forward_velocity"][1]) and np.isfinite(metrics["train/forward_velocity"][0])
    assert np.isfinite(history[-1]["train/critic_loss"][0])


def test_the_carry_holds_a_replay_buffer_for_the_whole_run_and_the_onboard_estimate_only_where_sensed(trainer):
    carry = jax.eval_shape(trainer.init, jax.random.PRNGKey(0))  # shapes only: nothing compiles
    assert isinstance(trainer, train.Trainer) and isinstance(carry, train.Carry)
    assert carry.buffer.data.reward.shape == (TINY_TRAIN.num_chunks * TINY_TRAIN.chunk_steps,)
    assert carry.buffer.data.obs.shape == (300, trainer.env.observation_size)
    assert not any(name in trainer.env._metric_names() for name in train.ESTIMATED)


def test_several_environments_per_seed_share_one_replay_sized_for_all_of_them():
    config = dataclasses.replace(TINY_TRAIN, num_envs=4)
    carry = jax.eval_shape(train.make_train(config).init, jax.random.PRNGKey(0))  # shapes only: nothing compiles
    assert carry.buffer.data.reward.shape == (4 * TINY_TRAIN.num_chunks * TINY_TRAIN.chunk_steps,)
    assert carry.episode_return.shape == (4,) and carry.env_state.obs.shape[0] == 4
    with pytest.raises(ValueError, match="num_envs"):
        dataclasses.replace(TINY_TRAIN, num_envs=0).validate()


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_a_seed_with_several_environments_learns_and_counts_all_of_them():
    config = dataclasses.replace(TINY_TRAIN, num_envs=3)
    trainer = train.make_train(config)
    carry = jax.jit(trainer.init)(jax.random.PRNGKey(0))
    chunk = jax.jit(trainer.chunk)
    for start in range(0, config.total_steps, config.chunk_steps):
        carry, metrics = chunk(carry, start)
    assert int(carry.buffer.size) == 3 * config.total_steps  # every environment's steps stored
    assert int(metrics["train/updates"]) == config.chunk_steps  # one learner: its updates per step, not per env
    assert np.isfinite(float(metrics["train/forward_velocity"])) and np.isfinite(float(metrics["train/critic_loss"]))
