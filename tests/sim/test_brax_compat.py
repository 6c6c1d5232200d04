"""brax's own trainers and wrappers on HB40Env, through brax_compat (compiles: a few minutes in all)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from brax.envs.wrappers.training import EvalWrapper
from brax.training.agents.ppo import train as ppo
from brax.training.agents.sac import train as sac

from mjx_badger.protocol import protocols
from mjx_badger.sim import brax_compat
from mjx_badger.sim.env import EnvConfig, HB40Env

# Episodes of 10 control steps (0.2 s at the thesis code's 50 Hz): several episode ends in a few steps.
SHORT = EnvConfig(protocol=protocols.THESIS_CODE.replace(episode_seconds=0.2))


@pytest.fixture(scope="module")
def short_env():
    return HB40Env("jt-nf", "forward", SHORT)


def test_the_wrapper_reports_the_envs_own_time_limit_and_keeps_its_reset():
    # Random commands: a second (brax) reset would bring back the first episode's command in the observation.
    env = HB40Env("jt-nf", "omni-random", SHORT)
    wrapped = EvalWrapper(brax_compat.wrap(env, episode_length=env.episode_steps))
    reset, step = jax.jit(wrapped.reset), jax.jit(wrapped.step)
    state = reset(jax.random.split(jax.random.PRNGKey(0), 3))
    start_commands = np.asarray(state.info["command"])
    action = jnp.zeros((3, env.action_size))
    truncations, steps = [], []
    for _ in range(2 * env.episode_steps + 1):
        state = step(state, action)
        truncations.append(np.asarray(state.info["truncation"]))
        steps.append(np.asarray(state.info["steps"]))
        command_in_obs = np.asarray(state.obs)[:, 48:51]
        np.testing.assert_allclose(command_in_obs, np.asarray(state.info["command"]), atol=1e-6)
    truncations, steps = np.array(truncations), np.array(steps)
    ends = np.arange(1, 2 * env.episode_steps + 2) % env.episode_steps == 0
    # Standing still never falls, so every episode ends by the time limit: brax must see a truncation there, only there.
    assert np.all(truncations[ends] == 1) and np.all(truncations[~ends] == 0)
    np.testing.assert_array_equal(steps[:, 0], [*range(1, 11), *range(1, 11), 1])
    assert not np.allclose(np.asarray(state.info["command"]), start_commands)  # new episodes drew new commands
    # The evaluator's metrics (with its `reward` key) survive the env's step.
    assert "reward" in state.metrics and np.all(np.asarray(state.info["eval_metrics"].episode_steps) == 10)


def test_the_wrapper_refuses_settings_the_env_does_not_honour(short_env):
    with pytest.raises(ValueError, match="episode_length=env.episode_steps"):
        brax_compat.wrap(short_env, episode_length=1000)
    with pytest.raises(ValueError, match="action_repeat=1"):
        brax_compat.wrap(short_env, episode_length=short_env.episode_steps, action_repeat=2)


def test_the_device_put_replicated_shim_stacks_one_copy_per_device():
    tree = {"w": jnp.arange(3.0), "n": jnp.uint32(7)}
    stacked = jax.device_put_replicated(tree, jax.local_devices())
    assert stacked["w"].shape == (jax.local_device_count(), 3) and stacked["n"].dtype == jnp.uint32
    np.testing.assert_array_equal(stacked["w"].addressable_shards[0].data.squeeze(0), tree["w"])


def _finite(tree):
    return all(bool(jnp.all(jnp.isfinite(leaf))) for leaf in jax.tree.leaves(tree))


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_brax_sac_trains_on_the_env(short_env):
    evaluations = []
    _, params, metrics = sac.train(
        environment=short_env, wrap_env_fn=brax_compat.wrap, episode_length=short_env.episode_steps,
        num_timesteps=200, num_envs=4, num_eval_envs=4, batch_size=32, min_replay_size=40, num_evals=2,
        progress_fn=lambda step, m: evaluations.append((step, m)))
    assert [step for step, _ in evaluations] == [0, 200]
    assert metrics["eval/avg_episode_length"] == short_env.episode_steps
    assert np.isfinite(metrics["eval/episode_reward"]) and _finite(params)


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_brax_ppo_trains_on_the_env(short_env):
    evaluations = []
    _, params, metrics = ppo.train(
        environment=short_env, wrap_env_fn=brax_compat.wrap, episode_length=short_env.episode_steps,
        num_timesteps=320, num_envs=4, num_eval_envs=4, unroll_length=10, batch_size=4, num_minibatches=4,
        num_updates_per_batch=1, num_evals=2, progress_fn=lambda step, m: evaluations.append((step, m)))
    assert evaluations[-1][0] >= 320
    assert metrics["eval/avg_episode_length"] == short_env.episode_steps
    assert np.isfinite(metrics["eval/episode_reward"]) and _finite(params)
