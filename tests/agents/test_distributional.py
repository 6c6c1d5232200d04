"""Distributional critics: the categorical projection and quantile regression against numbers worked by hand."""

import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import distributional

ATOMS = distributional.support(5, -1.0, 1.0)  # [-1, -0.5, 0, 0.5, 1]: atoms 0.5 apart


def one_hot(index, size=5):
    return jnp.eye(size)[index][None, :]


def test_a_terminal_reward_on_an_atom_puts_all_mass_there_and_one_beyond_the_support_is_clipped():
    np.testing.assert_allclose(ATOMS, [-1, -0.5, 0, 0.5, 1])
    for reward, atom in ((0.5, 3), (-1.0, 0), (5.0, 4)):
        target = distributional.project(one_hot(2), jnp.array([reward]), jnp.array([0.0]), ATOMS)
        np.testing.assert_allclose(target[0], jnp.eye(5)[atom], atol=1e-6)


def test_a_bootstrapped_atom_between_two_splits_its_mass_by_closeness():
    # r 0.1, discount 0.9, next mass on 0.5: 0.1 + 0.45 = 0.55 sits a tenth of the way from atom 3 to atom 4.
    target = distributional.project(one_hot(3), jnp.array([0.1]), jnp.array([0.9]), ATOMS)
    np.testing.assert_allclose(target[0], [0, 0, 0, 0.9, 0.1], atol=1e-6)
    # SAC's entropy term shifts the atoms first: alpha log pi = -0.1 gives 0.1 + 0.9 (0.5 + 0.1) = 0.64.
    target = distributional.project(one_hot(3), jnp.array([0.1]), jnp.array([0.9]), ATOMS, jnp.array([-0.1]))
    np.testing.assert_allclose(target[0], [0, 0, 0, 0.72, 0.28], atol=1e-6)
    spread = jnp.full((1, 5), 0.2)
    assert abs(float(distributional.project(spread, jnp.array([0.3]), jnp.array([0.5]), ATOMS).sum()) - 1) < 1e-6


def test_categorical_mean_and_cross_entropy():
    assert abs(float(distributional.categorical_mean(jnp.zeros(5), ATOMS))) < 1e-6  # equal logits: the middle
    assert abs(float(distributional.categorical_mean(jnp.array([0, 0, 0, 0, 100.0]), ATOMS)) - 1) < 1e-6
    # Uniform prediction over 4 atoms against a one-hot target: -log(1/4).
    np.testing.assert_allclose(distributional.cross_entropy(jnp.eye(4)[:1], jnp.zeros((1, 4))), [np.log(4)],
                               rtol=1e-6)


def test_quantile_levels_are_midpoints_and_the_huber_loss_weights_by_side():
    np.testing.assert_allclose(distributional.quantile_levels(4), [0.125, 0.375, 0.625, 0.875])
    # Levels 0.25, 0.75 predicting 0 and 1 against samples 0.5 and 2: pairs (0, .5) .25 x .125, (0, 2) .25 x 1.5,
    # (1, .5) below: .25 x .125, (1, 2) .75 x .5; summed over predictions, averaged over samples: 0.40625.
    loss = distributional.quantile_huber(jnp.array([[0.0, 1.0]]), jnp.array([[0.5, 2.0]]))
    assert abs(float(loss) - 0.40625) < 1e-6
