"""The on-robot checkpoint: policy, replay, trace and counters saved whole and restored; another run's refused."""

import dataclasses

import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.realtime import session_checkpoint
from mjx_badger.realtime.host_replay import HostReplay
from tests.realtime.test_report import CONFIG, _progress


def _state(value: float) -> tuple:
    return {"w": jnp.full(3, value)}, {"bins": jnp.zeros(2)}, jnp.array([0, value], jnp.uint32)


def test_a_saved_session_comes_back_as_it_was(tmp_path):
    folder = session_checkpoint.path(tmp_path, CONFIG)
    buffer = HostReplay(10, 2, 1)
    buffer.add(np.ones(2), np.ones(1), 2.0, np.ones(2), 1.0)
    progress = _progress(50)
    session_checkpoint.save(folder, CONFIG, *_state(5.0), 123, buffer, progress)
    assert session_checkpoint.exists(folder)
    fresh_buffer, fresh = HostReplay(10, 2, 1), _progress(0)
    agent, task_state, key, updates = session_checkpoint.load(folder, CONFIG, *_state(0.0), fresh_buffer, fresh)
    assert agent["w"].tolist() == [5.0] * 3 and key.tolist() == [0, 5] and updates == 123
    assert fresh.step == 50 and fresh.falls == 1 and fresh_buffer.size == 1
    np.testing.assert_array_equal(fresh.trace[:50], progress.trace[:50])


def test_another_runs_or_a_damaged_checkpoint_is_refused_naming_it(tmp_path):
    folder = session_checkpoint.path(tmp_path, CONFIG)
    session_checkpoint.save(folder, CONFIG, *_state(1.0), 0, HostReplay(10, 2, 1), _progress(10))
    other = dataclasses.replace(CONFIG, seed=7)
    with pytest.raises(ValueError, match="holds a run with other settings"):
        session_checkpoint.load(folder, other, *_state(0.0), HostReplay(10, 2, 1), _progress(0))
    newest = next(p for p in folder.parent.iterdir() if p.name.startswith(folder.name) and p.is_dir())
    (newest / "state.msgpack").write_bytes(b"cut short")
    with pytest.raises(ValueError, match="is damaged"):
        session_checkpoint.load(folder, CONFIG, *_state(0.0), HostReplay(10, 2, 1), _progress(0))
