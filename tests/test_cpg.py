"""Leg kinematics, the trot CPG and the CPG action spaces."""

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest

from mjx_badger import actions, cpg, kinematics, mjcf, motors, protocols, robot

TEXT = protocols.THESIS_TEXT
CODE = protocols.THESIS_CODE


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


def test_swing_spline_hits_apex_at_mid_swing_and_is_continuous():
    t = jnp.linspace(0.0, 1.0, 2001)
    height = np.asarray(cpg.swing_height(t))
    assert height[0] == pytest.approx(0.0) and height[-1] == pytest.approx(0.0, abs=1e-9)
    assert height.argmax() == 1000 and height.max() == pytest.approx(cpg.APEX_HEIGHT)
    # Continuous: no jump bigger than the steepest slope allows (smoothstep(2t): 1.5 x 2 = 3 h per unit t).
    assert np.abs(np.diff(height)).max() <= 3 * cpg.APEX_HEIGHT / 2000 * 1.01
    # Lift quarter: h * smoothstep(2t) at t = 0.125 -> h * (-2 * 0.25^3 + 3 * 0.25^2) = h * 0.15625
    assert float(cpg.swing_height(0.125)) == pytest.approx(cpg.APEX_HEIGHT * 0.15625)


def test_trot_diagonals_in_phase_laterals_in_anti_phase():
    phases = jnp.linspace(0.0, 1.0, 400, endpoint=False)
    heights = np.asarray(jax.vmap(cpg.foot_heights)(phases))  # (400, 4) FL, FR, RL, RR
    np.testing.assert_allclose(heights[:, 0], heights[:, 3])  # FL with RR
    np.testing.assert_allclose(heights[:, 1], heights[:, 2])  # FR with RL
    swinging = heights > 0
    # Left and right front legs never swing together, and half a cycle shifts one onto the other.
    assert not np.any(swinging[:, 0] & swinging[:, 1])
    np.testing.assert_allclose(np.roll(heights[:, 0], 200), heights[:, 1], atol=1e-6)
    # Each foot's height is continuous around the whole cycle, wrap included.
    cyclic = np.concatenate([heights, heights[:1]])
    assert np.abs(np.diff(cyclic, axis=0)).max() < 0.01


def test_cpg_progress_is_in_unit_range_and_continuous_at_wrap():
    progress = np.asarray(jax.vmap(cpg.progress)(jnp.array([0.0, 0.25, 0.999999])))
    assert progress.min() >= 0.0 and progress.max() <= 1.0
    np.testing.assert_allclose(progress[0], progress[2], atol=1e-4)
    np.testing.assert_allclose(progress[1], [1.0, 0.5], atol=1e-6)


@pytest.mark.parametrize("approach, size", [("cpg-d", 12), ("cpg-vf", 13), ("cpg-rt", 24), ("cpg-rt-avg", 24),
                                            ("cpg-rt-sum", 24)])
def test_cpg_action_spaces_have_table_4_2_sizes(approach, size):
    for protocol in (TEXT, CODE):
        space = actions.make_action_space(approach, 0.025, protocol)
        assert space.size == size
        state, ctrl = space.step(space.init(), jnp.zeros(size))
        assert ctrl.shape == (space.ctrl_size,) and np.isfinite(np.asarray(ctrl)).all()
        predicted, extra = space.observe(state)
        assert predicted.shape == (12,) and extra.shape == (2,)
    space = actions.make_action_space(approach, 0.025, TEXT)
    state, ctrl = space.step(space.init(), jnp.zeros(size))
    assert ctrl.shape == (space.ctrl_size,) and np.isfinite(np.asarray(ctrl)).all()
    predicted, extra = space.observe(state)
    assert predicted.shape == (12,) and extra.shape == (2,)


def test_cpg_d_with_zero_action_follows_the_trot_from_the_nominal_feet():
    space = actions.make_action_space("cpg-d", 0.025, TEXT)
    state = space.init()
    for _ in range(5):  # 5 x 0.025 s at 2 Hz: phase 0.25, FL and RR at apex, FR and RL in stance
        state, ctrl = space.step(state, jnp.zeros(12))
    assert float(state.cpg.phase) == pytest.approx(0.25)
    feet = np.asarray(kinematics.forward(ctrl))
    np.testing.assert_allclose(feet[:, 2] - kinematics.nominal_feet()[:, 2], [0.15, 0.0, 0.0, 0.15], atol=1e-5)
    np.testing.assert_allclose(feet[:, :2], kinematics.nominal_feet()[:, :2], atol=1e-5)


def test_cpg_vf_frequency_spans_1_to_4_hz():
    space = actions.make_action_space("cpg-vf", 0.025, TEXT)
    slow, _ = space.step(space.init(), jnp.zeros(13).at[12].set(-1.0))
    fast, _ = space.step(space.init(), jnp.zeros(13).at[12].set(1.0))
    assert float(slow.cpg.phase) == pytest.approx(1.0 * 0.025)
    assert float(fast.cpg.phase) == pytest.approx(4.0 * 0.025)


def test_foot_offsets_are_bounded_by_table_4_2():
    space = actions.make_action_space("cpg-d", 0.025, TEXT)
    state, _ = space.step(space.init(), jnp.full(12, 5.0))  # clipped to +1
    offsets = np.asarray(state.feet - kinematics.nominal_feet())
    np.testing.assert_allclose(offsets[:, 0], 0.15, atol=1e-6)
    np.testing.assert_allclose(offsets[:, 1], 0.15, atol=1e-6)
    assert offsets[:, 2].max() <= 0.1 + cpg.APEX_HEIGHT + 1e-6


