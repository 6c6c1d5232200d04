"""BRO's optimistic exploration: a second policy that acts, shifted towards where the critics disagree.

The main (pessimistic) actor is trained on the critics' lower bound and is what evaluation runs. The optimistic
actor shifts its mean by a learned amount and narrows its spread (x 0.75), is trained on the critics' upper
bound, mean + beta |q1 - q2| / 2, held near the main actor by a KL penalty; beta and the KL weight adjust
themselves so that the KL per action dimension stays near its target.
"""

from typing import Any, Sequence

import flax.linen as nn
import jax
import jax.numpy as jnp
from flax import struct

from mjx_badger.agents.trunks import BroTrunk, orthogonal

STD_MULTIPLIER = 0.75
KL_TARGET = 0.05
LOG_RANGE = (-10.0, 7.5)
"""Bounds of log beta and log KL-weight, both squashed into this range."""
BETA_INIT, KL_WEIGHT_INIT, ADJUSTMENT_LR = 1.0, 0.25, 3e-5


class Shift(nn.Module):
    """The optimistic actor's shift of the main actor's mean, from (obs, that mean); starts near zero."""

    action_size: int
    hidden: Sequence[int]

    @nn.compact
    def __call__(self, obs, mean):
        x = BroTrunk(widths=tuple(self.hidden))(jnp.concatenate([obs, mean], axis=-1), train=False)
        return nn.Dense(self.action_size, use_bias=False, kernel_init=orthogonal(0.01))(x)


class Optimism(struct.PyTreeNode):
    """The optimistic actor's parameters and optimiser state, and the raw beta and KL weight with theirs."""

    params: Any
    opt: Any
    beta: jnp.ndarray
    kl_weight: jnp.ndarray
    adjust_opt: Any


def squashed(raw):
    """A positive adjustment from its raw parameter: exp of raw squashed into LOG_RANGE."""
    low, high = LOG_RANGE
    return jnp.exp(low + 0.5 * (high - low) * (1 + jnp.tanh(raw)))


def raw_of(value: float):
    """The raw parameter whose `squashed` value is `value`."""
    low, high = LOG_RANGE
    return jnp.arctanh((jnp.log(value) - low) / (0.5 * (high - low)) - 1)


def bound(q, beta):
    """The ensemble's mean plus beta times half its spread, per quantile: q (2, B, ...) -> (B, ...)."""
    return jnp.mean(q, axis=0) + beta * jnp.abs(q[0] - q[1]) / 2


def shift_kl(optimistic_mean, mean, std):
    """KL between the optimistic and main Gaussians before the narrowing (same spread), summed over actions."""
    return jnp.sum((optimistic_mean - mean) ** 2 / (2 * std**2), axis=-1)


def adjustment_losses(beta_raw, kl_weight_raw, kl_per_dim, pessimism: float = 0.0):
    """beta shrinks and the KL weight grows while the KL per action dimension is above KL_TARGET."""
    excess = jax.lax.stop_gradient(kl_per_dim - KL_TARGET)
    return (squashed(beta_raw) - pessimism) * excess, -squashed(kl_weight_raw) * excess
