"""The memory a run needs: its estimate scales with seeds, steps and sweep members."""

import pytest

from mjx_badger.learning import memory
from mjx_badger.learning.config import TrainConfig


def test_the_estimate_scales_with_seeds_steps_and_sweep_members():
    small, large = TrainConfig(total_steps=10_000, chunk_steps=1000), TrainConfig(total_steps=50_000)
    assert memory.carry_sizes(large)["replay_bytes"] == pytest.approx(5 * memory.carry_sizes(small)["replay_bytes"], rel=1e-4)
    grow = lambda config, **k: memory.estimate(config, **k) - memory.OVERHEAD_BYTES
    assert grow(large, seeds=4) == 4 * grow(large, seeds=1) == 2 * grow(large, seeds=2, members=1)
    assert grow(large, seeds=2, members=3) == 6 * grow(large, seeds=1)
