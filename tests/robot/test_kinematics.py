"""Leg kinematics: forward and inverse agree with native MuJoCo and each other, and stand the feet."""

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics, mjcf, motors

MAX_TILT_RAD = 0.05


def test_forward_kinematics_matches_native_mujoco_and_inverts():
    model = mjcf.load_model()
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(robot.joint_limits()[0] * 0.6, robot.joint_limits()[1] * 0.6).reshape(-1)
        data.qpos[:] = robot.standing_qpos(model, pose=q)
        mujoco.mj_forward(model, data)
        native = np.array([data.geom(f"{leg}_foot").xpos - data.body(f"{leg}_hip").xpos for leg in robot.HB40.legs])
        np.testing.assert_allclose(np.asarray(kinematics.forward(q)), native, atol=1e-6)
        np.testing.assert_allclose(np.asarray(kinematics.inverse(native)).reshape(-1), q, atol=1e-5)


def test_thesis_code_ik_stands_the_feet_0_30_m_below_the_hips():
    """docs/thesis-code.md §2: the code's IK asks for 0.25 m but its angles on the model give ~0.30 m."""
    angles = kinematics.thesis_code_ik(np.asarray([[0.05, 0.02 * s, -0.25] for s in robot.HB40.left_sign]))
    feet = np.asarray(kinematics.forward(angles))
    np.testing.assert_allclose(-feet[:, 2], 0.303, atol=0.005)
    # Hips 0.08 rad outward on every leg, same signs as the nominal pose.
    np.testing.assert_allclose(np.sign(np.asarray(angles)), np.sign(robot.nominal_pose().reshape(4, 3)))


def test_first_version_robot_stands_its_feet_in_one_plane_0_33_m_below_the_hips():
    """hb40-v1 (the attribution's 'robot geometry' swap): no lateral offsets, thigh 0.6 rad behind vertical."""
    spec = robot.HB40_FIRST_VERSION
    model = mjcf.load_model(spec)
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model, spec)
    mujoco.mj_forward(model, data)
    for i, leg in enumerate(robot.HB40.legs):
        foot = data.geom(f"{leg}_foot").xpos - data.body(f"{leg}_hip").xpos
        np.testing.assert_allclose(-foot[2], 0.33 * np.cos(0.1) - 0.0125 * np.sin(0.1), atol=1e-3)
        np.testing.assert_allclose(robot.HB40.left_sign[i] * foot[1], 0.0125 * np.cos(0.1) + 0.33 * np.sin(0.1), atol=1e-3)
        assert abs(foot[0] - robot.HB40.front_sign[i] * 0.0555) < 1e-6  # thigh back, calf forward: under the thigh joint
    # Its knees fold from straight: left knees negative, right positive.
    np.testing.assert_allclose(model.jnt_range[1 + 2], [-2.53, 0.0])
    np.testing.assert_allclose(model.jnt_range[1 + 5], [0.0, 2.53])
    np.testing.assert_allclose(model.body("trunk").inertia, [0.01884, 0.03746, 0.04726], atol=1e-6)
    data.ctrl[:] = robot.nominal_pose(spec)
    motors.set_pd_gains(model, 25.0, 1.0)
    for _ in range(400):
        mujoco.mj_step(model, data)
    assert np.abs(data.qpos[4:6]).max() * 2 < MAX_TILT_RAD and data.qpos[2] > 0.3


def test_inverse_of_forward_over_the_reachable_workspace():
    """FK(IK(p)) = p for feet below the hip, sampled from joint angles inside the ranges (knee bent backward)."""
    rng = np.random.default_rng(1)
    # Hips +-0.5 rad; thighs 10-80 degrees behind vertical (a = -1.4 ... -0.17 from the horizontal zero);
    # knees 0.3-2.4 rad open; a joint angle is the physical angle times the leg's side sign.
    hip = rng.uniform(-0.5, 0.5, (2000, 4))
    a = rng.uniform(-1.4, -0.17, (2000, 4))
    b = rng.uniform(0.3, 2.4, (2000, 4))
    angles = np.stack([hip, robot.HB40.left_sign * a, robot.HB40.left_sign * b], axis=-1)
    feet = jax.vmap(kinematics.forward)(angles)
    below = np.asarray(jnp.all(feet[..., 2] < -0.05, axis=-1))
    feet = feet[below]
    assert len(feet) > 500
    solved = jax.vmap(kinematics.inverse)(feet)
    np.testing.assert_allclose(jax.vmap(kinematics.forward)(solved), feet, atol=1e-5)


def test_nominal_pose_round_trip():
    np.testing.assert_allclose(np.asarray(kinematics.inverse(kinematics.nominal_feet())).ravel(), robot.nominal_pose(),
                               atol=1e-6)


def test_inverse_kinematics_never_returns_nan_and_respects_limits():
    points = jnp.array([[[0.0, 0.0, 0.0]] * 4, [[1.0, 2.0, -3.0]] * 4, [[0.0, 0.0125, 0.0]] * 4,
                        [[0.0, 0.0, -0.5]] * 4, [[0.2, -0.3, 0.4]] * 4])
    angles = np.asarray(jax.vmap(kinematics.inverse)(points))
    assert np.isfinite(angles).all()
    assert (angles >= robot.joint_limits()[0] - 1e-6).all() and (angles <= robot.joint_limits()[1] + 1e-6).all()
    # Out of reach straight down: the leg stretches, its knee at the most open angle it reaches.
    stretched = np.asarray(kinematics.forward(angles[3]))
    assert (np.linalg.norm(stretched[:, [0, 2]], axis=-1) > 0.39).all()
