"""Gait frequency from foot contacts: a trot's, a brushing foot's, standing still's."""

import numpy as np
import pytest

from mjx_badger.sim import gait

DT = 0.005


T = np.arange(400) * DT  # a 2 s gait record at the physics rate


def trot(hz, duty=0.5, offsets=(0.0, 0.5, 0.5, 0.0)):
    """Contacts (T, 4) of a gait at `hz`: each foot in stance for `duty` of its cycle."""
    return np.stack([((T * hz + o) % 1.0) >= (1.0 - duty) for o in offsets], axis=1).astype(int)


@pytest.mark.parametrize("hz", [2.0, 2.5, 4.0, 6.0])
def test_gait_frequency_of_a_trot(hz):
    assert gait.gait_frequency(trot(hz), DT) == pytest.approx(hz, abs=0.05)


def test_a_foot_brushing_the_floor_mid_swing_does_not_double_the_frequency():
    contacts = trot(2.0)
    brush = ((T * 2.0) % 1.0 > 0.2) & ((T * 2.0) % 1.0 < 0.25)  # FL touches briefly during its swing
    contacts[brush, 0] = 1
    assert gait.gait_frequency(contacts, DT) == pytest.approx(2.0, abs=0.05)


def test_standing_still_has_no_gait_frequency():
    assert np.isnan(gait.gait_frequency(np.ones((400, 4), int), DT))


@pytest.mark.parametrize("first, second", [((0.4, 0.65), (0.8, 1.0)), ((0.5, 0.65), (0.85, 1.0))])
def test_two_touchdowns_per_cycle_still_count_one_cycle(first, second):
    """Stance split by a hop: the 2nd (or 3rd) harmonic is the strongest line, the cycle is still 2 Hz."""
    phase = (T[:, None] * 2.0 + np.array([0.0, 0.5, 0.5, 0.0])) % 1.0
    contacts = (((phase >= first[0]) & (phase < first[1])) | ((phase >= second[0]) & (phase < second[1]))).astype(int)
    assert gait.gait_frequency(contacts, DT) == pytest.approx(2.0, abs=0.05)
