"""What the newer agents normalise outside their networks: observations, rewards, and the weights themselves.

Observations by their running mean and variance (SimbaV2, FastSAC); rewards by the running spread of the
discounted return (XQC; SimbaV2 also by its largest magnitude); weights projected back onto the unit sphere
after every optimiser step (XQC, SimbaV2).
"""

import jax
import jax.numpy as jnp
from flax import struct

EPSILON = 1e-8


class Moments(struct.PyTreeNode):
    """Running mean and variance of a stream of values (..., D), merged batch by batch."""

    mean: jnp.ndarray
    var: jnp.ndarray
    count: jnp.ndarray


def moments(size: int | tuple = ()) -> Moments:
    """Moments before any data: mean 0, variance 1, a tiny count so the first batch all but replaces them."""
    return Moments(mean=jnp.zeros(size), var=jnp.ones(size), count=jnp.float32(1e-4))


def merge(running: Moments, batch) -> Moments:
    """Running moments after a batch (B, ...) of values: the parallel (Chan et al.) combination."""
    batch_mean, batch_var, batch_count = batch.mean(axis=0), batch.var(axis=0), batch.shape[0]
    total = running.count + batch_count
    delta = batch_mean - running.mean
    mean = running.mean + delta * batch_count / total
    m2 = running.var * running.count + batch_var * batch_count + delta**2 * running.count * batch_count / total
    return Moments(mean=mean, var=m2 / total, count=total)


def normalise(running: Moments, x):
    """x standardised by the running moments."""
    return (x - running.mean) / jnp.sqrt(running.var + EPSILON)


class RewardScale(struct.PyTreeNode):
    """The discounted return so far, its running moments and its largest magnitude: what rewards are divided by."""

    returns: jnp.ndarray
    moments: Moments
    largest: jnp.ndarray


def reward_scale(num_envs: int = 1) -> RewardScale:
    """Nothing seen yet, for one environment's returns or `num_envs` of them."""
    returns = jnp.float32(0.0) if num_envs == 1 else jnp.zeros(num_envs)
    return RewardScale(returns=returns, moments=moments(), largest=jnp.float32(0.0))


def observe_reward(scale: RewardScale, reward, done, gamma: float) -> RewardScale:
    """After one step: G <- gamma (1 - done) G + r (done ends an episode, by fall or time; the common wrappers'
    form, which restarts G at the step that ends it), then G's moments and largest magnitude."""
    returns = gamma * (1.0 - done) * scale.returns + reward
    return RewardScale(returns=returns, moments=merge(scale.moments, jnp.reshape(returns, (-1,))),
                       largest=jnp.maximum(scale.largest, jnp.max(jnp.abs(returns))))


def reward_divisor(scale: RewardScale, rule: str, g_max: float):
    """What rewards are divided by: 'return-std' the return's standard deviation (XQC); 'return-std-gmax' that or
    the largest return over g_max, whichever is larger (SimbaV2), so that returns stay within +-g_max."""
    if rule == "return-std":
        return jnp.sqrt(scale.moments.var) + EPSILON
    if rule == "return-std-gmax":
        return jnp.maximum(jnp.sqrt(scale.moments.var + EPSILON), scale.largest / g_max)
    raise ValueError(f"unknown reward scaling {rule!r}; valid: 'none', 'return-std', 'return-std-gmax'")


def unit_kernels(params):
    """Every dense kernel projected onto the unit sphere: each output unit's incoming weights of norm 1."""

    def project(path, leaf):
        if not path or getattr(path[-1], "key", None) != "kernel" or leaf.ndim < 2:
            return leaf
        return leaf / jnp.maximum(jnp.linalg.norm(leaf, axis=-2, keepdims=True), EPSILON)

    return jax.tree_util.tree_map_with_path(project, params)
