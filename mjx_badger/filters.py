"""Action filters of thesis §2.5 / Table 4.4 as pure init/step pairs.

Each filter is `init(x0) -> state` and `step(state, x) -> (state, y)` over arrays of any
shape. The smoothing factor is Casiez et al.'s alpha = 1 / (1 + tau / dt) with
tau = 1 / (2 pi f_c); the thesis print of alpha is garbled (DESIGN.md).
"""

from typing import Callable, NamedTuple

import jax.numpy as jnp


class Filter(NamedTuple):
    """A named pure filter."""

    init: Callable
    step: Callable


class LowPassState(NamedTuple):
    y: jnp.ndarray


class OneEuroState(NamedTuple):
    x: jnp.ndarray
    y: jnp.ndarray
    dx: jnp.ndarray


def smoothing_factor(cutoff_hz, dt):
    """Exponential-smoothing factor of a first-order low-pass filter at `cutoff_hz`."""
    tau = 1.0 / (2.0 * jnp.pi * cutoff_hz)
    return 1.0 / (1.0 + tau / dt)


def no_filter(dt: float) -> Filter:
    """Identity: the joint target is the action itself (JT-NF); `dt` is unused."""
    return Filter(init=lambda x0: (), step=lambda state, x: (state, x))


def low_pass(dt: float, cutoff_hz: float = 0.4) -> Filter:
    """First-order low-pass filter with a fixed cutoff (JT-LPF, Table 4.4)."""
    alpha = smoothing_factor(cutoff_hz, dt)

    def step(state, x):
        y = alpha * x + (1 - alpha) * state.y
        return LowPassState(y), y

    return Filter(init=lambda x0: LowPassState(jnp.asarray(x0)), step=step)


def one_euro(dt: float, min_cutoff: float = 2.5, beta: float = 0.1, d_cutoff: float = 100.0) -> Filter:
    """One Euro filter (Casiez et al. 2012; thesis Algorithm 2, Table 4.4)."""
    alpha_d = smoothing_factor(d_cutoff, dt)

    def step(state, x):
        dx = alpha_d * (x - state.x) / dt + (1 - alpha_d) * state.dx
        alpha = smoothing_factor(min_cutoff + beta * jnp.abs(dx), dt)
        y = alpha * x + (1 - alpha) * state.y
        return OneEuroState(x=x, y=y, dx=dx), y

    def init(x0):
        x0 = jnp.asarray(x0)
        return OneEuroState(x=x0, y=x0, dx=jnp.zeros_like(x0))

    return Filter(init=init, step=step)


FILTERS = {"none": no_filter, "lowpass": low_pass, "one_euro": one_euro}


def make_filter(name: str, dt: float) -> Filter:
    """The filter called `name` with the thesis's parameters at control period `dt`."""
    return FILTERS[name](dt)
