"""The thesis's agents' layers: batch renormalisation's two modes and the hashed dropout mask."""

import jax
import numpy as np

from mjx_badger.agents.layers import BatchRenorm, hashed_keep_mask


def test_batch_renorm_train_uses_batch_statistics_eval_uses_running_ones():
    layer = BatchRenorm(momentum=0.9)
    x = 3.0 + 2.0 * jax.random.normal(jax.random.PRNGKey(0), (512, 4))
    variables = layer.init(jax.random.PRNGKey(1), x, train=False)
    y, updated = layer.apply(variables, x, train=True, mutable=["batch_stats"])
    np.testing.assert_allclose(y.mean(0), 0.0, atol=1e-4)
    np.testing.assert_allclose(y.std(0), 1.0, atol=1e-3)
    # running mean moved 10 % of the way from 0 towards the batch mean (about 3)
    np.testing.assert_allclose(updated["batch_stats"]["mean"], 0.1 * x.mean(0), rtol=1e-5)
    assert int(updated["batch_stats"]["steps"]) == 1
    # evaluation with the initial running stats (mean 0, var 1) is nearly the identity
    y_eval = layer.apply(variables, x, train=False)
    np.testing.assert_allclose(y_eval, x / np.sqrt(1 + 1e-3), rtol=1e-5)


def test_hashed_dropout_mask_keeps_the_right_fraction_and_varies_with_the_key():
    a = np.asarray(hashed_keep_mask(jax.random.PRNGKey(0), (256, 256), 0.1))
    b = np.asarray(hashed_keep_mask(jax.random.PRNGKey(1), (256, 256), 0.1))
    assert abs(a.mean() - 0.9) < 0.005 and abs(b.mean() - 0.9) < 0.005
    # Independent masks agree on about 0.9^2 + 0.1^2 = 82 % of the entries.
    assert abs((a == b).mean() - 0.82) < 0.01
    # No structure along rows or columns.
    assert np.abs(a.mean(axis=0) - 0.9).max() < 0.1 and np.abs(a.mean(axis=1) - 0.9).max() < 0.1
