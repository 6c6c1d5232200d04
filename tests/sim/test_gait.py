"""Gait frequency from foot contacts: a trot's, a brushing foot's, standing still's."""

import warnings

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


@pytest.mark.parametrize("steps", [0, 1])
def test_no_contacts_to_read_have_no_gait_frequency_and_no_warning(steps):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.isnan(gait.gait_frequency(np.zeros((steps, 4)), DT))


def test_standing_still_has_no_gait_frequency():
    assert np.isnan(gait.gait_frequency(np.ones((400, 4), int), DT))


@pytest.mark.parametrize("first, second", [((0.4, 0.65), (0.8, 1.0)), ((0.5, 0.65), (0.85, 1.0))])
def test_two_touchdowns_per_cycle_still_count_one_cycle(first, second):
    """Stance split by a hop: the 2nd (or 3rd) harmonic is the strongest line, the cycle is still 2 Hz."""
    phase = (T[:, None] * 2.0 + np.array([0.0, 0.5, 0.5, 0.0])) % 1.0
    contacts = (((phase >= first[0]) & (phase < first[1])) | ((phase >= second[0]) & (phase < second[1]))).astype(int)
    assert gait.gait_frequency(contacts, DT) == pytest.approx(2.0, abs=0.05)


@pytest.mark.parametrize("name, offsets", [
    ("trot", (0.0, 0.5, 0.5, 0.0)),  # diagonals together
    ("pace", (0.0, 0.5, 0.0, 0.5)),  # same-side feet together
    ("walk", (0.0, 0.5, 0.75, 0.25)),  # left and right opposed, hind a quarter behind
    ("bound", (0.0, 0.0, 0.5, 0.5)),  # fore pair together, hind pair half a cycle later
    ("pronk", (0.0, 0.0, 0.0, 0.0)),
    ("gallop", (0.0, 0.15, 0.55, 0.7)),  # each pair's feet close, not together: the lead
])
def test_gaits_are_named_from_the_feet_phases(name, offsets):
    assert gait.gait_name(trot(2.0, offsets=offsets), DT) == name


def test_leg_phases_give_each_foot_its_delay_behind_the_first():
    phases = gait.leg_phases(trot(2.0, offsets=(0.0, 0.15, 0.55, 0.7)), DT, 2.0)
    # trot() advances a foot by its offset: the delay behind FL is 1 - offset, in cycles
    assert phases == pytest.approx([0.0, 0.85, 0.45, 0.30], abs=0.02)


def test_standing_and_a_foot_that_never_lifts_are_not_named_as_gaits():
    assert gait.gait_name(np.ones((400, 4)), DT) == "standing"
    three_legged = trot(2.0)
    three_legged[:, 2] = 1
    assert gait.gait_name(three_legged, DT) == "irregular"
