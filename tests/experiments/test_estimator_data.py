"""The learned estimator's dataset: walked by a run's saved policy, refused before compiling if it has none."""

import pytest

from mjx_badger.core.paths import REFERENCE
from mjx_badger.estimation.learned import FIELDS
from mjx_badger.experiments import estimator_data


def test_a_run_without_a_saved_policy_is_refused_before_anything_is_built(tmp_path):
    without = REFERENCE / "quick" / "thesis-code" / "forward" / "jt-nf_crossq_forward.json"
    with pytest.raises(ValueError, match="has no saved policy"):
        estimator_data.collect(without, steps=10, envs=2)
    with pytest.raises(ValueError, match="has no saved policy"):
        estimator_data.write(without, 1000, 2, "omni-random", 0, 0.0, tmp_path / "dataset.npz")
    assert list(tmp_path.iterdir()) == []


def test_the_dataset_records_every_field_an_estimator_can_read():
    assert [name for name, _ in FIELDS][:3] == ["joint_angle", "joint_velocity", "joint_torque"]
    assert estimator_data.collect.__defaults__[:2] == ("omni-random", 0)  # random commands, every direction
