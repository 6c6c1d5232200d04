"""The Gymnasium environment: registered, passes Gymnasium's checker, steps as the MJX env does, vectorises."""

import warnings

import gymnasium
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import mjx_badger
from mjx_badger.protocol import protocols
from mjx_badger.sim import native
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.sim.gym_env import HB40GymEnv

# Native MuJoCo and MJX integrate the same contacts a little differently; after 20 control steps of
# random actions from the same state (measured: joint angles 3e-4 to 1.5e-2, joint velocities 8e-4 to
# 0.1, trunk velocity 2e-3 to 1.7e-2, angular velocity 5e-4 to 0.07, gravity 4e-4 to 3e-3; rewards
# up to 10 % of max(1, |reward|)) the blocks stay within these (observation units, after scaling):
PARITY_TOLERANCE = {"joint_angle": 0.03, "joint_velocity": 0.2, "predicted_joint_angle": 1e-5,
                    "predicted_feet_position": 1e-5, "trunk_linear_velocity": 0.04, "trunk_angular_velocity": 0.15,
                    "target_velocity": 1e-6, "projected_gravity": 0.01, "cpg_progress": 1e-5}
# The accelerations are left out: contact impulses make them spike by several m/s^2 between engines.
REWARD_TOLERANCE = 0.15  # relative to max(1, |reward|)
PARITY_STEPS = 20


@pytest.fixture(scope="module")
def gym_env():
    env = gymnasium.make(mjx_badger.GYM_ENV_ID, approach="cpg-vf", task="omni-pdec", protocol="thesis-text")
    yield env
    env.close()


def test_the_env_is_registered_on_import_and_passes_gymnasiums_checker(gym_env):
    assert gym_env.spec.id == "mjx_badger/HB40-v0" and isinstance(gym_env.unwrapped, HB40GymEnv)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(gym_env.unwrapped, skip_render_check=True)
    # The only complaint allowed: observations (accelerations among them) have no finite bound.
    assert all("infinity" in str(warning.message) for warning in caught), [str(w.message) for w in caught]
    assert gym_env.observation_space.shape == (56,) and gym_env.action_space.shape == (13,)  # CPG-VF, thesis-text: 8 + 1 + 4


def test_the_curriculum_carries_over_between_episodes_of_one_env(gym_env):
    gym_env.reset(seed=0)
    stage = gym_env.unwrapped._task_state
    for _ in range(3):
        gym_env.step(gym_env.action_space.sample())
    gym_env.reset()
    assert jax.tree.structure(gym_env.unwrapped._task_state) == jax.tree.structure(stage)
    _, info = gym_env.reset(options={"command": (0.3, 0.0, 0.0)})
    np.testing.assert_allclose(info["command"], [0.3, 0.0, 0.0])


def test_an_episode_ends_truncated_at_the_protocols_length():
    env = gymnasium.make(mjx_badger.GYM_ENV_ID, approach="cpg-d", task="forward", protocol="thesis-code")
    env.unwrapped.native.env.episode_steps = 5  # the CPG never terminates under thesis-code: only time ends it
    env.reset(seed=1)
    ends = [env.step(np.zeros(env.action_space.shape, np.float32))[2:4] for _ in range(5)]
    assert ends == [(False, False)] * 4 + [(False, True)]


@pytest.mark.parametrize("approach, protocol", [("jt-oef", "thesis-text"), ("cpg-d", "thesis-code")])
def test_native_and_mjx_envs_agree_under_the_same_actions_from_the_same_state(approach, protocol):
    env = HB40Env(approach, "forward", EnvConfig(protocol=protocols.get(protocol)))
    twin, step = native.NativeEnv(env), jax.jit(env.step)
    key = jax.random.PRNGKey(3)  # the same key: the same action delays (thesis-text) in both engines
    mjx_state, native_state = jax.jit(env.reset)(key), twin.reset(key)
    actions = np.random.default_rng(0).uniform(-1, 1, (PARITY_STEPS, env.action_size)).astype(np.float32)
    worst = {}
    for action in actions:
        mjx_state, native_state = step(mjx_state, jnp.asarray(action)), twin.step(action)
        assert not bool(mjx_state.done) and not bool(native_state.done)
        start = 0
        for name, size, _ in env.observation_layout:
            gap = np.abs(np.asarray(mjx_state.obs)[start:start + size] - np.asarray(native_state.obs)[start:start + size])
            worst[name] = max(worst.get(name, 0.0), float(gap.max()))
            start += size
        reward = float(mjx_state.reward)
        assert abs(reward - float(native_state.reward)) <= REWARD_TOLERANCE * max(1.0, abs(reward))
    for name, gap in worst.items():
        if name in PARITY_TOLERANCE:
            assert gap <= PARITY_TOLERANCE[name], (name, gap)


def test_a_synchronous_vector_of_envs_steps_several_seeds():
    envs = gymnasium.make_vec(mjx_badger.GYM_ENV_ID, num_envs=3, vectorization_mode="sync", approach="jt-nf",
                              task="omni-random", protocol="thesis-code")
    observations, _ = envs.reset(seed=0)
    assert observations.shape == (3, 54)
    assert len({tuple(np.round(o[48:51], 5)) for o in observations}) == 3  # each seed draws its own command
    observations, rewards, terminated, truncated, _ = envs.step(np.zeros((3, 12), np.float32))
    assert observations.shape == (3, 54) and rewards.shape == (3,) and np.all(np.isfinite(rewards))
    envs.close()
