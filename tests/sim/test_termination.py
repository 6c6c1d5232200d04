"""When an episode ends: the protocols' fall rules, the robot's own stop, a blow-up that is no fall."""

import math

import jax
import jax.numpy as jnp
import numpy as np
from mujoco import mjx

from mjx_badger.protocol import conditions, protocols
from mjx_badger.sim import termination
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.tasks import locomotion as tasks


def test_the_robots_own_stop_ends_the_episode_as_a_fall(office):
    """Pitched 40 degrees: past the released robot env's 30 (thesis-code), so the first step stops it."""
    state = jax.jit(office.reset)(jax.random.PRNGKey(0))
    half = math.radians(40) / 2
    qpos = state.pipeline_state.qpos.at[3:7].set(jnp.array([math.cos(half), 0.0, math.sin(half), 0.0]))
    state = state.replace(pipeline_state=state.pipeline_state.replace(qpos=qpos))
    after = jax.device_get(jax.jit(office.step)(state, jnp.zeros(office.action_size)))
    assert after.info["terminated"] and after.info["falls"] == 1
    # A CPG robot stops too: on the robot the monitor, not the simulation code's never-terminating CPG, decides.
    cpg = HB40Env("cpg-d", "forward", EnvConfig(conditions=conditions.OFFICE))
    assert cpg.conditions.safety_stop and not cpg.protocol.cpg_terminates


CODE, TEXT = protocols.THESIS_CODE, protocols.THESIS_TEXT


def _tilted(env, angle, axis=0):
    """Initial data with the trunk turned by `angle` about x (axis 0) or y (axis 1)."""
    data = env._init_data
    quat = jnp.zeros(4).at[0].set(jnp.cos(angle / 2)).at[1 + axis].set(jnp.sin(angle / 2))
    return data.replace(qpos=data.qpos.at[3:7].set(quat))


def _rule(env, data, power_steps=0):
    rot = data.xmat[env._trunk]
    roll, pitch = jnp.arctan2(rot[2, 1], rot[2, 2]), jnp.arcsin(-rot[2, 0])
    motion = tasks.Motion(jnp.zeros(3), jnp.zeros(3), roll, pitch, jnp.zeros(12))
    return bool(env._fall_rule(data, motion, jnp.int32(power_steps)))


def _forward_data(env, data):

    return jax.jit(mjx.forward)(env.mjx_model, data)  # one compile; op by op it is hundreds of small ones


def test_termination_rules_of_the_code_and_the_text(env):
    """thesis-code: 30 deg, |omega| > 4 rad/s, trunk-floor contact, 3 steps over 1500 W; thesis-text: 0.8 rad, 0.15 m."""
    text = HB40Env("jt-nf", "forward", EnvConfig(protocol=TEXT))
    level = env._init_data
    assert not _rule(env, level) and not _rule(text, level)
    tilt_35 = _forward_data(env, _tilted(env, np.deg2rad(35)))
    assert _rule(env, tilt_35) and not _rule(text, tilt_35)  # 35 deg: beyond 30 deg, within 0.8 rad
    spinning = level.replace(qvel=level.qvel.at[5].set(4.5))
    assert _rule(env, spinning) and not _rule(text, spinning)
    assert not _rule(env, level, power_steps=2) and _rule(env, level, power_steps=termination.CODE_POWER_STEPS)
    # A step counts towards the power rule while |torque . joint velocity| passes 1500 W, and the count restarts below.
    info, hot = {"power_steps": jnp.int32(2)}, level.replace(qvel=level.qvel.at[6:].set(10.0))
    assert int(env._power_steps(info, hot, jnp.full(12, 12.6))) == 3  # 12 x 12.6 N m x 10 rad/s = 1512 W
    assert int(env._power_steps(info, hot, jnp.full(12, 12.4))) == 0  # 1488 W
    # The trunk box (half height 0.05 m) level with its bottom 1 mm into the floor, and 1 mm above it.
    on_floor = _forward_data(env, level.replace(qpos=level.qpos.at[2].set(0.049)))
    above = _forward_data(env, level.replace(qpos=level.qpos.at[2].set(0.051)))
    assert _rule(env, on_floor) and not _rule(env, above)


def test_cpg_under_the_code_never_terminates_but_counts_the_would_be_fall(cpg_code_env):
    env, reset, step = cpg_code_env
    state = reset(jax.random.PRNGKey(0))
    tipped = state.pipeline_state.replace(qpos=state.pipeline_state.qpos.at[3:7].set(
        jnp.array([np.cos(np.pi / 4), np.sin(np.pi / 4), 0.0, 0.0])))
    state = step(state.replace(pipeline_state=tipped), jnp.zeros(env.action_size))
    assert not bool(state.info["terminated"]) and float(state.done) == 0.0 and int(state.info["step"]) == 1
    assert int(state.info["falls"]) == 0 and int(state.info["would_falls"]) == 1
    # Lying there, the rule keeps firing; the would-be fall is counted once.
    state = step(state, jnp.zeros(env.action_size))
    assert int(state.info["would_falls"]) == 1


def test_a_physics_blowup_ends_the_episode_without_nans_and_is_not_a_fall(env, env_fns):
    reset, step = env_fns
    state = reset(jax.random.PRNGKey(0))
    broken = state.pipeline_state.replace(qvel=state.pipeline_state.qvel.at[0].set(jnp.nan))
    state = step(state.replace(pipeline_state=broken), jnp.zeros(12))
    assert bool(state.info["terminated"]) and int(state.info["blowups"]) == 1 and int(state.info["falls"]) == 0
    assert int(state.info["would_falls"]) == 0  # nor a would-be fall: the rule is read on finite states only
    assert np.isfinite(np.asarray(state.info["next_obs"])).all() and np.isfinite(float(state.reward))
    assert np.isfinite(np.asarray(state.obs)).all() and int(state.info["step"]) == 0  # a fresh episode


def test_a_stop_the_truth_shows_no_fall_at_is_counted_and_one_only_the_noise_made_is_premature(office):
    """The truth's tilt-height rule falls at 0.8 rad; the robot's own stop (on the truth) at 30 deg of pitch."""
    stop = jnp.bool_(True)
    kinds = lambda angle: tuple(bool(k) for k in office.stop_kinds(_forward_data(office, _tilted(office, angle, 1)),
                                                                     stop))
    assert kinds(0.0) == (True, True)  # level: a stop here came from the sensors' noise alone
    assert kinds(np.deg2rad(40)) == (True, False)  # the stop's own rule fires on the truth, but no fall yet
    assert kinds(np.deg2rad(60)) == (False, False)  # past the fall tilt: a stop at a fall
    assert not any(bool(k) for k in office.stop_kinds(_forward_data(office, office._init_data), jnp.bool_(False)))