def test_residual_combinations():
    """Torque averaging: 24 targets for two half-strength PDs; angle average; angle sum."""
    action = jnp.zeros(24).at[12:].set(1.0)
    residual = robot.nominal_pose() + actions.RESIDUAL_SCALE
    torque = actions.make_action_space("cpg-rt", 0.025, TEXT)
    _, ctrl = torque.step(torque.init(), action)
    np.testing.assert_allclose(ctrl[12:], residual, atol=1e-6)
    cpg_angles = ctrl[:12]
    _, averaged = actions.make_action_space("cpg-rt-avg", 0.025, TEXT).step(torque.init(), action)
    np.testing.assert_allclose(averaged, 0.5 * (cpg_angles + residual), atol=1e-6)
    _, summed = actions.make_action_space("cpg-rt-sum", 0.025, TEXT).step(torque.init(), action)
    expected = np.clip(cpg_angles + actions.RESIDUAL_SCALE, robot.joint_limits()[0].ravel(),
                       robot.joint_limits()[1].ravel())
    np.testing.assert_allclose(summed, expected, atol=1e-6)


def test_split_pd_model_averages_two_clipped_pd_torques():
    """Two actuators per joint at half gains and half limit: the joint torque is the mean of two PD torques."""
    model = mjcf.load_model(split_pd=True)
    assert model.nu == 24
    data = mujoco.MjData(model)
    motors.set_pd_gains(model, 60.0, 3.0, split_pd=True)
    data.qpos[:] = robot.standing_qpos(model)
    first = robot.nominal_pose() + 0.05
    second = robot.nominal_pose() - 1.0  # saturates: -60 rad^-1 x 1 rad is beyond 16 N m
    data.ctrl[:] = np.concatenate([first, second])
    mujoco.mj_forward(model, data)
    q = data.qpos[7:]
    limit = robot.HB40.torque_limit
    pd = lambda target: np.clip(60.0 * (target - q), -limit, limit)
    np.testing.assert_allclose(data.qfrc_actuator[6:], 0.5 * (pd(first) + pd(second)), atol=1e-9)
    with pytest.raises(ValueError, match="24 actuators for 12 joints, not 1 per joint"):
        motors.set_pd_gains(model, 60.0, 3.0)  # the split is said, not guessed from the shapes


def test_thesis_code_cpg_adds_the_action_to_joint_angles_after_ik():
    """CPG under thesis-code: ctrl = IK(stance + swing) + action x [0.15, 0.15, 0.10] rad, not offsets before IK."""
    space = actions.make_action_space("cpg-d", 0.025, CODE)
    action = jnp.linspace(-1.0, 1.0, 12)
    state, ctrl = space.step(space.init(), action)
    # First step: heights read before the phase advances, so both pairs stand.
    stance = np.asarray(kinematics.thesis_code_ik(actions.THESIS_CODE_STANCE)).reshape(-1)
    np.testing.assert_allclose(ctrl, stance + np.asarray(action) * actions.JOINT_OFFSET_SCALE, atol=1e-6)
    # The same action through the text's pipeline moves the feet, not the joints, by its offsets.
    text = actions.make_action_space("cpg-d", 0.025, TEXT)
    _, text_ctrl = text.step(text.init(), action)
    assert np.abs(np.asarray(text_ctrl) - ctrl).max() > 0.1


def test_the_code_reads_swing_heights_before_advancing_the_phase():
    """cpg_heights_before_advance: the code's first step stands (heights of phase 0), the text's already lifts a pair."""
    for before, lifts in ((True, False), (False, True)):
        space = actions.make_action_space("cpg-d", 0.025, CODE.replace(cpg_heights_before_advance=before))
        state, ctrl = space.step(space.init(), jnp.zeros(12))
        assert (np.abs(np.asarray(state.heights)).max() > 1e-4) == lifts, before
        stance = np.asarray(kinematics.thesis_code_ik(actions.THESIS_CODE_STANCE)).reshape(-1)
        assert np.allclose(ctrl, stance, atol=1e-6) != lifts, before


def test_thesis_code_residual_cpg_folds_the_d_term_bug_into_one_pd_target():
    """tau = [60 (t - q) - 3 qdot + 60 (n + r - q) + 3 (a - qdot)] / 2 = 60 (ctrl - q) - 3 qdot."""
    space = actions.make_action_space("cpg-rt", 0.025, CODE)
    assert not space.split_pd
    action = jnp.concatenate([jnp.full(12, 0.5), jnp.full(12, -1.0)])
    _, ctrl = space.step(space.init(), action)
    t = np.asarray(kinematics.thesis_code_ik(actions.THESIS_CODE_STANCE)).reshape(-1) + 0.5 * actions.JOINT_OFFSET_SCALE
    n_r = robot.nominal_pose() - actions.RESIDUAL_SCALE
    a = 0.5 * actions.JOINT_OFFSET_SCALE
    q, qdot = robot.nominal_pose() + 0.01, np.full(12, 0.3)
    expected = 0.5 * (60 * (t - q) - 3 * qdot + 60 * (n_r - q) + 3 * (a - qdot))
    np.testing.assert_allclose(60 * (np.asarray(ctrl) - q) - 3 * qdot, expected, rtol=1e-5, atol=1e-5)
