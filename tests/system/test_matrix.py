"""The configuration matrix: every approach on every task, vmapped; CPG observations; curriculum in the env."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.control import actions
from mjx_badger.experiments.registry import THESIS_APPROACHES
from mjx_badger.protocol import protocols
from mjx_badger.protocol.conditions import CONDITIONS
from mjx_badger.sim.env import EnvConfig, HB40Env

TASKS = ("forward", "forward-max", "omni-random", "omni-pdec")
# 1 s episodes (40 or 50 steps), so a short rollout crosses resets.
SMOKE = EnvConfig(protocol=protocols.THESIS_CODE.replace(episode_seconds=1.0))
SMOKE_TEXT = EnvConfig(protocol=protocols.THESIS_TEXT.replace(episode_seconds=1.0))
STEPS = 100
SEEDS = 2
# Each pair compiles an MJX program (~25 s on 2 cores): the default run covers every approach
# and every task once; the whole 6 x 4 matrix runs with `make test-slow`.
DIAGONAL = (("jt-nf", "forward"), ("jt-lpf", "omni-pdec"), ("jt-oef", "forward-max"), ("cpg-d", "omni-pdec"),
            ("cpg-vf", "omni-random"), ("cpg-rt", "forward"))
MATRIX = [pytest.param(a, t, marks=() if (a, t) in DIAGONAL else pytest.mark.slow)
          for a in THESIS_APPROACHES for t in TASKS]
_compiled = {}


def rollout(approach, task, states=None):
    """Random actions for STEPS steps, one env per seed, from `states` or from reset; compiled once per pair."""
    if (approach, task) not in _compiled:
        env = HB40Env(approach, task, SMOKE)

        def one(state, key):
            actions = jax.random.uniform(key, (STEPS, env.action_size), minval=-1, maxval=1)

            def body(state, action):
                state = env.step(state, action)
                return state, (state.obs, state.reward, state.done, state.info["command"], state.metrics)

            return jax.lax.scan(body, state, actions)

        _compiled[approach, task] = env, jax.jit(jax.vmap(one)), jax.jit(jax.vmap(env.reset))
    env, run, reset = _compiled[approach, task]
    keys = jax.random.split(jax.random.PRNGKey(0), SEEDS)
    states = reset(keys) if states is None else states
    return env, states, run(states, keys)


@pytest.mark.parametrize("approach, task", MATRIX)
def test_every_approach_and_task_runs_a_vmapped_smoke_episode(approach, task):
    env, _, (state, (obs, reward, done, _, metrics)) = rollout(approach, task)
    expected_obs = 56 if actions.is_cpg(approach) else 54
    assert env.observation_size == expected_obs and obs.shape == (SEEDS, STEPS, expected_obs)
    assert np.isfinite(np.asarray(obs)).all() and np.isfinite(np.asarray(reward)).all()
    if task != "forward-max":  # the released max_x reward is unclipped (docs/thesis-code.md §5)
        assert (np.asarray(reward) >= 0).all()
    assert np.asarray(done).sum(axis=1).min() >= 2  # every seed finished episodes and carried on
    for name, values in metrics.items():
        assert np.isfinite(np.asarray(values)).all(), name
    if task == "omni-pdec":
        assert "curriculum/learned_bins" in metrics


def test_cpg_observation_carries_feet_and_phase_under_the_text():
    env = HB40Env("cpg-vf", "forward", SMOKE_TEXT)
    state = jax.jit(env.reset)(jax.random.PRNGKey(0))
    names = [name for name, _, _ in env.observation_layout]
    assert names[2] == "predicted_feet_position" and names[-1] == "cpg_progress"
    np.testing.assert_allclose(state.obs[24:36], 0.0, atol=1e-6)  # nominal feet
    np.testing.assert_allclose(state.obs[54:56], [0.5, 1.0], atol=1e-6)  # phase 0 as (1 + sin, 1 + cos) / 2
    np.testing.assert_allclose(state.obs[48:51], [0.5, 0.0, 0.0])


def test_cpg_observation_carries_the_action_and_swing_heights_under_the_code(cpg_code_env):
    """The released CPG observes its scaled action (/3.14) and the two swing heights, [0, pi] at reset."""
    env, reset, step = cpg_code_env
    state = reset(jax.random.PRNGKey(0))
    np.testing.assert_allclose(state.obs[54:56], [0.0, np.pi], atol=1e-6)
    state = step(state, jnp.ones(env.action_size))
    np.testing.assert_allclose(state.obs[24:36], np.tile([0.15, 0.15, 0.1], 4) / 3.14, atol=1e-6)
    np.testing.assert_allclose(state.obs[54:56], [0.0, 0.0], atol=1e-6)  # heights read before the phase moves
    state = step(state, jnp.ones(env.action_size))
    # Phase 2 Hz / 40 Hz = 0.05 cycles: one pair lifts smoothstep(0.2) x 0.15 = 0.0156 m, the other stands.
    np.testing.assert_allclose(sorted(np.asarray(state.obs[54:56])), [0.0, 0.15 * (3 * 0.2**2 - 2 * 0.2**3)],
                               atol=1e-5)


def test_curricula_live_in_the_env_state_per_seed_and_survive_resets():
    """Seed 0 starts with two bins learned left and one right, seed 1 with none; 100 steps cross two resets each."""
    env, states, _ = rollout("cpg-d", "omni-pdec")
    task_state = states.info["task_state"]
    states = states.replace(info=dict(states.info, task_state=task_state._replace(
        learned=task_state.learned.at[0].set(jnp.array([2, 1])))))
    _, _, (final, (_, _, done, commands, metrics)) = rollout("cpg-d", "omni-pdec", states)
    np.testing.assert_array_equal(np.asarray(final.info["task_state"].learned), [[2, 1], [0, 0]])
    np.testing.assert_allclose(np.asarray(metrics["curriculum/learned_bins"])[:, -1], [3, 0])
    speeds = np.linalg.norm(np.asarray(commands)[..., :2], axis=-1)
    np.testing.assert_allclose(speeds[1], 0.25, atol=1e-6)  # the code's 0.25 m/s until complete
    assert speeds[0].max() <= 0.25 + 1e-6
    for seed in range(SEEDS):
        assert np.asarray(done)[seed].sum() >= 2
        assert len({tuple(c.round(5)) for c in np.asarray(commands)[seed]}) >= 2  # a fresh command every episode


@pytest.mark.parametrize("protocol", [protocols.THESIS_CODE, protocols.THESIS_TEXT], ids=lambda p: p.name)
@pytest.mark.parametrize("conditions", ["sim", "outdoor"])
def test_every_approach_steps_under_each_protocol_and_condition(protocol, conditions):
    """Traced, not compiled: each approach's step keeps its shapes (CPG-RT under the text drives 24 actuators).
    The outdoor conditions hold every field the office's do (estimate, stop, resets, the robot's controller) and
    the cobblestones besides."""
    for approach in THESIS_APPROACHES:
        env = HB40Env(approach, "forward", EnvConfig(protocol=protocol, conditions=CONDITIONS[conditions]))
        state = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
        stepped = jax.eval_shape(env.step, state, jnp.zeros(env.action_size))
        assert stepped.obs.shape == state.obs.shape == (env.observation_size,), approach
