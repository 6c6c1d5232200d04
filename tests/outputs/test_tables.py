"""The tables: our seeds read as the released code's and counted inside its range."""

import numpy as np

from mjx_badger.outputs import tables
from mjx_badger.records import analysis


def test_our_seeds_are_read_as_the_released_codes_and_counted_inside_its_range():
    # Two seeds, 1000-step chunks; warm-up ends at 1000 with one fall already counted for seed 1.
    document = {"config": {"warmup_steps": 1000}, "seeds": [0, 1], "steps": [1000, 2000, 3000, 4000, 5000],
                "metrics": {"train/forward_velocity": [[0.1, 0.1], [0.5, 0.2], [0.6, 0.3], [0.5, 0.3], [0.4, 0.3]],
                            "train/falls": [[0, 1], [0, 3], [2, 5], [3, 5], [4, 6]]}}
    measured = analysis.per_seed_released_measures(document)
    assert measured["steps_to_0.45"] == [2000, None]  # seed 1 never reaches 0.45 m/s
    np.testing.assert_allclose(measured["velocity_last_3k"], [0.5, 0.3])  # mean of the last three chunks
    assert measured["falls"] == [4.0, 5.0]  # the fall in warm-up does not count
    released = {"approaches": {"jt-nf": {"steps_to_0.45": [1000, 3000], "velocity_last_3k": [0.45, 0.55],
                                         "falls": [4, 9]}}}
    row = tables.released_code_table({"jt-nf": document}, released, "quick").splitlines()[-1]
    assert row == "| JT-NF | 1k, 3k / 2k, never (1 of 2) | 0.45, 0.55 / 0.50, 0.30 (1 of 2) | 4, 9 / 4, 5 (2 of 2) |"
