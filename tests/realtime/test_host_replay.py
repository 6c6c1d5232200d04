"""The on-robot replay buffer in host memory: a ring the control thread fills, sampled and saved whole."""

import numpy as np

from mjx_badger.realtime.host_replay import HostReplay


def test_the_ring_keeps_the_newest_transitions_and_samples_only_stored_ones(tmp_path):
    buffer = HostReplay(capacity=4, obs_size=2, action_size=1)
    for k in range(6):  # 4 and 5 replace 0 and 1
        buffer.add(np.full(2, k), np.full(1, -k), float(k), np.full(2, k + 1), 1.0)
    assert buffer.size == 6 and buffer.reward.tolist() == [4.0, 5.0, 2.0, 3.0]
    batch = buffer.sample(np.random.default_rng(0), 64)
    assert set(batch.reward.tolist()) <= {2.0, 3.0, 4.0, 5.0} and np.array_equal(batch.action[:, 0], -batch.reward)
    buffer.save(tmp_path / "replay.npz")
    again = HostReplay(capacity=4, obs_size=2, action_size=1)
    again.load(tmp_path / "replay.npz")
    assert again.size == 6 and np.array_equal(again.next_obs, buffer.next_obs)


def test_an_early_sample_draws_from_the_few_stored():
    buffer = HostReplay(capacity=100, obs_size=1, action_size=1)
    buffer.add(np.ones(1), np.ones(1), 7.0, np.ones(1), 0.0)
    assert set(buffer.sample(np.random.default_rng(1), 8).reward.tolist()) == {7.0}
