"""A fitted learned estimator gives the same velocity in NumPy as in JAX."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.estimation import estimators, fit, learned

DT = 0.025


def _dataset(robot_name="hb40", steps=60, envs=5, seed=0):
    """A synthetic dataset: the velocity a known function of the readings, so a fit can learn it."""
    rng = np.random.default_rng(seed)
    arrays = {name: rng.normal(size=(steps, envs, size)).astype(np.float32) for name, size in learned.FIELDS}
    arrays["velocity"] = np.stack([0.3 * arrays["acceleration"][..., 0], 0.1 * arrays["joint_angle"][..., 1],
                                   np.zeros((steps, envs))], -1).astype(np.float32)
    arrays["done"] = rng.random((steps, envs)) < 0.05
    meta = {"robot": robot_name, "fields": [list(f) for f in learned.FIELDS], "policy": "synthetic",
            "steps": steps, "envs": envs, "task": "none", "control_hz": 40.0}
    return meta, arrays


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    meta, arrays = _dataset()
    config = fit.FitConfig(epochs=8, batch_size=32)
    document = fit.fit(meta, arrays, learned.INPUTS["rich"], config)
    return fit.save(tmp_path_factory.mktemp("estimator") / "rich.estimator.npz", document)


def test_a_saved_learned_estimator_gives_the_same_velocity_in_numpy_as_in_jax(fitted):
    estimator = learned.load(fitted)
    curve = estimator.meta["curves"]["train_mae"]
    assert sum(curve[-1]) < sum(curve[0])  # it learned
    meta, arrays = _dataset(seed=3)
    readings = [estimators.Reading(arrays["joint_angle"][t, 0], arrays["joint_velocity"][t, 0],
                                   arrays["acceleration"][t, 0], arrays["angular_velocity"][t, 0],
                                   np.eye(3, dtype=np.float32), arrays["contacts"][t, 0], arrays["joint_torque"][t, 0])
                for t in range(12)]
    runner = estimator.numpy()
    with_numpy = np.array([runner.update(r) for r in readings])
    jax_estimator = estimators.make("learned", path=fitted)
    step = jax.jit(jax_estimator.step)
    state, with_jax = jax_estimator.init(), []
    for r in readings:
        state, velocity = step(state, jax.tree.map(jnp.asarray, r), DT)
        with_jax.append(np.asarray(velocity))
    np.testing.assert_allclose(with_numpy, np.array(with_jax), atol=1e-4)
    assert np.all(with_numpy[:, 2] == 0.0) and np.any(with_numpy[:, 0] != 0.0)
