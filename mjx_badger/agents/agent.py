"""Pure init / act / update of an agent of the SAC family."""

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
import optax
from flax import struct

from mjx_badger.agents.config import AgentConfig
from mjx_badger.agents.losses import Transition, actor_variables, make_losses
from mjx_badger.agents.networks import Actor, Critic, sample_action


class AgentState(struct.PyTreeNode):
    """Parameters, optimiser states and update count of one agent."""

    actor_params: Any
    actor_stats: Any
    critic_params: Any
    critic_stats: Any
    target_params: Any
    log_alpha: jnp.ndarray
    actor_opt: Any
    critic_opt: Any
    alpha_opt: Any
    updates: jnp.ndarray


class Agent(NamedTuple):
    """`init(key)`, `act(state, obs, key, deterministic)`, `update(state, batch, key, update_index)`."""

    config: AgentConfig
    init: Callable
    act: Callable
    update: Callable


def make_agent(cfg: AgentConfig, obs_size: int, action_size: int) -> Agent:
    """Build the pure functions of the agent `cfg` for the given observation and action sizes."""
    actor = Actor(action_size=action_size, hidden=cfg.hidden, batch_renorm=cfg.actor_batch_renorm,
                  renorm_momentum=cfg.renorm_momentum, renorm_warmup_steps=cfg.renorm_warmup_steps,
                  log_std_clip=cfg.log_std_clip)
    critic = Critic(
        ensemble_size=cfg.ensemble_size,
        hidden=cfg.hidden,
        batch_renorm=cfg.batch_renorm,
        renorm_momentum=cfg.renorm_momentum,
        renorm_warmup_steps=cfg.renorm_warmup_steps,
        dropout_rate=cfg.dropout_rate,
        layer_norm=cfg.layer_norm,
    )
    losses = make_losses(actor, critic, cfg, action_size)
    optimizer = optax.adam(cfg.learning_rate, b1=cfg.adam_b1)
    alpha_optimizer = optax.adam(cfg.learning_rate, b1=cfg.adam_b1 if cfg.alpha_adam_b1 is None else cfg.alpha_adam_b1)

    def init(key) -> AgentState:
        actor_key, critic_key = jax.random.split(key)
        obs = jnp.zeros((1, obs_size))
        action = jnp.zeros((1, action_size))
        actor_vars = actor.init(actor_key, obs)
        actor_params = {"params": actor_vars["params"]}  # the stats ride in their own field
        critic_vars = critic.init(critic_key, obs, action)
        critic_params = critic_vars["params"]
        log_alpha = jnp.log(jnp.float32(cfg.initial_alpha))
        return AgentState(
            actor_params=actor_params,
            actor_stats=actor_vars.get("batch_stats", {}),
            critic_params=critic_params,
            critic_stats=critic_vars.get("batch_stats", {}),
            target_params=critic_params if cfg.target_network else None,
            log_alpha=log_alpha,
            actor_opt=optimizer.init(actor_params),
            critic_opt=optimizer.init(critic_params),
            alpha_opt=alpha_optimizer.init(log_alpha),
            updates=jnp.int32(0),
        )

    def act(state: AgentState, obs, key, deterministic=False):
        """Action in [-1, 1]^A for obs (..., O): a policy sample, or its mode if deterministic."""
        mean, log_std = actor.apply(actor_variables(state.actor_params, state.actor_stats), obs)
        if deterministic:
            return jnp.tanh(mean)
        return sample_action(mean, log_std, key)[0]

    def update(state: AgentState, batch: Transition, key, update_index):
        """One gradient update of the critic and, every `policy_delay` updates, of actor and temperature.

        `update_index` is the update's number shared by all seeds; keeping it out of the
        vmapped state keeps the policy-delay branch a real branch under vmap.
        """
        critic_key, actor_key = jax.random.split(key)
        (_, (stats, metrics)), grads = jax.value_and_grad(losses.critic, has_aux=True)(
            state.critic_params, state.critic_stats, state.target_params, state.actor_params, state.actor_stats,
            state.log_alpha, batch, critic_key)
        updates, critic_opt = optimizer.update(grads, state.critic_opt, state.critic_params)
        critic_params = optax.apply_updates(state.critic_params, updates)
        target_params = state.target_params
        if cfg.target_network:
            target_params = optax.incremental_update(critic_params, target_params, cfg.tau)
        state = state.replace(critic_params=critic_params, critic_stats=stats, critic_opt=critic_opt,
                              target_params=target_params, updates=state.updates + 1)

        def actor_step(state):
            (loss, (log_prob, actor_stats)), grads = jax.value_and_grad(losses.actor, has_aux=True)(
                state.actor_params, state.actor_stats, state.critic_params, state.critic_stats, state.log_alpha,
                batch.obs, actor_key)
            updates, actor_opt = optimizer.update(grads, state.actor_opt, state.actor_params)
            actor_params = optax.apply_updates(state.actor_params, updates)
            alpha_grad = jax.grad(losses.alpha)(state.log_alpha, log_prob)
            updates, alpha_opt = alpha_optimizer.update(alpha_grad, state.alpha_opt, state.log_alpha)
            log_alpha = optax.apply_updates(state.log_alpha, updates)
            state = state.replace(actor_params=actor_params, actor_stats=actor_stats, actor_opt=actor_opt,
                                  log_alpha=log_alpha, alpha_opt=alpha_opt)
            return state, loss, -jnp.mean(log_prob)

        def skip(state):
            return state, jnp.float32(jnp.nan), jnp.float32(jnp.nan)

        due = update_index % cfg.policy_delay == 0
        if cfg.actor_updates_per_step is not None:
            # The last of each step's critic updates carry the actor's (RL-X: 20 critic, then 1 actor).
            due &= update_index % cfg.updates_per_step >= cfg.updates_per_step - cfg.actor_updates_per_step
        state, actor_loss, entropy = jax.lax.cond(due, actor_step, skip, state)
        metrics = dict(metrics, actor_loss=actor_loss, entropy=entropy, alpha=jnp.exp(state.log_alpha))
        return state, metrics

    return Agent(config=cfg, init=init, act=act, update=update)
