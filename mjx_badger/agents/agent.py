"""Pure init / act / update of an agent of the SAC family."""

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
import optax
from flax import struct

from mjx_badger.agents import normalisers, optimism
from mjx_badger.agents.config import AgentConfig
from mjx_badger.agents.losses import Transition, actor_variables, critic_variables, make_losses
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
    normaliser: Any = None
    """Running moments of observations and returns (agents that normalise); None for the thesis's four."""
    optimism: Any = None
    """BRO's optimistic actor (agents.optimism.Optimism); None without it."""


class Agent(NamedTuple):
    """`init(key)`, `act(state, obs, key, deterministic)`, `update(state, batch, key, update_index)`,
    `observe(state, obs, reward, done)` (each stored step, in order) and `reset(state, key)` (fresh networks)."""

    config: AgentConfig
    init: Callable
    act: Callable
    update: Callable
    observe: Callable
    reset: Callable


def optimiser(cfg: AgentConfig, b1: float, weight_decay: float):
    """Adam, or AdamW with decoupled weight decay; with a learning-rate schedule its rate is set before each step."""

    def build(learning_rate):
        if weight_decay:
            return optax.adamw(learning_rate, b1=b1, b2=cfg.adam_b2, weight_decay=weight_decay)
        return optax.adam(learning_rate, b1=b1, b2=cfg.adam_b2)

    return build(cfg.learning_rate) if cfg.learning_rate_end is None else optax.inject_hyperparams(build)(
        learning_rate=cfg.learning_rate)


def learning_rate(cfg: AgentConfig, updates, total_updates):
    """The rate after `updates` critic updates: falling linearly to `learning_rate_end` over `total_updates`."""
    done = jnp.clip(updates / jnp.maximum(total_updates, 1), 0.0, 1.0)
    return cfg.learning_rate + (cfg.learning_rate_end - cfg.learning_rate) * done


