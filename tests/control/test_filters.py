"""Filters against hand-computed step responses, and scan == Python loop."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.signal

from mjx_badger.control import actions, filters
from mjx_badger.protocol import protocols

DT = 0.025  # 40 Hz control


def test_smoothing_factor_by_hand():
    # f_c = 0.4 Hz: tau = 1 / (2 pi 0.4) = 0.397887; alpha = 1 / (1 + 0.397887 / 0.025) = 1 / 16.91549 = 0.0591174
    assert float(filters.smoothing_factor(0.4, DT)) == pytest.approx(0.0591174, rel=1e-5)


def test_no_filter_is_identity():
    f = filters.make_filter("none", DT)
    state = f.init(jnp.zeros(3))
    _, y = f.step(state, jnp.array([1.0, -2.0, 3.0]))
    np.testing.assert_array_equal(y, [1.0, -2.0, 3.0])


def test_low_pass_step_response():
    f = filters.make_filter("lowpass", DT)
    state = f.init(jnp.zeros(1))
    outputs = []
    for _ in range(3):
        state, y = f.step(state, jnp.ones(1))
        outputs.append(float(y[0]))
    # y_n = 1 - (1 - alpha)^n with alpha = 0.0591174: 0.0591174, 0.1147400, 0.1670743
    np.testing.assert_allclose(outputs, [0.0591174, 0.1147400, 0.1670743], rtol=1e-5)


def test_one_euro_step_response():
    f = filters.make_filter("one_euro", DT)
    state = f.init(jnp.zeros(1))
    state, y1 = f.step(state, jnp.ones(1))
    # alpha_d (100 Hz) = 1 / (1 + 0.00159155 / 0.025) = 0.9401483
    # dx_1 = alpha_d * (1 - 0) / 0.025 = 37.605932
    # f_c = 2.5 + 0.1 * 37.605932 = 6.2605932 Hz; tau = 0.0254216; alpha = 1 / (1 + 1.0168643) = 0.4958182
    assert float(y1[0]) == pytest.approx(0.4958182, rel=1e-5)
    state, y2 = f.step(state, jnp.ones(1))
    # dx_2 = alpha_d * 0 + (1 - alpha_d) * 37.605932 = 2.2507789; f_c = 2.7250779 Hz
    # tau = 0.0584038; alpha = 1 / (1 + 2.3361526) = 0.2997465; y2 = y1 + alpha (1 - y1) = 0.6469449
    assert float(y2[0]) == pytest.approx(0.6469449, rel=1e-5)


def test_one_euro_follows_fast_moves_closer_than_low_pass():
    x = jnp.ones(1)
    lp, oe = filters.make_filter("lowpass", DT), filters.make_filter("one_euro", DT)
    _, y_lp = lp.step(lp.init(jnp.zeros(1)), x)
    _, y_oe = oe.step(oe.init(jnp.zeros(1)), x)
    assert float(y_oe[0]) > float(y_lp[0])


@pytest.mark.parametrize("name", list(filters.FILTERS))
def test_scan_equals_python_loop(name):
    f = filters.make_filter(name, DT)
    signal = jax.random.normal(jax.random.PRNGKey(0), (50, 12))
    _, scanned = jax.lax.scan(f.step, f.init(jnp.zeros(12)), signal)
    state, looped = f.init(jnp.zeros(12)), []
    for x in signal:
        state, y = f.step(state, x)
        looped.append(y)
    np.testing.assert_allclose(scanned, np.stack(looped), rtol=1e-5, atol=1e-6)


CODE, TEXT = protocols.THESIS_CODE, protocols.THESIS_TEXT


def test_butterworth_low_pass_matches_scipy_lfilter():
    """thesis-code's JT-LPF: scipy.signal.butter(2, 4 Hz, fs=40) run with lfilter from rest."""
    b, a = scipy.signal.butter(2, 4.0, fs=40.0)
    np.testing.assert_allclose(filters.butterworth_coefficients(4.0, 40.0), (b, a), rtol=1e-12)
    x = np.random.default_rng(0).normal(size=(60, 12))
    rest = np.linspace(-1.0, 1.0, 12)
    expected = scipy.signal.lfilter(b, a, x - rest, axis=0) + rest  # zero state on the offsets from rest
    filt = filters.butterworth(1 / 50)
    _, ours = jax.lax.scan(filt.step, filt.init(jnp.asarray(rest)), jnp.asarray(x))
    np.testing.assert_allclose(ours, expected, atol=1e-5)
    # The JT-LPF action space uses it under thesis-code and the first-order filter under thesis-text.
    code = actions.make_action_space("jt-lpf", 0.02, CODE)
    text = actions.make_action_space("jt-lpf", 0.02, TEXT)
    assert isinstance(code.init().filter, filters.BiquadState)
    assert isinstance(text.init().filter, filters.LowPassState)


def test_one_euro_first_output_is_the_first_input_under_the_code():
    x = jnp.array([0.3, -0.2])
    code = filters.one_euro(0.02, start_at_first_input=True)
    _, first = code.step(code.init(jnp.zeros(2)), x)
    np.testing.assert_allclose(first, x)
    text = filters.one_euro(0.02)
    _, first_text = text.step(text.init(jnp.zeros(2)), x)
    assert np.abs(np.asarray(first_text)).max() < 0.2  # started at rest, it moves only part of the way
    space = actions.make_action_space("jt-oef", 0.02, CODE)
    _, target = space.step(space.init(), jnp.ones(12))
    np.testing.assert_allclose(target - space.init().target, np.tile([0.2, 0.4, 0.4], 4), atol=1e-6)
