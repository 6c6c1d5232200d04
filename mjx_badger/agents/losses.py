"""Critic, actor and temperature losses of the SAC family, built from one config.

A factory closes over the networks and the config and returns pure functions; which
algorithm they implement is decided only by config fields (target network or joint
batch-renormalised pass, dropout, layer norm).
"""

from typing import NamedTuple

import jax
import jax.numpy as jnp

from mjx_badger.agents import distributional
from mjx_badger.agents.config import AgentConfig
from mjx_badger.agents.networks import sample_action


class Transition(NamedTuple):
    """A batch of transitions: obs (B, O), action (B, A), reward (B,), next_obs (B, O), discount (B,)."""

    obs: jnp.ndarray
    action: jnp.ndarray
    reward: jnp.ndarray
    next_obs: jnp.ndarray
    discount: jnp.ndarray


class Losses(NamedTuple):
    critic: callable
    actor: callable
    alpha: callable
    expected: callable
    """Q from the critic's output, whatever its kind."""


def actor_variables(params, stats):
    """flax variables of the actor (params holds {'params': ...}), plus batch statistics when it has any."""
    return dict(params, batch_stats=stats) if stats else params


def critic_variables(params, stats):
    """flax variables of the critic: params plus batch statistics when it has any."""
    return {"params": params, "batch_stats": stats} if stats else {"params": params}


