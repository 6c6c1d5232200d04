"""The on-robot run's milestones, on a hand-made trace whose answers are worked out by hand."""

import numpy as np
import pytest

from mjx_badger.outputs import real_world
from mjx_badger.realtime import milestones
from mjx_badger.realtime.report import TRACE

HZ = 40


def _trace(speeds_per_minute, fall_at_s=None):
    """A 40 Hz trace whose true forward speed holds each value for 60 s."""
    velocity = np.repeat(np.asarray(speeds_per_minute, float), 60 * HZ)
    trace = np.zeros((len(velocity), len(TRACE)), np.float32)
    trace[:, TRACE.index("step")] = np.arange(1, len(velocity) + 1)
    trace[:, TRACE.index("train_s")] = np.arange(1, len(velocity) + 1) / HZ
    trace[:, TRACE.index("true_vx")] = velocity
    if fall_at_s is not None:
        trace[int(fall_at_s * HZ), TRACE.index("fall")] = 1
    return trace


def test_milestones_are_where_the_30_s_mean_crosses_each_speed():
    # (to a sample either way) 0 for a minute, 0.1 for one, 0.3 for one, then 0.2. The 30 s mean reaches 0.05 when half the window is at
    # 0.1 (75 s), 0.125 when 3.75 s of it are at 0.3 (123.75 s: (0.1 x 26.25 + 0.3 x 3.75) / 30), and peaks at 0.3
    # from 150 s. One fall at 30 s adds the conditions' 20 s reset to every later time with resets.
    found = milestones.milestones(_trace([0.0, 0.1, 0.3, 0.2], fall_at_s=30), reset_seconds=20.0)
    assert found["first"][0] == pytest.approx(75 / 60, abs=2 / (HZ * 60))
    assert found["first"][1] == pytest.approx((75 + 20) / 60, abs=2 / (HZ * 60))
    assert found["bigger"][0] == pytest.approx(123.75 / 60, abs=2 / (HZ * 60))
    assert found["peak"][0] == pytest.approx(150 / 60, abs=2 / (HZ * 60))
    assert found["peak_velocity"] == pytest.approx(0.3, abs=1e-6)


def test_a_run_that_never_walks_reaches_no_milestone():
    found = milestones.milestones(_trace([0.0, 0.04, -0.1]), reset_seconds=0.0)
    assert found["first"] is None and found["bigger"] is None
    assert found["peak_velocity"] == pytest.approx(0.04, abs=1e-6)


def test_the_table_puts_ours_beside_the_thesis_words():
    document = {"steps": 14400, "falls": 1, "evaluation": {"true_velocity": 0.21, "true_peak_1s": 0.33}}
    table = real_world.milestones_table({"office": {"jt-oef": (document, _trace([0.0, 0.1, 0.3, 0.2], 30))}})
    # office resets take 20 s (conditions.py); the thesis's JT-OEF: 3, 4.5 and 12.5 minutes, 1.5 m/s in simulation
    assert "| office | JT-OEF | 14,400 | 1 | 1.3 / 1.6 (3) | 2.1 / 2.4 (4.5) | 2.5 / 2.8 (12.5) | 0.30 | 0.21, 0.33 | 1.5 |" in table


def test_an_evaluation_that_fell_reads_as_a_fall_not_a_speed():
    document = {"steps": 14400, "falls": 1, "evaluation": {"true_velocity": 1.02, "true_peak_1s": None, "seconds": 0.35,
                                                           "fell": "pitch +0.88 rad"}}
    table = real_world.milestones_table({"outdoor": {"jt-oef": (document, _trace([0.0, 0.1, 0.3, 0.2], 30))}})
    assert "| fell after 0.35 s |" in table and "1.02" not in table
