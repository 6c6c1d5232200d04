"""Gait measures from foot contacts: the gait frequency of a run, on either engine or from a results file."""

import numpy as np


def gait_frequency(contacts, dt: float, low_hz: float = 0.5, high_hz: float = 12.0) -> float:
    """Gait frequency (Hz): the strongest frequency of the feet's contact signals, summed over feet.

    A spectral peak rather than a touchdown count, so a foot that brushes the floor twice in
    one cycle does not double the figure (Hann window, zero-padded to 0.01 Hz bins).
    """
    contacts = np.asarray(contacts, dtype=float)
    if len(contacts) < 2:
        return float("nan")  # an episode that ended at once has no contacts to read a rhythm from
    signal = (contacts - contacts.mean(axis=0)) * np.hanning(len(contacts))[:, None]
    n = max(int(round(1.0 / (0.01 * dt))), len(contacts))
    power = np.sum(np.abs(np.fft.rfft(signal, n=n, axis=0)) ** 2, axis=1)
    frequency = np.fft.rfftfreq(n, dt)
    band = (frequency >= low_hz) & (frequency <= high_hz)
    if not np.any(power[band] > 0):
        return float("nan")  # no foot changes contact: standing still
    peak = frequency[band][np.argmax(power[band])]
    # Two touchdowns per cycle can make the second harmonic the strongest line: take the lowest
    # whole fraction of the peak that still carries a third of its power, the cycle itself.
    for divisor in (4, 3, 2):
        near = band & (np.abs(frequency - peak / divisor) <= 0.15)
        if peak / divisor >= low_hz and np.any(near) and power[near].max() >= power[band].max() / 3:
            return float(frequency[near][np.argmax(power[near])])
    return float(peak)


PHASE_TOLERANCE = 0.125
"""Cycles (an eighth) within which two feet count as landing together, or half a cycle apart."""
GAITS = ("trot", "pace", "walk", "bound", "pronk", "gallop", "standing", "irregular")
"""What `gait_name` can call a gait."""


def leg_phases(contacts, dt: float, frequency: float) -> np.ndarray:
    """Each foot's delay behind the first foot (cycles, 0-1), from the contact signals' component at `frequency`."""
    contacts = np.asarray(contacts, dtype=float)
    t = np.arange(len(contacts)) * dt
    component = ((contacts - contacts.mean(axis=0)) * np.exp(-2j * np.pi * frequency * t)[:, None]).sum(axis=0)
    # A foot delayed by tau carries the first foot's angle minus 2 pi f tau.
    return ((np.angle(component[0]) - np.angle(component)) / (2 * np.pi)) % 1.0


def _apart(a: float, b: float) -> float:
    """Circular distance between two phases, in cycles (0-0.5)."""
    d = abs(a - b) % 1.0
    return min(d, 1.0 - d)


def gait_name(contacts, dt: float) -> str:
    """The gait of four feet (FL, FR, RL, RR) by Hildebrand's phase rules, named as the thesis names them.

    Symmetric gaits keep each pair's left and right feet half a cycle apart and differ in the hind feet's lag
    behind the fore: a trot moves the diagonals together, a pace the same-side feet, a walk lags a quarter.
    Asymmetric gaits land a pair close together: both pairs at once and half a cycle apart is a bound, all four
    at once a pronk, a pair's feet close but not together (the gallop's lead) a gallop.
    """
    contacts = np.asarray(contacts, dtype=float)
    frequency = gait_frequency(contacts, dt)
    if np.isnan(frequency):
        return "standing"
    if np.any(contacts.min(axis=0) == contacts.max(axis=0)):
        return "irregular"  # a foot that never lifts or never lands: no four-beat pattern to name
    fl, fr, rl, rr = leg_phases(contacts, dt, frequency)
    together = lambda a, b: _apart(a, b) < PHASE_TOLERANCE  # noqa: E731
    opposed = lambda a, b: _apart(a, b) > 0.5 - PHASE_TOLERANCE  # noqa: E731
    if opposed(fl, fr) and opposed(rl, rr):
        lag = _apart(fl, rl)
        return "pace" if lag < PHASE_TOLERANCE else "trot" if lag > 0.5 - PHASE_TOLERANCE else "walk"
    if together(fl, fr) and together(rl, rr):
        return "pronk" if together(fl, rl) else "bound"
    return "gallop"
