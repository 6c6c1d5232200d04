"""Distributional critics: the categorical (C51) target and loss, and quantile regression with the Huber loss.

XQC, SimbaV2 and FastSAC learn a categorical distribution over a fixed support and take Q as its mean;
BRO learns quantiles and takes Q as their mean. These are the pure pieces their losses share.
"""

import jax
import jax.numpy as jnp


def support(atoms: int, v_min: float, v_max: float) -> jnp.ndarray:
    """The categorical critic's atoms: `atoms` evenly spaced values from v_min to v_max."""
    return jnp.linspace(v_min, v_max, atoms)


def categorical_mean(logits, atoms):
    """Q of categorical logits (..., atoms): the mean of softmax(logits) over the support."""
    return jnp.sum(jax.nn.softmax(logits, axis=-1) * atoms, axis=-1)


def project(probs, reward, discount, atoms, shift=0.0):
    """The target distribution on the support: each atom z_j moved to r + discount (z_j - shift), clipped to the
    support, its mass split between the two neighbouring atoms in proportion to closeness (the C51 projection).

    probs (B, N) is the next state's distribution, reward and discount (B,), shift (B,) SAC's alpha log pi(a'|s').
    """
    v_min, v_max = atoms[0], atoms[-1]
    delta = (v_max - v_min) / (atoms.shape[0] - 1)
    moved = reward[:, None] + discount[:, None] * (atoms[None, :] - jnp.asarray(shift)[..., None])
    position = (jnp.clip(moved, v_min, v_max) - v_min) / delta
    # A tent around each atom: atom i receives 1 - |position - i| of the mass where that is positive, which is
    # the two-bin split, and all of it when the position is exactly on atom i.
    weight = jnp.clip(1.0 - jnp.abs(position[:, :, None] - jnp.arange(atoms.shape[0])[None, None, :]), 0.0, 1.0)
    return jnp.einsum("bj,bji->bi", probs, weight)


def cross_entropy(target, logits):
    """Per-sample cross-entropy -sum target log softmax(logits): (B, N), (B, N) -> (B,)."""
    return -jnp.sum(target * jax.nn.log_softmax(logits, axis=-1), axis=-1)


def quantile_levels(count: int) -> jnp.ndarray:
    """The quantile levels a quantile critic learns: the midpoints (2i + 1) / 2N."""
    return (2 * jnp.arange(count) + 1) / (2.0 * count)


def quantile_huber(predicted, target, kappa: float = 1.0):
    """Quantile regression loss (QR-DQN, BRO): predicted (B, N) quantiles at `quantile_levels(N)`, target (B, M)
    samples; each pair's Huber loss weighted by |tau - 1{target < predicted}|, summed over the predicted
    quantiles and averaged over the target samples and the batch."""
    taus = quantile_levels(predicted.shape[-1])
    error = target[:, None, :] - predicted[:, :, None]  # (B, N, M)
    absolute = jnp.abs(error)
    huber = jnp.where(absolute <= kappa, 0.5 * error**2, kappa * (absolute - 0.5 * kappa))
    weight = jnp.abs(taus[None, :, None] - jax.lax.stop_gradient((error < 0).astype(error.dtype)))
    return jnp.mean(jnp.sum(weight * huber / kappa, axis=1))
