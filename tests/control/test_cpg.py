"""Leg kinematics, the trot CPG and the CPG action spaces."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.control import cpg


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


