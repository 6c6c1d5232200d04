"""BRO's optimistic exploration: its bounds, KL and self-adjustment against numbers worked by hand."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import optimism


def test_adjustments_start_where_bro_starts_them():
    assert abs(float(optimism.raw_of(1.0)) - 0.143841) < 1e-5
    assert abs(float(optimism.raw_of(0.25)) + 0.015578) < 1e-5
    for value in (1.0, 0.25, 3.0):
        assert abs(float(optimism.squashed(optimism.raw_of(value))) - value) < 1e-5


def test_the_bounds_are_the_mean_plus_beta_half_spreads():
    q = jnp.array([[10.0], [6.0]])
    assert float(optimism.bound(q, 0.0)[0]) == 8.0
    assert float(optimism.bound(q, 1.0)[0]) == 10.0
    assert float(optimism.bound(q, 0.5)[0]) == 9.0
    assert float(optimism.bound(q, -1.0)[0]) == 6.0  # the pessimistic bound: the minimum of two


def test_kl_of_a_shifted_mean_and_the_adjustment_losses():
    assert abs(float(optimism.shift_kl(jnp.array([0.1]), jnp.array([0.0]), jnp.array([0.5]))) - 0.02) < 1e-6
    beta, kl_weight = optimism.raw_of(1.0), optimism.raw_of(0.25)
    beta_loss, kl_loss = optimism.adjustment_losses(beta, kl_weight, 0.02)
    assert abs(float(beta_loss) + 0.03) < 1e-6 and abs(float(kl_loss) - 0.0075) < 1e-6
    # KL above its target: descending the losses lowers beta and raises the KL weight.
    grads = jax.grad(lambda r: sum(optimism.adjustment_losses(r[0], r[1], 0.2)))(jnp.stack([beta, kl_weight]))
    assert grads[0] > 0 and grads[1] < 0


def test_the_shift_network_starts_near_zero():
    net = optimism.Shift(action_size=3, hidden=(16, 16))
    obs, mean = jnp.ones((2, 5)), jnp.zeros((2, 3))
    shift = net.apply(net.init(jax.random.PRNGKey(0), obs, mean), obs, mean)
    assert shift.shape == (2, 3) and float(jnp.max(jnp.abs(shift))) < 0.1
    np.testing.assert_array_less(0, optimism.STD_MULTIPLIER)
