"""The on-robot loop's memory: its replay and trace grow with its steps, and a run that cannot fit is refused."""

import pytest

from mjx_badger.realtime import memory
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.report import TRACE


def test_the_estimate_grows_by_one_replay_row_and_one_trace_row_per_step(monkeypatch):
    short, long = (RealtimeConfig(approach="jt-oef", steps=steps, warmup_steps=100) for steps in (1000, 2000))
    row = 4 * (2 * 54 + 12 + 2) + 8 * len(TRACE)  # float32 obs, action, reward, next obs, discount; float64 trace
    assert memory.estimate(long) - memory.estimate(short) == 1000 * row
    monkeypatch.setattr(memory, "host_available", lambda: memory.estimate(short))
    memory.check(short)
    with pytest.raises(ValueError, match="the run does not fit: .* for 2000 steps of replay and trace"):
        memory.check(long)
