"""The action pipelines: the CPG approaches' sizes, offsets and frequency, residuals, and the released code's order."""

import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.control import actions, cpg
from mjx_badger.protocol import protocols
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics

TEXT = protocols.THESIS_TEXT


CODE = protocols.THESIS_CODE


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


def test_on_the_robot_the_cpg_swings_0_2_m_at_1_75_hz_and_mixes_residuals_as_each_protocol_ran_it():
    from mjx_badger.protocol import conditions
    office = conditions.OFFICE
    space = actions.make_action_space("cpg-d", 0.025, TEXT, conditions=office)
    state, _ = space.step(space.init(), jnp.zeros(12))
    assert float(state.cpg.phase) == pytest.approx(1.75 * 0.025)
    # A parameter the run sets wins over the conditions': at 2 Hz five steps reach the apex, now 0.2 m.
    space = actions.make_action_space("cpg-d", 0.025, TEXT, conditions=office, frequency_hz=2.0)
    state = space.init()
    for _ in range(5):
        state, ctrl = space.step(state, jnp.zeros(12))
    lift = np.asarray(kinematics.forward(ctrl))[:, 2] - kinematics.nominal_feet()[:, 2]
    np.testing.assert_allclose(lift, [0.2, 0.0, 0.0, 0.2], atol=1e-5)
    assert actions.on_robot("cpg-rt", CODE, office)[0].cpg_residual == "angle-sum"  # the released robot CPG
    assert actions.on_robot("cpg-rt", TEXT, office)[0].cpg_residual == "angle-average"  # §4.3 item 2
    assert actions.on_robot("cpg-vf", CODE, office)[1] == {"apex_m": 0.2}  # its frequency is its own action
    assert actions.on_robot("jt-oef", CODE, office) == (CODE, {})
    assert actions.on_robot("cpg-rt", CODE, None) == (CODE, {})  # simulation: as the simulation code ran it
