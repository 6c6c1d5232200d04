"""The HB40 model stands still, and MJX agrees with native MuJoCo."""

import contextlib
import io

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger import robot

with contextlib.redirect_stdout(io.StringIO()):
    from mujoco import mjx

STAND_SECONDS = 10.0
MAX_TILT_RAD = 0.05
MAX_FOOT_SLIDE_M = 0.01
MIN_HEIGHT_M = 0.30


def _standing_data(model):
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    data.ctrl[:] = robot.NOMINAL_POSE
    mujoco.mj_forward(model, data)
    return data


def _feet_xy(model, data):
    return np.array([data.geom(name).xpos[:2] for name in robot.FOOT_GEOMS])


def test_model_figures_match_design():
    model = robot.load_model()
    assert model.opt.timestep == robot.PHYSICS_DT == 0.005
    # 5.423 trunk + 4 x (0.645 + 0.827 + 0.118) = 11.783 kg
    np.testing.assert_allclose(model.body("trunk").subtreemass[0], 11.783, atol=1e-3)
    # Uniform 0.27 x 0.178 x 0.10 box of 5.423 kg: I = m/12 (b^2 + c^2) = 0.0188, 0.0375, 0.0473
    np.testing.assert_allclose(model.body("trunk").inertia, [0.01884, 0.03746, 0.04726], atol=2e-4)
    assert model.npair == 4 and model.nu == 12
    assert all(model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0 for g in range(model.ngeom))


def test_native_mujoco_stands_still_for_10_s():
    model = robot.load_model()
    data = _standing_data(model)
    for _ in range(40):  # let the PD settle on its stance (0.2 s) before measuring sliding
        mujoco.mj_step(model, data)
    feet0 = _feet_xy(model, data)
    min_height, max_tilt = np.inf, 0.0
    for _ in range(int(STAND_SECONDS / robot.PHYSICS_DT)):
        mujoco.mj_step(model, data)
        min_height = min(min_height, data.qpos[2])
        max_tilt = max(max_tilt, np.abs(data.qpos[4:6]).max() * 2)  # small-angle roll/pitch from the quaternion
    slide = np.abs(_feet_xy(model, data) - feet0).max()
    assert min_height > MIN_HEIGHT_M, f"trunk sank to {min_height:.3f} m"
    assert max_tilt < MAX_TILT_RAD, f"trunk tilted {max_tilt:.3f} rad"
    assert slide < MAX_FOOT_SLIDE_M, f"a foot slid {slide * 1000:.1f} mm"


def test_mjx_stands_still_for_10_s(env, env_fns):
    reset, step = env_fns
    state = reset(jax.random.PRNGKey(0))
    heights, tilts = [], []
    for _ in range(int(STAND_SECONDS * env.config.control_hz)):
        state = step(state, jnp.zeros(env.action_size))
        heights.append(float(state.metrics["height"]))
        tilts.append(float(jnp.abs(state.obs[51:53]).max()))  # projected gravity x, y = sin(tilt)
    assert int(state.info["falls"]) == 0
    assert min(heights) > MIN_HEIGHT_M, f"trunk sank to {min(heights):.3f} m"
    assert max(tilts) < MAX_TILT_RAD
    assert abs(float(state.pipeline_state.qpos[0])) < 0.05, "trunk drifted in x"


def test_mjx_matches_native_mujoco_over_one_second():
    """Same state, same control sequence: MJX (float32) tracks the C engine over 200 physics steps."""
    model = robot.load_model()
    data = _standing_data(model)
    steps = int(1.0 / robot.PHYSICS_DT)
    t = np.arange(steps) * robot.PHYSICS_DT
    # Gentle 2 Hz joint-target wave so the feet load and unload.
    controls = robot.NOMINAL_POSE + 0.15 * np.sin(2 * np.pi * 2.0 * t)[:, None] * np.tile([0.5, 1, 1], 4)

    native = []
    for u in controls:
        data.ctrl[:] = u
        mujoco.mj_step(model, data)
        native.append(data.qpos.copy())
    native = np.array(native)

    mx = mjx.put_model(model)
    dx = mjx.put_data(model, _standing_data(model))

    def body(dx, u):
        dx = mjx.step(mx, dx.replace(ctrl=u))
        return dx, dx.qpos

    _, ours = jax.jit(lambda dx, us: jax.lax.scan(body, dx, us))(dx, jnp.asarray(controls, jnp.float32))
    ours = np.asarray(ours)
    joint_error = np.abs(ours[:, 7:] - native[:, 7:]).max()
    trunk_error = np.abs(ours[:, :3] - native[:, :3]).max()
    assert joint_error < 0.02, f"joint angles differ by up to {joint_error:.4f} rad"
    assert trunk_error < 0.01, f"trunk position differs by up to {trunk_error:.4f} m"
