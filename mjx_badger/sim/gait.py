"""Gait measures from foot contacts: the gait frequency of a run, on either engine or from a results file."""

import numpy as np


def gait_frequency(contacts, dt: float, low_hz: float = 0.5, high_hz: float = 12.0) -> float:
    """Gait frequency (Hz): the strongest frequency of the feet's contact signals, summed over feet.

    A spectral peak rather than a touchdown count, so a foot that brushes the floor twice in
    one cycle does not double the figure (Hann window, zero-padded to 0.01 Hz bins).
    """
    contacts = np.asarray(contacts, dtype=float)
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
