"""Action filters of thesis §2.5 / Table 4.4 as pure init/step pairs.

Each filter is `init(x0) -> state` and `step(state, x) -> (state, y)` over arrays of any
shape. The first-order smoothing factor is Casiez et al.'s alpha = 1 / (1 + tau / dt) with
tau = 1 / (2 pi f_c); the thesis print of alpha is garbled, as docs/readings.md (Filters) says.
"""

import math
from typing import Callable, NamedTuple

import jax.numpy as jnp


class Filter(NamedTuple):
    """A named pure filter."""

    init: Callable
    step: Callable


class LowPassState(NamedTuple):
    y: jnp.ndarray


class BiquadState(NamedTuple):
    z: jnp.ndarray  # (2, ...) transposed direct-form-II delay line


class OneEuroState(NamedTuple):
    x: jnp.ndarray
    y: jnp.ndarray
    dx: jnp.ndarray
    started: jnp.ndarray  # () bool: whether a first sample has been seen


def smoothing_factor(cutoff_hz, dt):
    """Exponential-smoothing factor of a first-order low-pass filter at `cutoff_hz`."""
    tau = 1.0 / (2.0 * jnp.pi * cutoff_hz)
    return 1.0 / (1.0 + tau / dt)


def no_filter(dt: float) -> Filter:
    """Identity: the joint target is the action itself (JT-NF); `dt` is unused."""
    return Filter(init=lambda x0: (), step=lambda state, x: (state, x))


def low_pass(dt: float, cutoff_hz: float = 0.4) -> Filter:
    """First-order low-pass filter with a fixed cutoff (JT-LPF as the thesis text reads, Table 4.4)."""
    alpha = smoothing_factor(cutoff_hz, dt)

    def step(state, x):
        y = alpha * x + (1 - alpha) * state.y
        return LowPassState(y), y

    return Filter(init=lambda x0: LowPassState(jnp.asarray(x0)), step=step)


def butterworth_coefficients(cutoff_hz: float, sample_hz: float):
    """(b, a) of a second-order Butterworth low-pass by the bilinear transform, as scipy.signal.butter(2, ...)."""
    k = math.tan(math.pi * cutoff_hz / sample_hz)
    norm = 1.0 / (1.0 + math.sqrt(2.0) * k + k * k)
    b0 = k * k * norm
    return (b0, 2 * b0, b0), (1.0, 2.0 * (k * k - 1.0) * norm, (1.0 - math.sqrt(2.0) * k + k * k) * norm)


def butterworth(dt: float, cutoff_hz: float = 4.0, design_hz: float | None = 40.0) -> Filter:
    """Second-order Butterworth low-pass (the released code's JT-LPF: 4 Hz designed for a 40 Hz rate).

    `design_hz` is the sample rate the coefficients were designed for (None: 1 / dt); the
    released code designs at 40 Hz and runs JT at 50 Hz, so its cutoff is really 5 Hz there.
    `init(x0)` starts at rest at x0, as a zero-state filter of the offsets from x0 does.
    """
    (b0, b1, b2), (_, a1, a2) = butterworth_coefficients(cutoff_hz, design_hz or 1.0 / dt)

    def init(x0):
        x0 = jnp.asarray(x0)
        # Steady state of the transposed direct form at a constant input x0 (DC gain 1).
        return BiquadState(jnp.stack([(b1 + b2 - a1 - a2) * x0, (b2 - a2) * x0]))

    def step(state, x):
        y = b0 * x + state.z[0]
        z0 = b1 * x - a1 * y + state.z[1]
        z1 = b2 * x - a2 * y
        return BiquadState(jnp.stack([z0, z1])), y

    return Filter(init=init, step=step)


def one_euro(dt: float, min_cutoff: float = 2.5, beta: float = 0.1, d_cutoff: float = 100.0,
             start_at_first_input: bool = False) -> Filter:
    """One Euro filter (Casiez et al. 2012; thesis Algorithm 2, Table 4.4).

    `init(x0)` starts at rest at x0; with `start_at_first_input` the first output is the first
    input itself (the OneEuroFilter package the released code uses, and Algorithm 2's y(0) = x(0)).
    """
    alpha_d = smoothing_factor(d_cutoff, dt)

    def step(state, x):
        dx = alpha_d * (x - state.x) / dt + (1 - alpha_d) * state.dx
        alpha = smoothing_factor(min_cutoff + beta * jnp.abs(dx), dt)
        y = alpha * x + (1 - alpha) * state.y
        if start_at_first_input:
            y = jnp.where(state.started, y, x)
            dx = jnp.where(state.started, dx, jnp.zeros_like(dx))
        return OneEuroState(x=x, y=y, dx=dx, started=jnp.bool_(True)), y

    def init(x0):
        x0 = jnp.asarray(x0)
        return OneEuroState(x=x0, y=x0, dx=jnp.zeros_like(x0), started=jnp.bool_(False))

    return Filter(init=init, step=step)


FILTERS = {"none": no_filter, "lowpass": low_pass, "butterworth": butterworth, "one_euro": one_euro}


def make_filter(name: str, dt: float, **params) -> Filter:
    """The filter called `name` at control period `dt`, with its parameters (defaults: the thesis's)."""
    return FILTERS[name](dt, **params)
