"""The real-world numbers: heading drift in the thesis's categories, minutes with each fall's reset."""

import numpy as np
import pytest

from mjx_badger.records import real_world
from tests.documents import real_world_document


@pytest.mark.parametrize("degrees, category", [(5, "very good"), (10, "good"), (29.9, "good"), (45, "medium"),
                                               (61, "poor")])
def test_heading_drift_falls_in_the_thesis_categories(degrees, category):
    document = real_world_document(0.3, 0.0, yaw_rate=np.radians(degrees) / 10.0)
    row = real_world.summary(document)
    assert row["yaw_drift_deg"] == pytest.approx(degrees) and row["yaw"] == category


def test_minutes_count_each_fall_at_the_conditions_reset_time():
    row = real_world.summary(real_world_document(0.3, falls=30.0))
    # 20k steps at 40 Hz are 8.33 simulated minutes; each of 30 falls adds the office's 20 s reset.
    assert row["minutes"] == pytest.approx(20 * 0.4167 + 30 * 20 / 60)
    assert row["falls"] == 30.0 and row["estimated_velocity"] == pytest.approx(0.05)


def test_the_row_gives_the_falls_by_10k_steps_and_the_stops_the_truth_calls_no_fall():
    document = real_world_document(0.3, falls=40.0)  # falls rise evenly over 20 chunks of 1k steps
    row = real_world.summary(document)
    assert row["falls_10k"] == 20.0 and row["stops_before_fall"] is None
    document["metrics"].update({"train/stops_before_fall": [[6.0, 8.0]] * 20, "train/premature_stops": [[1.0, 3.0]] * 20})
    row = real_world.summary(document)
    assert (row["stops_before_fall"], row["premature_stops"]) == (7.0, 2.0)
