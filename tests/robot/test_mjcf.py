"""The MuJoCo model of the HB40: it settles at the thesis code's heights, stands, and MJX agrees with native."""

import contextlib
import dataclasses
import io

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger.control import actions
from mjx_badger.protocol import protocols
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf, motors

with contextlib.redirect_stdout(io.StringIO()):  # mjx notes its missing GPU backend on stdout
    from mujoco import mjx


STAND_SECONDS = 10.0


MAX_TILT_RAD = 0.05


MAX_FOOT_SLIDE_M = 0.01


def _standing_data(model, kp=60.0, kd=3.0):
    motors.set_pd_gains(model, kp, kd)
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    data.ctrl[:] = robot.nominal_pose()
    mujoco.mj_forward(model, data)
    return data


def _feet_xy(model, data):
    return np.array([data.geom(name).xpos[:2] for name in robot.HB40.foot_geoms])


def test_settles_at_the_thesis_code_heights():
    """docs/thesis-code.md §1: dropped from 0.316 m the model settles at 0.262 m (Kp 60 / Kd 3), 0.244 m (Kp 25 / Kd 1)."""
    for (kp, kd), expected in (((60.0, 3.0), 0.262), ((25.0, 1.0), 0.244)):
        model = mjcf.load_model()
        data = _standing_data(model, kp, kd)
        for _ in range(400):
            mujoco.mj_step(model, data)
        assert abs(data.qpos[2] - expected) < 0.005, f"Kp {kp}: settled at {data.qpos[2]:.3f} m"


def test_native_mujoco_stands_still_for_10_s():
    model = mjcf.load_model()
    data = _standing_data(model)
    for _ in range(200):  # let it land and settle (1 s) before measuring sliding
        mujoco.mj_step(model, data)
    feet0 = _feet_xy(model, data)
    max_tilt = 0.0
    for _ in range(int(STAND_SECONDS / robot.HB40.physics_dt)):
        mujoco.mj_step(model, data)
        max_tilt = max(max_tilt, np.abs(data.qpos[4:6]).max() * 2)  # small-angle roll/pitch from the quaternion
    slide = np.abs(_feet_xy(model, data) - feet0).max()
    assert max_tilt < MAX_TILT_RAD, f"trunk tilted {max_tilt:.3f} rad"
    assert slide < MAX_FOOT_SLIDE_M, f"a foot slid {slide * 1000:.1f} mm"


def _rollout(env, reset, step, steps):
    """`steps` steps at zero action from reset: (final state, trunk heights, largest tilt, trunk x per step)."""
    state = reset(jax.random.PRNGKey(0))
    heights, tilts, xs = [], [], []
    for _ in range(steps):
        state = step(state, jnp.zeros(env.action_size))
        heights.append(float(state.metrics["height"]))
        tilts.append(float(jnp.abs(state.obs[51:53]).max()))  # projected gravity x, y = sin(tilt)
        xs.append(float(state.pipeline_state.qpos[0]))
    return state, np.array(heights), np.array(tilts), np.array(xs)


def test_mjx_zero_action_stands_for_10_s(env, env_fns):
    """JT at zero action under the thesis-code protocol (Kp 25 / Kd 1, 50 Hz): no fall, level, in place.

    The soft gains let the trunk pitch a few degrees on landing from the 4.4 cm drop, hence 0.1 rad; the
    landing also slides it back about 5.5 cm in the first half second, after which it stays put.
    """
    assert env.episode_steps == int(STAND_SECONDS * env.control_hz)
    # The episode's last step would end it and reset the robot, hiding any drift: all steps but that one.
    state, heights, tilts, xs = _rollout(env, *env_fns, env.episode_steps - 1)
    assert int(state.info["would_falls"]) == 0
    assert heights[-100:].min() > 0.22, f"trunk sank to {heights.min():.3f} m"
    assert tilts.max() < 0.1
    assert abs(xs[-1]) < 0.1, "the landing slid the trunk too far"
    landed = xs[int(env.control_hz):]  # from 1 s on
    assert landed.max() - landed.min() < 0.01, "trunk drifted in x after landing"


def test_mjx_cpg_at_zero_action_trots_in_place_for_10_s(cpg_code_env):
    """CPG-D at zero action (thesis-code): the trot keeps the trunk near 0.30 m, upright, never a would-be fall,
    over the protocol's whole 10-s episode but its last step (which would end it and reset the robot)."""
    env = cpg_code_env[0]
    assert env.episode_steps == int(STAND_SECONDS * env.control_hz)
    state, heights, tilts, _ = _rollout(*cpg_code_env, env.episode_steps - 1)
    assert int(state.info["would_falls"]) == 0
    assert 0.25 < heights[-200:].mean() < 0.33, f"trunk at {heights[-200:].mean():.3f} m"
    assert tilts.max() < 0.3
    assert abs(float(state.pipeline_state.qpos[0])) < 1.0, "trunk walked off"


def test_mjx_matches_native_mujoco_over_one_second():
    """Same state, same control sequence: MJX (float32) tracks the C engine over 200 physics steps."""
    model = mjcf.load_model()
    data = _standing_data(model)
    steps = int(1.0 / robot.HB40.physics_dt)
    t = np.arange(steps) * robot.HB40.physics_dt
    # Gentle 2 Hz joint-target wave so the feet load and unload after the drop.
    controls = robot.nominal_pose() + 0.15 * np.sin(2 * np.pi * 2.0 * t)[:, None] * np.tile([0.5, 1, 1], 4)

    native = []
    for u in controls:
        data.ctrl[:] = u
        mujoco.mj_step(model, data)
        native.append(data.qpos.copy())
    native = np.array(native)

    mx = mjx.put_model(model)
    dx = mjx.put_data(model, _standing_data(mjcf.load_model()))

    def body(dx, u):
        dx = mjx.step(mx, dx.replace(ctrl=u))
        return dx, dx.qpos

    _, ours = jax.jit(lambda dx, us: jax.lax.scan(body, dx, us))(dx, jnp.asarray(controls, jnp.float32))
    ours = np.asarray(ours)
    joint_error = np.abs(ours[:, 7:] - native[:, 7:]).max()
    trunk_error = np.abs(ours[:, :3] - native[:, :3]).max()
    assert joint_error < 0.02, f"joint angles differ by up to {joint_error:.4f} rad"
    assert trunk_error < 0.01, f"trunk position differs by up to {trunk_error:.4f} m"


def test_floor_contacts_choose_the_collision_pairs_and_keep_the_legs():
    """13 floor pairs (trunk, and per leg thigh motor, calf, foot); feet only is the first version's 4."""
    feet_only = dataclasses.replace(robot.HB40, floor_contacts=("foot",))
    assert mjcf.load_model().npair == 13 and mjcf.load_model(feet_only).npair == 4
    actions.check_robot("cpg-d", feet_only, protocols.THESIS_CODE)  # the released CPG's IK still fits these legs
