"""The newer agents' network bodies: their shapes, sizes and normalisations against numbers worked by hand."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents import trunks
from mjx_badger.agents.networks import Actor, QNetwork

KEY = jax.random.PRNGKey(0)


def count(params) -> int:
    return sum(x.size for x in jax.tree.leaves(params))


def test_unit_and_the_scaler():
    np.testing.assert_allclose(trunks.unit(jnp.array([3.0, 4.0])), [0.6, 0.8])
    np.testing.assert_allclose(trunks.unit(jnp.zeros(2)), [0.0, 0.0])
    scaler = trunks.Scaler(start=0.5, size=0.125)
    params = scaler.init(KEY, jnp.ones(3))
    np.testing.assert_allclose(params["params"]["gain"], [0.125] * 3)  # stored at its size ...
    np.testing.assert_allclose(scaler.apply(params, jnp.array([1.0, 2.0, 4.0])), [0.5, 1.0, 2.0])  # ... acts at start


def test_simba_features_lie_on_the_unit_sphere():
    trunk = trunks.HyperTrunk(widths=(16, 16, 16))
    obs = jax.random.normal(KEY, (4, 7)) * 10
    out = trunk.apply(trunk.init(KEY, obs, False), obs, False)
    np.testing.assert_allclose(jnp.linalg.norm(out, axis=-1), np.ones(4), rtol=1e-5)


def test_a_bro_critic_has_the_size_of_the_published_one():
    # Input layer 512 wide, two residual blocks of two 512 layers with layer norms, 100 quantiles: 512 d + 1,107,556.
    obs, action = jnp.ones((1, 54)), jnp.ones((1, 12))
    critic = QNetwork(hidden=(512,) * 3, trunk="bro", outputs=100)
    assert count(critic.init(KEY, obs, action)) == 512 * 66 + 1_107_556
    assert critic.apply(critic.init(KEY, obs, action), obs, action).shape == (1, 100)


def test_xqc_blocks_have_no_dense_bias_and_normalise_by_the_batch_in_training():
    trunk = trunks.XQCTrunk(widths=(8, 8))
    x = jax.random.normal(KEY, (32, 5)) * 3 + 7
    variables = trunk.init(KEY, x, True)
    dense = [v for k, v in variables["params"].items() if k.startswith("Dense")]
    assert len(dense) == 2 and all(set(d) == {"kernel"} for d in dense)
    out, _ = trunk.apply(variables, x, True, mutable=["batch_stats"])
    # ReLU of batch-normalised features: about half of each feature's batch is zero.
    assert 0.2 < float(jnp.mean(out == 0)) < 0.8


def test_fastsac_starts_its_policy_at_zero_mean_and_the_middle_of_its_log_std_range():
    actor = Actor(action_size=3, hidden=(16, 8), trunk="layernorm", log_std_range=(-5.0, 0.0))
    obs = jnp.ones((2, 5))
    mean, log_std = actor.apply(actor.init(KEY, obs), obs)
    np.testing.assert_allclose(mean, 0.0)
    np.testing.assert_allclose(log_std, -2.5)  # raw 0 squashed into [-5, 0]


def test_an_unknown_body_is_named_with_the_valid_ones():
    with pytest.raises(ValueError, match="unknown network body 'resnet'; valid: mlp, xqc, bro, simba, layernorm"):
        trunks.make_trunk("resnet", (8,))


def test_orthogonal_initialisation_has_orthonormal_columns_or_rows_times_its_scale():
    tall = trunks.orthogonal(2.0)(KEY, (40, 8))
    np.testing.assert_allclose(tall.T @ tall, 4.0 * np.eye(8), atol=1e-4)
    wide = trunks.orthogonal(1.0)(KEY, (8, 40))
    np.testing.assert_allclose(wide @ wide.T, np.eye(8), atol=1e-4)
    stacked = jax.vmap(lambda k: trunks.orthogonal(1.0)(k, (16, 16)))(jax.random.split(KEY, 3))  # an ensemble's
    np.testing.assert_allclose(jnp.einsum("eij,eik->ejk", stacked, stacked), np.broadcast_to(np.eye(16), (3, 16, 16)),
                               atol=1e-4)
    assert not np.allclose(stacked[0], stacked[1])
