"""The on-robot run's results document and trace: timing percentiles, the period histogram, rows of the trace."""

import json

import numpy as np
import pytest

from mjx_badger.realtime import report
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.control import Progress

CONFIG = RealtimeConfig(approach="jt-oef", steps=400, warmup_steps=100)


def _progress(steps: int = 300) -> Progress:
    """A run of `steps` steps at 1 s each, walking at 0.1 * step m/s truly and half of it as estimated, one fall."""
    progress = Progress(CONFIG.steps)
    for k in range(1, steps + 1):
        progress.trace[k - 1] = (k, k, 0.05 * k, 0.0, 0.1 * k, 0.0, 1.0, float(k == 150))
    progress.step, progress.falls, progress.train_seconds = steps, 1, float(steps)
    return progress


def test_a_row_averages_the_last_200_steps_of_the_trace():
    row = report.row(_progress(), updates=40)
    # Steps 101..300: true velocity 0.1 x their mean step 200.5, the estimate half of it.
    assert row["true_velocity"] == pytest.approx(20.05) and row["estimated_velocity"] == pytest.approx(10.025)
    assert row["step"] == 300 and row["train_minutes"] == 5.0 and row["falls"] == 1 and row["updates"] == 40
    assert report.column(_progress().trace, "fall")[149] == 1.0


def test_the_document_gives_the_control_periods_percentiles_and_histogram_around_25_ms():
    timing = report.timing_log(fifo=False, locked=True, page_faults=0)
    timing.update(periods=[0.025] * 98 + [0.030, 0.040], work=[0.004] * 100, wake=[0.0001] * 100,
                  at_step=list(range(100)), at_time=[0.0] * 100, late=2, ticks=100)
    document = report.document(CONFIG, _progress(), timing, updates=400, compile_s=3.0, started="now", complete=False,
                               evaluation={})
    t = document["timing"]
    assert t["nominal_period_ms"] == 25.0 and t["period_p50_ms"] == pytest.approx(25.0)
    assert t["period_error_max_ms"] == pytest.approx(15.0) and t["missed_deadlines"] == 2
    assert t["worst_periods"][0]["period_ms"] == pytest.approx(40.0) and t["scheduling"] == report.ORDINARY_LABEL
    histogram = t["period_histogram"]  # 25 +- 5 ms: the 40 ms period lies above it
    assert sum(histogram["counts"]) == 99 and histogram["above"] == 1 and histogram["below"] == 0
    assert document["updates_per_learning_step"] == 400 / (300 - 100)
    json.dumps(document)  # a results file can hold it


def test_the_document_and_trace_are_saved_beside_each_other(tmp_path):
    progress = _progress(50)
    report.save(tmp_path, CONFIG, {"schema": report.SCHEMA}, progress)
    assert json.loads(report.document_path(tmp_path, CONFIG).read_text())["schema"] == report.SCHEMA
    trace = report.load_trace(tmp_path, CONFIG)
    assert trace.shape == (50, len(report.TRACE)) and trace.dtype == np.float32
