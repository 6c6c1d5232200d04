"""Environment: layout, vmap equivalence, no NaN, delay, falls and auto-reset."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.protocol import protocols
from mjx_badger.sim.env import EnvConfig, HB40Env

ROLLOUT_STEPS = 200
BATCH = 4


def test_observation_layout_is_table_4_1(env, env_fns):
    assert sum(size for _, size, _ in env.observation_layout) == 54 == env.observation_size
    assert env.action_size == 12
    state = env_fns[0](jax.random.PRNGKey(0))
    assert state.obs.shape == (54,)
    np.testing.assert_allclose(state.obs[48:51], [0.5, 0.0, 0.0])  # target velocities
    np.testing.assert_allclose(state.obs[51:54], [0.0, 0.0, -1.0], atol=1e-6)  # gravity, level trunk


def test_episode_and_rates_follow_the_protocol(env):
    # thesis-code: JT at 50 Hz (4 physics steps), CPG at 40 Hz (5), 10 s episodes (docs/thesis-code.md §2, §6).
    assert env.substeps == 4 and env.episode_steps == 500
    assert env.mj_model.actuator_gainprm[0, 0] == 25.0 and env.mj_model.actuator_biasprm[0, 2] == -1.0
    cpg = HB40Env("cpg-d", "forward")
    assert cpg.substeps == 5 and cpg.episode_steps == 400 and cpg.mj_model.actuator_biasprm[0, 2] == -3.0
    # thesis-text: the algorithm's rate (CrossQ 40 Hz, the others 20 Hz), 20 s episodes, Kp 60 / Kd 3.
    text = HB40Env("jt-nf", "forward", EnvConfig(protocol=protocols.THESIS_TEXT))
    assert text.substeps == 5 and text.episode_steps == 800 and text.mj_model.actuator_gainprm[0, 0] == 60.0
    slow = HB40Env("jt-nf", "forward", EnvConfig(control_hz=20.0, protocol=protocols.THESIS_TEXT))
    assert slow.substeps == 10 and slow.episode_steps == 400


def _random_rollout(env, key, steps):
    """Random actions from reset; returns per-step (obs, reward, falls)."""
    reset_key, action_key = jax.random.split(key)
    actions = jax.random.uniform(action_key, (steps, env.action_size), minval=-1, maxval=1)

    def body(state, action):
        state = env.step(state, action)
        return state, (state.obs, state.reward, state.info["falls"], state.info["next_obs"])

    return jax.lax.scan(body, env.reset(reset_key), actions)


def test_vmapped_random_rollout_has_no_nan_and_equals_single_env(env, env_fns):
    keys = jax.random.split(jax.random.PRNGKey(3), BATCH)
    _, (obs, reward, falls, _) = jax.jit(jax.vmap(lambda k: _random_rollout(env, k, ROLLOUT_STEPS)))(keys)
    assert np.isfinite(np.asarray(obs)).all() and np.isfinite(np.asarray(reward)).all()
    assert (np.asarray(reward) >= 0).all()

    # The same seed stepped one env at a time with the shared jitted step.
    reset, step = env_fns
    reset_key, action_key = jax.random.split(keys[0])
    actions = jax.random.uniform(action_key, (ROLLOUT_STEPS, env.action_size), minval=-1, maxval=1)
    state = reset(reset_key)
    # The stiff contacts of the thesis-code model (landing from the reset drop) grow float32
    # summation-order differences within 10 steps, most in velocities and in the raw free-joint
    # accelerations the code observes (on an AMD EPYC: 4e-4 in joint angles, 5e-3 in velocities,
    # 0.5 in accelerations at step 9); a wrong key or carry would differ at order one.
    blocks = {"joint angles and actions": (np.r_[0:12, 24:36], 2e-3), "joint velocities": (np.r_[12:24], 2e-2),
              "accelerations": (np.r_[36:42], 2.0), "trunk velocities": (np.r_[42:48], 2e-2),
              "command and gravity": (np.r_[48:54], 2e-3)}
    for t in range(10):
        state = step(state, actions[t])
        for name, (where, tolerance) in blocks.items():
            np.testing.assert_allclose(state.obs[where], obs[0, t][where], rtol=5e-2, atol=tolerance,
                                       err_msg=f"vmapped and single env: {name} differ at step {t}")


def test_fall_terminates_counts_and_resets(env, env_fns):
    reset, step = env_fns
    state = reset(jax.random.PRNGKey(0))
    # Tip the trunk over by 90 degrees about x: roll beyond the 30 degree threshold.
    qpos = state.pipeline_state.qpos.at[3:7].set(jnp.array([np.cos(np.pi / 4), np.sin(np.pi / 4), 0.0, 0.0]))
    state = state.replace(pipeline_state=state.pipeline_state.replace(qpos=qpos))
    state = step(state, jnp.zeros(env.action_size))
    assert bool(state.info["terminated"]) and float(state.done) == 1.0
    assert int(state.info["falls"]) == 1
    # The returned state is already a fresh episode; next_obs keeps the fallen robot's observation.
    assert int(state.info["step"]) == 0
    np.testing.assert_allclose(state.obs[51:54], [0.0, 0.0, -1.0], atol=1e-6)
    assert abs(float(state.info["next_obs"][52])) > 0.5


def test_time_limit_truncates_without_a_fall(env, env_fns):
    reset, step = env_fns
    state = reset(jax.random.PRNGKey(0))
    state = state.replace(info=dict(state.info, step=jnp.int32(env.episode_steps - 1)))
    state = step(state, jnp.zeros(env.action_size))
    assert bool(state.info["truncated"]) and not bool(state.info["terminated"])
    assert int(state.info["falls"]) == 0 and int(state.info["step"]) == 0


def test_action_delay_is_quantised_and_capped_under_the_text_and_absent_under_the_code():
    delayed = HB40Env("jt-nf", "forward", EnvConfig(protocol=protocols.THESIS_TEXT))
    steps = jax.vmap(delayed._delay_steps)(jax.random.split(jax.random.PRNGKey(0), 2000))
    steps = np.asarray(steps)
    assert steps.min() >= 0 and steps.max() == delayed.substeps  # capped at one control period
    # |0.03 + N(0, 0.05^2)| / 0.005 s: median about 8 physics steps before the cap, so most are capped
    assert 0.4 < (steps == 5).mean() < 0.8
    assert HB40Env("jt-nf", "forward")._delay_steps(None) == 0


def test_joint_velocity_is_clipped_to_25_rad_s_under_the_code(env, env_fns):
    reset, step = env_fns
    state = reset(jax.random.PRNGKey(0))
    flung = state.pipeline_state.replace(qvel=state.pipeline_state.qvel.at[6:].set(80.0))
    state = step(state.replace(pipeline_state=flung), jnp.zeros(12))
    assert float(jnp.abs(state.info["next_obs"][12:24]).max()) <= 25.0 / 25 + 1e-5  # observed as qdot / 25
