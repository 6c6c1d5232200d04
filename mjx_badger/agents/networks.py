"""Actor and critic networks shared by every algorithm of the SAC family."""

import math
from typing import Sequence

import flax.linen as nn
import jax
import jax.numpy as jnp

LOG_STD_MIN, LOG_STD_MAX = -10.0, 2.0
CLIPPED_LOG_STD_MIN = -20.0  # RL-X's policies clip the raw output to [-20, 2]


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


class Actor(nn.Module):
    """Tanh-squashed Gaussian policy: obs (B, O) -> mean, log_std (B, A).

    With `batch_renorm` (the released CrossQ) the input and every hidden layer are batch
    renormalised, running statistics in evaluation mode (`train=False`), as when acting.
    """

    action_size: int
    hidden: Sequence[int] = (256, 256)
    batch_renorm: bool = False
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    log_std_clip: bool = False
    """Clip the raw log-std to [-20, 2] instead of squashing it (see AgentConfig.log_std_clip)."""

    @nn.compact
    def __call__(self, obs, train: bool = False):
        norm = lambda: BatchRenorm(momentum=self.renorm_momentum, warmup_steps=self.renorm_warmup_steps)
        x = norm()(obs, train) if self.batch_renorm else obs
        for width in self.hidden:
            x = nn.relu(nn.Dense(width)(x))
            if self.batch_renorm:
                x = norm()(x, train)
        mean = nn.Dense(self.action_size)(x)
        log_std = nn.Dense(self.action_size)(x)
        if self.log_std_clip:
            return mean, jnp.clip(log_std, CLIPPED_LOG_STD_MIN, LOG_STD_MAX)
        # Squash log_std smoothly into its range so the gradient never dies at a clip.
        log_std = LOG_STD_MIN + 0.5 * (LOG_STD_MAX - LOG_STD_MIN) * (jnp.tanh(log_std) + 1)
        return mean, log_std


class QNetwork(nn.Module):
    """One Q function: (obs, action) (B, O), (B, A) -> (B,)."""

    hidden: Sequence[int] = (256, 256)
    batch_renorm: bool = False
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    dropout_rate: float = 0.0
    layer_norm: bool = False

    @nn.compact
    def __call__(self, obs, action, train: bool = False):
        x = jnp.concatenate([obs, action], axis=-1)
        norm = lambda: BatchRenorm(momentum=self.renorm_momentum, warmup_steps=self.renorm_warmup_steps)
        if self.batch_renorm:
            x = norm()(x, train)
        for width in self.hidden:
            x = nn.Dense(width)(x)
            if self.dropout_rate > 0:
                x = Dropout(self.dropout_rate)(x, train)
            if self.layer_norm:
                x = nn.LayerNorm()(x)
            x = nn.relu(x)
            if self.batch_renorm:
                x = norm()(x, train)
        return nn.Dense(1)(x)[..., 0]


class Critic(nn.Module):
    """An ensemble of Q functions evaluated in one pass: -> (ensemble, B)."""

    ensemble_size: int = 2
    hidden: Sequence[int] = (256, 256)
    batch_renorm: bool = False
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    dropout_rate: float = 0.0
    layer_norm: bool = False

    @nn.compact
    def __call__(self, obs, action, train: bool = False):
        ensemble = nn.vmap(
            QNetwork,
            variable_axes={"params": 0, "batch_stats": 0},
            split_rngs={"params": True, "dropout": True},
            in_axes=None,
            out_axes=0,
            axis_size=self.ensemble_size,
        )
        return ensemble(
            hidden=self.hidden,
            batch_renorm=self.batch_renorm,
            renorm_momentum=self.renorm_momentum,
            renorm_warmup_steps=self.renorm_warmup_steps,
            dropout_rate=self.dropout_rate,
            layer_norm=self.layer_norm,
        )(obs, action, train)


def sample_action(mean, log_std, key):
    """Reparameterised tanh-Gaussian sample and its log-probability: (B, A), (B,)."""
    std = jnp.exp(log_std)
    raw = mean + std * jax.random.normal(key, mean.shape)
    action = jnp.tanh(raw)
    log_prob = -0.5 * (((raw - mean) / std) ** 2 + 2 * log_std + jnp.log(2 * jnp.pi))
    # Change of variables through tanh; the softplus form is the numerically stable log(1 - tanh^2).
    log_prob = log_prob - 2 * (jnp.log(2.0) - raw - jax.nn.softplus(-2 * raw))
    return action, log_prob.sum(axis=-1)