def make_agent(cfg: AgentConfig, obs_size: int, action_size: int, total_updates: int = 1_000_000,
               num_envs: int = 1) -> Agent:
    """Build the pure functions of the agent `cfg` for the given observation and action sizes; a learning-rate
    schedule runs over `total_updates`; `observe` takes `num_envs` environments' steps at once (1: unbatched)."""
    actor = Actor(action_size=action_size, hidden=cfg.hidden, batch_renorm=cfg.actor_batch_renorm,
                  renorm_momentum=cfg.renorm_momentum, renorm_warmup_steps=cfg.renorm_warmup_steps,
                  log_std_clip=cfg.log_std_clip, trunk=cfg.trunk, log_std_range=cfg.log_std_range)
    critic = Critic(
        ensemble_size=cfg.ensemble_size,
        hidden=cfg.critic_hidden or cfg.hidden,
        batch_renorm=cfg.batch_renorm,
        renorm_momentum=cfg.renorm_momentum,
        renorm_warmup_steps=cfg.renorm_warmup_steps,
        dropout_rate=cfg.dropout_rate,
        layer_norm=cfg.layer_norm,
        trunk=cfg.trunk,
        outputs=1 if cfg.critic_output == "scalar" else cfg.atoms,
    )
    shift = optimism.Shift(action_size=action_size, hidden=cfg.hidden)
    losses = make_losses(actor, critic, cfg, action_size)
    optimizer = optimiser(cfg, cfg.adam_b1, cfg.weight_decay)
    alpha_optimizer = optimiser(cfg, cfg.adam_b1 if cfg.alpha_adam_b1 is None else cfg.alpha_adam_b1, 0.0)
    adjust_optimizer = optax.adam(optimism.ADJUSTMENT_LR, b1=0.5)
    project = normalisers.unit_kernels if cfg.weight_norm else (lambda params: params)

    def step(opt, grads, opt_state, params, rate):
        """One optimiser step at the scheduled rate, the kernels put back on the sphere where the agent does."""
        if cfg.learning_rate_end is not None:
            opt_state = opt_state._replace(hyperparams=dict(opt_state.hyperparams, learning_rate=rate))
        updates, opt_state = opt.update(grads, opt_state, params)
        return project(optax.apply_updates(params, updates)), opt_state

    def alpha_step(state: AgentState, log_prob, rate) -> AgentState:
        """One step of the temperature towards its target entropy, from these log-probabilities."""
        alpha_grad = jax.grad(losses.alpha)(state.log_alpha, log_prob)
        log_alpha, alpha_opt = step(alpha_optimizer, alpha_grad, state.alpha_opt, state.log_alpha, rate)
        return state.replace(log_alpha=log_alpha, alpha_opt=alpha_opt)

    def init(key) -> AgentState:
        actor_key, critic_key, shift_key = jax.random.split(key, 3)
        obs = jnp.zeros((1, obs_size))
        action = jnp.zeros((1, action_size))
        actor_vars = actor.init(actor_key, obs)
        actor_params = project({"params": actor_vars["params"]})  # the stats ride in their own field
        critic_vars = critic.init(critic_key, obs, action)
        critic_params = project(critic_vars["params"])
        log_alpha = jnp.log(jnp.float32(cfg.initial_alpha))
        normaliser = None
        if cfg.observation_norm or cfg.reward_scaling != "none":
            normaliser = {"obs": normalisers.moments(obs_size), "reward": normalisers.reward_scale(num_envs)}
        explorer = None
        if cfg.optimism:
            shift_params = shift.init(shift_key, obs, action)
            raws = {"beta": optimism.raw_of(optimism.BETA_INIT), "kl_weight": optimism.raw_of(optimism.KL_WEIGHT_INIT)}
            explorer = optimism.Optimism(params=shift_params, opt=optimizer.init(shift_params), beta=raws["beta"],
                                         kl_weight=raws["kl_weight"], adjust_opt=adjust_optimizer.init(raws))
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
            normaliser=normaliser,
            optimism=explorer,
        )

    def standardised(state: AgentState, obs):
        return normalisers.normalise(state.normaliser["obs"], obs) if cfg.observation_norm else obs

    def act(state: AgentState, obs, key, deterministic=False):
        """Action in [-1, 1]^A for obs (..., O): a policy sample (BRO: the optimistic one), or its mode if
        deterministic."""
        obs = standardised(state, obs)
        mean, log_std = actor.apply(actor_variables(state.actor_params, state.actor_stats), obs)
        if deterministic:
            return jnp.tanh(mean)
        if cfg.optimism:
            mean = mean + shift.apply(state.optimism.params, obs, mean)
            log_std = log_std + jnp.log(optimism.STD_MULTIPLIER)
        return sample_action(mean, log_std, key)[0]

    def observe(state: AgentState, obs, reward, done) -> AgentState:
        """The running moments after one stored step (observation acted on, its reward, whether it ended an
        episode); the identity for agents that normalise nothing."""
        if state.normaliser is None:
            return state
        moments = normalisers.merge(state.normaliser["obs"], jnp.reshape(obs, (-1, obs_size)))
        scale = normalisers.observe_reward(state.normaliser["reward"], reward, done, cfg.gamma)
        return state.replace(normaliser={"obs": moments, "reward": scale})

    def reset(state: AgentState, key) -> AgentState:
        """Every network and optimiser afresh, the normalisers and the update count kept (BRO's resets)."""
        return init(key).replace(normaliser=state.normaliser, updates=state.updates)

    def prepared(state: AgentState, batch: Transition) -> Transition:
        """The batch as the losses see it: observations standardised, rewards scaled."""
        batch = batch._replace(obs=standardised(state, batch.obs), next_obs=standardised(state, batch.next_obs))
        if cfg.reward_scaling == "none":
            return batch
        divisor = normalisers.reward_divisor(state.normaliser["reward"], cfg.reward_scaling, cfg.g_max)
        return batch._replace(reward=batch.reward / divisor)

    def update(state: AgentState, batch: Transition, key, update_index):
        """One gradient update of the critic and, every `policy_delay` updates, of actor and temperature.

        `update_index` is the update's number shared by all seeds; keeping it out of the
        vmapped state keeps the policy-delay branch a real branch under vmap.
        """
        critic_key, actor_key = jax.random.split(key)
        batch = prepared(state, batch)
        rate = actor_rate = None
        if cfg.learning_rate_end is not None:  # each optimiser's schedule counts its own steps (RL-X's optax ones)
            rate = learning_rate(cfg, state.updates, total_updates)
            actor_rate = learning_rate(cfg, state.updates // cfg.policy_delay, total_updates)
        (_, (stats, metrics, next_log_prob)), grads = jax.value_and_grad(losses.critic, has_aux=True)(
            state.critic_params, state.critic_stats, state.target_params, state.actor_params, state.actor_stats,
            state.log_alpha, batch, critic_key)
        critic_params, critic_opt = step(optimizer, grads, state.critic_opt, state.critic_params, rate)
        target_params = state.target_params
        if cfg.target_network:
            target_params = optax.incremental_update(critic_params, target_params, cfg.tau)
        state = state.replace(critic_params=critic_params, critic_stats=stats, critic_opt=critic_opt,
                              target_params=target_params, updates=state.updates + 1)
        if cfg.alpha_every_update:  # FastSAC: the temperature steps with the critic, on the next states' entropy
            state = alpha_step(state, next_log_prob, rate)

        def actor_step(state):
            (loss, (log_prob, actor_stats)), grads = jax.value_and_grad(losses.actor, has_aux=True)(
                state.actor_params, state.actor_stats, state.critic_params, state.critic_stats, state.log_alpha,
                batch.obs, actor_key)
            actor_params, actor_opt = step(optimizer, grads, state.actor_opt, state.actor_params, actor_rate)
            state = state.replace(actor_params=actor_params, actor_stats=actor_stats, actor_opt=actor_opt)
            if not cfg.alpha_every_update:
                state = alpha_step(state, log_prob, actor_rate)
            if cfg.optimism:
                state = state.replace(optimism=optimistic_step(state, batch.obs, jax.random.fold_in(actor_key, 1)))
            return state, loss, -jnp.mean(log_prob)

        def skip(state):
            if cfg.trunk == "xqc":  # XQC's actor refreshes its batch statistics on every update
                _, updated = actor.apply(actor_variables(state.actor_params, state.actor_stats), batch.obs,
                                         train=True, mutable=["batch_stats"])
                state = state.replace(actor_stats=updated["batch_stats"])
            return state, jnp.float32(jnp.nan), jnp.float32(jnp.nan)

        due = update_index % cfg.policy_delay == 0
        if cfg.actor_updates_per_step is not None:
            # The last of each step's critic updates carry the actor's (RL-X: 20 critic, then 1 actor).
            due &= update_index % cfg.updates_per_step >= cfg.updates_per_step - cfg.actor_updates_per_step
        state, actor_loss, entropy = jax.lax.cond(due, actor_step, skip, state)
        metrics = dict(metrics, actor_loss=actor_loss, entropy=entropy, alpha=jnp.exp(state.log_alpha))
        return state, metrics

    def optimistic_step(state: AgentState, obs, key) -> optimism.Optimism:
        """BRO's optimistic actor on the critics' upper bound, held near the main actor by the KL weight; then
        beta and the KL weight adjust towards the KL target."""
        explorer = state.optimism
        mean, log_std = jax.lax.stop_gradient(actor.apply(actor_variables(state.actor_params, state.actor_stats), obs))
        beta, kl_weight = optimism.squashed(explorer.beta), optimism.squashed(explorer.kl_weight)
        variables = critic_variables(state.critic_params, state.critic_stats)

        def loss(params):
            optimistic_mean = mean + shift.apply(params, obs, mean)
            action, _ = sample_action(optimistic_mean, log_std + jnp.log(optimism.STD_MULTIPLIER), key)
            upper = optimism.bound(critic.apply(variables, obs, action), beta)
            kl = jnp.mean(optimism.shift_kl(optimistic_mean, mean, jnp.exp(log_std)))
            return -jnp.mean(upper) + kl_weight * kl, kl

        (_, kl), grads = jax.value_and_grad(loss, has_aux=True)(explorer.params)
        params, opt = step(optimizer, grads, explorer.opt, explorer.params, None)
        raws = {"beta": explorer.beta, "kl_weight": explorer.kl_weight}
        adjust_grads = jax.grad(lambda r: sum(optimism.adjustment_losses(r["beta"], r["kl_weight"],
                                                                         kl / action_size)))(raws)
        updates, adjust_opt = adjust_optimizer.update(adjust_grads, explorer.adjust_opt, raws)
        raws = optax.apply_updates(raws, updates)
        return optimism.Optimism(params=params, opt=opt, beta=raws["beta"], kl_weight=raws["kl_weight"],
                                 adjust_opt=adjust_opt)

    return Agent(config=cfg, init=init, act=act, update=update, observe=observe, reset=reset)
