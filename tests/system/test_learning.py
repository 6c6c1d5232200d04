"""Learning runs (minutes each): `make test-slow`."""

import numpy as np
import pytest

from mjx_badger.learning import runner
from mjx_badger.learning.config import TrainConfig


@pytest.mark.slow
def test_crossq_jt_nf_learns_to_walk_forward(tmp_path):
    """Quick-profile JT-NF seeds pass 0.3 m/s mean training velocity by 6k steps (0.35 at 4k)."""
    config = TrainConfig(approach="jt-nf", algo="crossq", task="forward", total_steps=6_000, chunk_steps=1_000)
    document = runner.run(config, [0, 1], tmp_path / "learn.json", progress=False)
    velocity = np.array(document["metrics"]["train/forward_velocity"])
    assert velocity[0].mean() < 0.1, "warm-up already walks forward?"
    assert velocity[-1].mean() > 0.3, f"mean training velocity {velocity[-1].mean():.2f} m/s after 6k steps"
