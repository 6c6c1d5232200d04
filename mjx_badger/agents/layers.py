"""Layers of the thesis's agents' networks: batch renormalisation (CrossQ) and a cheap dropout (DroQ)."""

import math

import flax.linen as nn
import jax
import jax.numpy as jnp


class BatchRenorm(nn.Module):
    """Batch renormalisation (Ioffe 2017), as CrossQ uses it in the critic.

    In training mode the batch is normalised with its own statistics, corrected towards
    the running ones by r and d (both without gradient); before `warmup_steps` updates
    it is plain batch normalisation (r = 1, d = 0). In evaluation mode the running
    statistics are used.
    """

    momentum: float = 0.99
    epsilon: float = 1e-3
    r_max: float = 3.0
    d_max: float = 5.0
    warmup_steps: int = 100_000

    @nn.compact
    def __call__(self, x, train: bool):
        features = x.shape[-1]
        mean = self.variable("batch_stats", "mean", jnp.zeros, (features,))
        var = self.variable("batch_stats", "var", jnp.ones, (features,))
        steps = self.variable("batch_stats", "steps", jnp.zeros, (), jnp.int32)
        scale = self.param("scale", nn.initializers.ones, (features,))
        bias = self.param("bias", nn.initializers.zeros, (features,))
        if train:
            batch_mean = x.mean(axis=0)
            batch_var = x.var(axis=0)
            batch_std = jnp.sqrt(batch_var + self.epsilon)
            running_std = jnp.sqrt(var.value + self.epsilon)
            r = jax.lax.stop_gradient(jnp.clip(batch_std / running_std, 1 / self.r_max, self.r_max))
            d = jax.lax.stop_gradient(jnp.clip((batch_mean - mean.value) / running_std, -self.d_max, self.d_max))
            warm = steps.value < self.warmup_steps
            r = jnp.where(warm, 1.0, r)
            d = jnp.where(warm, 0.0, d)
            y = (x - batch_mean) / batch_std * r + d
            if not self.is_initializing():
                mean.value = self.momentum * mean.value + (1 - self.momentum) * batch_mean
                var.value = self.momentum * var.value + (1 - self.momentum) * batch_var
                steps.value = steps.value + 1
        else:
            y = (x - mean.value) / jnp.sqrt(var.value + self.epsilon)
        return y * scale + bias


def hashed_keep_mask(key, shape, rate: float):
    """Bernoulli(1 - rate) mask from one random word and a counter hash (murmur3 finaliser).

    A threefry draw per element costs about 11 ns on a CPU, which made it most of a DroQ
    update; hashing (index xor seed) is ten times cheaper and random enough for dropout.
    """
    seed = jax.random.bits(key, dtype=jnp.uint32)
    h = jax.lax.iota(jnp.uint32, math.prod(shape)).reshape(shape) ^ seed
    h = h * jnp.uint32(0x9E3779B1)
    h = (h ^ (h >> 16)) * jnp.uint32(0x85EBCA6B)
    h = (h ^ (h >> 13)) * jnp.uint32(0xC2B2AE35)
    h = h ^ (h >> 16)
    return h >= jnp.uint32(int(rate * 2**32))


class Dropout(nn.Module):
    """Inverted dropout with a hashed mask; the identity when not training."""

    rate: float

    @nn.compact
    def __call__(self, x, train: bool):
        if not train or self.rate == 0:
            return x
        keep = hashed_keep_mask(self.make_rng("dropout"), x.shape, self.rate)
        return jnp.where(keep, x / (1.0 - self.rate), 0.0)
