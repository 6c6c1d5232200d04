"""Actor and critic networks shared by every algorithm of the SAC family."""

from typing import Sequence

import flax.linen as nn
import jax
import jax.numpy as jnp

from mjx_badger.agents.layers import BatchRenorm, Dropout
from mjx_badger.agents.trunks import head, make_trunk

LOG_STD_MIN, LOG_STD_MAX = -10.0, 2.0
CLIPPED_LOG_STD_MIN = -20.0  # RL-X's policies clip the raw output to [-20, 2]


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
    trunk: str = "mlp"
    """The body (agents.trunks.TRUNKS); 'mlp' is the one below, with its optional batch renormalisation."""
    log_std_range: tuple | None = None
    """Bounds of the log-std for either form; None: [-10, 2] squashed, [-20, 2] clipped."""

    @nn.compact
    def __call__(self, obs, train: bool = False):
        if self.trunk != "mlp":
            x = make_trunk(self.trunk, self.hidden)(obs, train)
            return self.bounded(head(self.trunk, self.action_size, policy=True)(x),
                                head(self.trunk, self.action_size, 1.0, policy=True)(x))
        norm = lambda: BatchRenorm(momentum=self.renorm_momentum, warmup_steps=self.renorm_warmup_steps)
        x = norm()(obs, train) if self.batch_renorm else obs
        for width in self.hidden:
            x = nn.relu(nn.Dense(width)(x))
            if self.batch_renorm:
                x = norm()(x, train)
        return self.bounded(nn.Dense(self.action_size)(x), nn.Dense(self.action_size)(x))

    def bounded(self, mean, log_std):
        """The mean and the log-std clipped or squashed into its range."""
        if self.log_std_clip:
            low, high = self.log_std_range or (CLIPPED_LOG_STD_MIN, LOG_STD_MAX)
            return mean, jnp.clip(log_std, low, high)
        low, high = self.log_std_range or (LOG_STD_MIN, LOG_STD_MAX)
        # Squash log_std smoothly into its range so the gradient never dies at a clip.
        return mean, low + 0.5 * (high - low) * (jnp.tanh(log_std) + 1)


class QNetwork(nn.Module):
    """One Q function: (obs, action) (B, O), (B, A) -> (B,), or (B, outputs) for a distributional critic."""

    hidden: Sequence[int] = (256, 256)
    batch_renorm: bool = False
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    dropout_rate: float = 0.0
    layer_norm: bool = False
    trunk: str = "mlp"
    outputs: int = 1
    """1 for a Q value; the atoms or quantiles of a distributional critic."""

    @nn.compact
    def __call__(self, obs, action, train: bool = False):
        x = jnp.concatenate([obs, action], axis=-1)
        if self.trunk != "mlp":
            out = head(self.trunk, self.outputs)(make_trunk(self.trunk, self.hidden)(x, train))
            return out[..., 0] if self.outputs == 1 else out
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
        out = nn.Dense(self.outputs)(x)
        return out[..., 0] if self.outputs == 1 else out


class Critic(nn.Module):
    """An ensemble of Q functions evaluated in one pass: -> (ensemble, B) or (ensemble, B, outputs)."""

    ensemble_size: int = 2
    hidden: Sequence[int] = (256, 256)
    batch_renorm: bool = False
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    dropout_rate: float = 0.0
    layer_norm: bool = False
    trunk: str = "mlp"
    outputs: int = 1

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
            trunk=self.trunk,
            outputs=self.outputs,
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
