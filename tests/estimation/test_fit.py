"""The learned estimator's dataset and fit: windows restart at resets, a dataset of another layout is refused."""

import numpy as np

from mjx_badger.estimation import fit
from mjx_badger.estimation.learned import FIELDS
from tests.commands import refused


def _dataset(robot_name="hb40", steps=60, envs=5, seed=0):
    """A synthetic dataset: the velocity a known function of the readings, so a fit can learn it."""
    rng = np.random.default_rng(seed)
    arrays = {name: rng.normal(size=(steps, envs, size)).astype(np.float32) for name, size in FIELDS}
    arrays["velocity"] = np.stack([0.3 * arrays["acceleration"][..., 0], 0.1 * arrays["joint_angle"][..., 1],
                                   np.zeros((steps, envs))], -1).astype(np.float32)
    arrays["done"] = rng.random((steps, envs)) < 0.05
    meta = {"robot": robot_name, "fields": [list(f) for f in FIELDS], "policy": "synthetic",
            "steps": steps, "envs": envs, "task": "none", "control_hz": 40.0}
    return meta, arrays


def test_the_windows_of_the_fit_start_afresh_at_every_reset():
    done = np.array([[False], [False], [True], [False], [False]])
    np.testing.assert_array_equal(fit.since_reset(done)[:, 0], [0, 1, 0, 1, 2])


def test_a_dataset_of_another_robot_or_layout_is_refused_with_one_line(tmp_path, capsys):
    other = fit.save_dataset(tmp_path / "other.npz", *reversed(_dataset("hb40-v1")))
    err = refused(capsys, ["estimator", "fit", "--dataset", str(other)])
    assert err == f"error: {other}: a dataset of robot 'hb40-v1', not 'hb40'\n"
    meta, arrays = _dataset()
    meta["fields"] = meta["fields"][:-1]
    layout = fit.save_dataset(tmp_path / "layout.npz", arrays, meta)
    err = refused(capsys, ["estimator", "fit", "--dataset", str(layout)])
    assert err.startswith(f"error: {layout}: its fields")  # one line: refused checks it
    assert sorted(p.name for p in tmp_path.iterdir()) == ["layout.npz", "other.npz"]  # nothing written
