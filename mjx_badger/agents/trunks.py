"""The newer agents' network bodies, each named after the agent that brought it; `make_trunk` picks one.

'xqc': batch norm on the input, then dense (no bias) -> batch norm -> ReLU blocks (XQC).
'bro': dense -> layer norm -> ReLU, then residual blocks of two such layers (BroNet, BRO).
'simba': the observation shifted and put on the unit sphere, then blocks that step towards an MLP's output
along the sphere (SimbaV2's hyperspherical network, with learned scalers).
'layernorm': dense -> layer norm -> SiLU with narrowing widths (FastSAC).
"""

import math
from typing import Sequence

import flax.linen as nn
import jax
import jax.numpy as jnp

from mjx_badger.agents.layers import BatchRenorm
from mjx_badger.agents.normalisers import EPSILON

TRUNKS = ("mlp", "xqc", "bro", "simba", "layernorm")
"""'mlp' is the thesis's agents' body, kept in networks.py with its dropout, layer norm and batch renorm."""

SIMBA_SHIFT = 3.0
"""The constant SimbaV2 appends to every input before projecting it onto the sphere (c_shift)."""


def orthogonal(scale: float = math.sqrt(2)):
    """Orthogonal initialisation (rows or columns orthonormal, times `scale`), by Gram-Schmidt in plain array
    operations: jaxlib's batched LAPACK QR, which flax's initialiser calls once per ensemble member, deadlocked
    XLA's two-thread CPU pool here (the QR waits for batch tasks queued behind itself)."""

    def init(key, shape, dtype=jnp.float32):
        rows, cols = math.prod(shape[:-1]), shape[-1]
        tall = (max(rows, cols), min(rows, cols))
        q = gram_schmidt(jax.random.normal(key, tall, jnp.float32))
        return (scale * (q if rows >= cols else q.T)).reshape(shape).astype(dtype)

    return init


def gram_schmidt(matrix):
    """Orthonormal columns spanning a tall matrix's, column by column (twice each: 'twice is enough' in float32);
    the Q of its QR with a positive diagonal R, so a Gaussian matrix gives a uniformly random orthogonal one."""

    def column(q, j):
        v = matrix[:, j]
        for _ in range(2):
            v = v - q @ (q.T @ v)
        return q.at[:, j].set(v / jnp.linalg.norm(v)), None

    return jax.lax.scan(column, jnp.zeros_like(matrix), jnp.arange(matrix.shape[1]))[0]


def unit(x):
    """x put on the unit sphere along its last axis (zero stays zero)."""
    return x / jnp.maximum(jnp.linalg.norm(x, axis=-1, keepdims=True), EPSILON)


class Scaler(nn.Module):
    """A learned per-feature gain that starts at `start`; stored as `size` and multiplied by start / size, so its
    step size is that of a parameter of that size (SimbaV2's scaler, init and scale)."""

    start: float
    size: float

    @nn.compact
    def __call__(self, x):
        gain = self.param("gain", nn.initializers.constant(self.size), (x.shape[-1],))
        return gain * (self.start / self.size) * x


class XQCTrunk(nn.Module):
    widths: Sequence[int]

    @nn.compact
    def __call__(self, x, train: bool):
        # Plain batch normalisation: batch renormalisation that never leaves its warm-up (r = 1, d = 0).
        norm = lambda: BatchRenorm(momentum=0.99, warmup_steps=2**31 - 1)
        x = norm()(x, train)
        for width in self.widths:
            x = nn.relu(norm()(nn.Dense(width, use_bias=False, kernel_init=orthogonal())(x), train))
        return x


class BroTrunk(nn.Module):
    widths: Sequence[int]
    """The width of the input layer, then one entry per residual block (all equal)."""

    @nn.compact
    def __call__(self, x, train: bool):
        dense = lambda: nn.Dense(self.widths[0], kernel_init=orthogonal())
        x = nn.relu(nn.LayerNorm()(dense()(x)))
        for _ in self.widths[1:]:
            residual = nn.relu(nn.LayerNorm()(dense()(x)))
            x = x + nn.LayerNorm()(dense()(residual))
        return x


class HyperTrunk(nn.Module):
    widths: Sequence[int]
    """The embedding's width, then one entry per block (all equal)."""

    @nn.compact
    def __call__(self, x, train: bool):
        width, blocks = self.widths[0], len(self.widths) - 1
        hyper = lambda size: nn.Dense(size, use_bias=False, kernel_init=orthogonal(1.0))
        gain = math.sqrt(2.0 / width)
        shifted = jnp.concatenate([x, jnp.full(x.shape[:-1] + (1,), SIMBA_SHIFT)], axis=-1)
        h = unit(Scaler(gain, gain)(hyper(width)(unit(shifted))))
        for _ in range(blocks):
            inner = Scaler(gain / 2, gain / 2)(hyper(4 * width)(h))
            mlp = unit(hyper(width)(nn.relu(inner) + EPSILON))
            h = unit(h + Scaler(1.0 / (blocks + 1), 1.0 / math.sqrt(width))(mlp - h))
        return h


class HyperHead(nn.Module):
    """SimbaV2's output: a hyperspherical dense layer, a scaler, then a dense layer with a bias."""

    size: int

    @nn.compact
    def __call__(self, h):
        width = h.shape[-1]
        gain = math.sqrt(2.0 / width)
        x = Scaler(gain, gain)(nn.Dense(width, use_bias=False, kernel_init=orthogonal(1.0))(h))
        return nn.Dense(self.size, kernel_init=orthogonal(1.0))(x)


class LayerNormTrunk(nn.Module):
    widths: Sequence[int]

    @nn.compact
    def __call__(self, x, train: bool):
        for width in self.widths:
            x = nn.silu(nn.LayerNorm()(nn.Dense(width)(x)))
        return x


def make_trunk(kind: str, widths: Sequence[int]) -> nn.Module:
    """The body `kind` of TRUNKS other than 'mlp', with these widths."""
    bodies = {"xqc": XQCTrunk, "bro": BroTrunk, "simba": HyperTrunk, "layernorm": LayerNormTrunk}
    if kind not in bodies:
        raise ValueError(f"unknown network body {kind!r}; valid: {', '.join(TRUNKS)}")
    return bodies[kind](widths=tuple(widths))


def head(kind: str, size: int, scale: float = math.sqrt(2), policy: bool = False) -> nn.Module:
    """The output layer of a body: SimbaV2's hyperspherical head; FastSAC's policy heads start at zero, its critic's
    as flax's dense layers do; else orthogonal, as XQC and BRO initialise theirs."""
    if kind == "simba":
        return HyperHead(size)
    if kind == "layernorm":
        return nn.Dense(size, kernel_init=nn.initializers.zeros) if policy else nn.Dense(size)
    return nn.Dense(size, kernel_init=orthogonal(scale))