def make_losses(actor, critic, cfg: AgentConfig, action_size: int) -> Losses:
    """Loss functions for the algorithm described by `cfg`."""
    target_entropy = (cfg.target_entropy if cfg.target_entropy is not None
                      else cfg.target_entropy_per_action * action_size)
    atoms = distributional.support(cfg.atoms, *cfg.value_range)

    def policy(actor_params, actor_stats, obs, key):
        """A policy sample for the critic's target: the actor's batch statistics in evaluation mode."""
        mean, log_std = actor.apply(actor_variables(actor_params, actor_stats), obs)
        return sample_action(mean, log_std, key)

    def critic_loss(critic_params, critic_stats, target_params, actor_params, actor_stats, log_alpha,
                    batch: Transition, key):
        """Soft Bellman residual; returns (loss, (new batch stats, metrics, log pi(a'|s') of the target's actions))."""
        policy_key, dropout_key = jax.random.split(key)
        target_key = jax.random.fold_in(dropout_key, 1)
        next_action, next_log_prob = policy(actor_params, actor_stats, batch.next_obs, policy_key)
        variables = critic_variables(critic_params, critic_stats)
        rngs = {"dropout": dropout_key}
        joint_obs = jnp.concatenate([batch.obs, batch.next_obs])
        joint_action = jnp.concatenate([batch.action, next_action])
        if cfg.target_network and cfg.joint_pass:
            # XQC: both critics see [s; s'] in training mode, so the target is normalised with the batch's
            # statistics like the prediction; the target critic's statistics are left as they are.
            joint_q, updated = critic.apply(variables, joint_obs, joint_action, train=True, mutable=["batch_stats"])
            q = jnp.split(joint_q, 2, axis=1)[0]
            next_q = jnp.split(critic.apply(critic_variables(target_params, critic_stats), joint_obs, joint_action,
                                            train=True, mutable=["batch_stats"])[0], 2, axis=1)[1]
        elif cfg.target_network:
            q, updated = critic.apply(variables, batch.obs, batch.action, train=True, rngs=rngs, mutable=["batch_stats"])
            # DroQ keeps dropout on in the target critic too (its regulariser acts on the target).
            next_q = critic.apply({"params": target_params}, batch.next_obs, next_action, train=cfg.dropout_rate > 0,
                                  rngs={"dropout": target_key})
        else:
            # CrossQ: current and next state-actions go through the critic in one batch, so
            # batch renormalisation sees both distributions and the bootstrap target is
            # normalised with the same statistics as the prediction; this is what lets it
            # drop the target network.
            joint_q, updated = critic.apply(variables, joint_obs, joint_action, train=True, rngs=rngs,
                                            mutable=["batch_stats"])
            q, next_q = jnp.split(joint_q, 2, axis=1)
        shift = jax.lax.stop_gradient(jnp.exp(log_alpha) * next_log_prob)
        loss = bellman_loss(q, jax.tree.map(jax.lax.stop_gradient, next_q), batch, shift)
        metrics = {"critic_loss": loss, "q_mean": jnp.mean(expected(q))}
        return loss, (updated.get("batch_stats", {}), metrics, jax.lax.stop_gradient(next_log_prob))

    def bellman_loss(q, next_q, batch, shift):
        """The critics' loss against r + gamma d (next value - alpha log pi), by the critic's kind of output."""
        discount = cfg.gamma * batch.discount
        if cfg.critic_output == "categorical":
            probs = jax.nn.softmax(next_q, axis=-1)  # (E, B, N)
            if cfg.ensemble_rule == "min":  # every member learns the lower member's distribution, sample by sample
                lower = jnp.argmin(distributional.categorical_mean(next_q, atoms), axis=0)
                probs = jnp.broadcast_to(jnp.take_along_axis(probs, lower[None, :, None], axis=0), probs.shape)
            elif cfg.ensemble_rule == "mean":
                probs = jnp.broadcast_to(jnp.mean(probs, axis=0), probs.shape)
            target = jax.vmap(lambda p: distributional.project(p, batch.reward, discount, atoms, shift))(probs)
            return jnp.sum(jnp.mean(jax.vmap(distributional.cross_entropy)(target, q), axis=1))
        if cfg.critic_output == "quantile":
            next_value = combine(next_q, own=False)  # (B, N): BRO's bound with pessimism 0 is the mean
            target = batch.reward[:, None] + discount[:, None] * (next_value - shift[:, None])
            return jnp.sum(jax.vmap(lambda member: distributional.quantile_huber(member, target))(q))
        target = batch.reward + discount * (combine(next_q, own=cfg.ensemble_rule == "own") - shift)
        return 0.5 * jnp.sum(jnp.mean((q - target) ** 2, axis=-1))

    def combine(values, own: bool):
        """The ensemble's values combined by the rule: its minimum or mean (or each member's own)."""
        if own:
            return values
        return jnp.min(values, axis=0) if cfg.ensemble_rule == "min" else jnp.mean(values, axis=0)

    def expected(out):
        """Q from the critic's output: the value, the categorical mean, or the quantiles' mean."""
        if cfg.critic_output == "categorical":
            return distributional.categorical_mean(out, atoms)
        return jnp.mean(out, axis=-1) if cfg.critic_output == "quantile" else out

    def actor_loss(actor_params, actor_stats, critic_params, critic_stats, log_alpha, obs, key):
        """alpha log pi - min Q; returns (loss, (log_prob, new actor batch stats)).

        The critic runs in evaluation mode (running batch statistics) except that a dropout
        critic keeps its dropout, as DroQ trains its actor against the regularised Q. A batch-
        renormalised actor runs in training mode here, as the released CrossQ does.
        """
        mean, log_std, new_stats = apply_actor_train(actor_params, actor_stats, obs)
        action, log_prob = sample_action(mean, log_std, key)
        q = expected(critic.apply(critic_variables(critic_params, critic_stats), obs, action,
                                  train=cfg.dropout_rate > 0, rngs={"dropout": jax.random.fold_in(key, 1)}))
        # The actor climbs the lower critic ('min'), or their mean ('mean', 'own': BRO, FastSAC).
        loss = jnp.mean(jnp.exp(log_alpha) * log_prob - combine(q, own=False))
        return loss, (log_prob, new_stats)

    def apply_actor_train(actor_params, actor_stats, obs):
        if not actor_stats:
            return (*actor.apply(actor_params, obs), actor_stats)
        (mean, log_std), updated = actor.apply(actor_variables(actor_params, actor_stats), obs, train=True,
                                               mutable=["batch_stats"])
        return mean, log_std, updated["batch_stats"]

    def alpha_loss(log_alpha, log_prob):
        """Temperature objective J(alpha) of §2.3 on log alpha, or RL-X's alpha (H - target) (cfg.alpha_loss_scaled)."""
        weight = jnp.exp(log_alpha) if cfg.alpha_loss_scaled else log_alpha
        return -jnp.mean(weight * jax.lax.stop_gradient(log_prob + target_entropy))

    return Losses(critic=critic_loss, actor=actor_loss, alpha=alpha_loss, expected=expected)
