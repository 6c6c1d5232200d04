"""`train(key)`: the whole learning loop as one pure program, vmapped over seeds.

`make_train(config)` returns `init(key) -> Carry`, `chunk(carry, start_step) -> (carry,
metrics)` and `train(key)`, the loop over all chunks. The host runs
`jit(vmap(chunk, in_axes=(0, None)))` chunk by chunk to show progress and write results
as it goes; the step counter is passed unbatched so the warm-up and policy-delay branches
stay real branches under vmap.
"""

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
from flax import struct

from mjx_badger.agents import replay_buffer
from mjx_badger.agents.agent import AgentState, make_agent
from mjx_badger.agents.losses import Transition
from mjx_badger.learning.config import TrainConfig
from mjx_badger.sim import evaluation
from mjx_badger.sim.env import HB40Env
from mjx_badger.tasks import locomotion as tasks

ESTIMATED = ("estimated_forward_velocity", "estimated_lateral_velocity", "estimated_desired_velocity")
"""The onboard estimate's metrics, beside the true ones, where the env senses (on-robot conditions)."""
STOPS = ("stops_before_fall", "premature_stops")
"""Safety stops the truth shows no fall at, and those only the sensors' noise made (on-robot conditions, §6.4)."""
SUMMED = ("episode_end", "finished_return", "falls_total", "would_falls", "blowups") + STOPS
"""Step metrics that count, summed over a seed's environments when it has several (the others are averaged)."""


class Carry(struct.PyTreeNode):
    """Everything one seed's training loop carries from step to step."""

    env_state: object
    agent_state: AgentState
    buffer: replay_buffer.ReplayBuffer
    key: jax.Array
    eval_key: jax.Array
    episode_return: jnp.ndarray
    falls: jnp.ndarray
    """Falls as the protocol counts them (thesis-code: only once learning has started)."""
    diverged_at: jnp.ndarray
    """-1, or the step at whose chunk end the agent or its metrics went non-finite; from then the seed is frozen."""


class Trainer(NamedTuple):
    config: TrainConfig
    env: HB40Env
    init: Callable
    step: Callable
    """(carry, step index) -> (carry, that step's metrics): one environment step and its updates, what a chunk scans."""
    chunk: Callable
    train: Callable
    evaluate: Callable
    gait: Callable


def make_train(config: TrainConfig) -> Trainer:
    """The pure training functions of `config`."""
    config.validate()
    cfg = config.agent_config
    protocol = config.protocol_spec
    env_config = config.env_config
    task = tasks.make_task(config.task, env_config.protocol.rewards, env_config.protocol.curriculum,
                           **dict(config.task_params))
    env = HB40Env(config.approach, task, env_config, config.robot_spec, config.approach_params)
    envs = config.num_envs
    batched = envs > 1  # several environments per seed: each stepped alike, all feeding the one learner
    agent = make_agent(cfg, env.observation_size, env.action_size,
                       total_updates=(config.total_steps - config.warmup_steps) * cfg.updates_per_step, num_envs=envs)
    capacity = config.num_chunks * config.chunk_steps * envs
    reset_envs = jax.vmap(env.reset) if batched else env.reset
    step_envs = jax.vmap(env.step) if batched else env.step
    store = replay_buffer.add_many if batched else replay_buffer.add

    def init(key) -> Carry:
        key, env_key, agent_key, eval_key = jax.random.split(key, 4)
        return Carry(
            env_state=reset_envs(jax.random.split(env_key, envs) if batched else env_key),
            agent_state=agent.init(agent_key),
            buffer=replay_buffer.init(capacity, env.observation_size, env.action_size),
            key=key,
            eval_key=eval_key,
            episode_return=jnp.zeros(envs) if batched else jnp.float32(0.0),
            falls=jnp.int32(0),
            diverged_at=jnp.int32(-1),
        )

    def learn(agent_state, buffer, key, step):
        """`updates_per_step` gradient updates on fresh batches, as one scan."""

        def one_update(agent_state, j):
            batch_key, update_key = jax.random.split(jax.random.fold_in(key, j))
            batch = replay_buffer.sample(buffer, batch_key, cfg.batch_size)
            index = (step - config.warmup_steps) * cfg.updates_per_step + j
            return agent.update(agent_state, batch, update_key, index)

        before = agent_state.updates
        agent_state, metrics = jax.lax.scan(one_update, agent_state, jnp.arange(cfg.updates_per_step))
        metrics = {k: jnp.nanmean(v) for k, v in metrics.items()}
        # Counted from the agent's own update counter, not assumed from the config.
        return agent_state, dict(metrics, updates=(agent_state.updates - before).astype(jnp.float32))

    def skip_learning(agent_state, buffer, key, step):
        nan = jnp.float32(jnp.nan)
        metrics = {k: nan for k in ("critic_loss", "q_mean", "actor_loss", "entropy", "alpha")}
        return agent_state, dict(metrics, updates=jnp.float32(0.0))

    def env_step(carry: Carry, step):
        key, act_key, explore_key, learn_key = jax.random.split(carry.key, 4)
        obs = carry.env_state.obs
        policy_action = agent.act(carry.agent_state, obs, act_key)
        random_action = jax.random.uniform(explore_key, obs.shape[:-1] + (env.action_size,), minval=-1.0, maxval=1.0)
        action = jnp.where(step < config.warmup_steps, random_action, policy_action)
        env_state = step_envs(carry.env_state, action)
        info = env_state.info
        next_obs = info["next_obs"]
        if protocol.bootstraps_from_next_episode(config.algo):
            # The released replay's next state is the following row: at a time-out, the next episode's start.
            next_obs = jnp.where(info["truncated"][..., None], env_state.obs, next_obs)
        transition = Transition(obs, action, env_state.reward, next_obs, 1.0 - info["terminated"].astype(jnp.float32))
        buffer = store(carry.buffer, transition)
        agent_state = agent.observe(carry.agent_state, obs, env_state.reward, env_state.done)
        if cfg.resets:
            agent_state = jax.lax.cond(jnp.isin(step, jnp.asarray(cfg.resets)), agent.reset, lambda s, k: s,
                                       agent_state, jax.random.fold_in(learn_key, 1))
        agent_state, learn_metrics = jax.lax.cond(step >= config.warmup_steps, learn, skip_learning,
                                                  agent_state, buffer, learn_key, step)
        episode_return = carry.episode_return + env_state.reward
        done = env_state.done > 0
        counted = (info["terminated"] & ~info["blew_up"]
                   & ((step >= config.warmup_steps) | (not protocol.falls_after_warmup)))
        falls = carry.falls + jnp.sum(counted).astype(jnp.int32)
        step_metrics = dict(
            env_state.metrics,
            reward=env_state.reward,
            episode_end=done.astype(jnp.float32),
            finished_return=jnp.where(done, episode_return, 0.0),
            falls=falls.astype(jnp.float32),
            falls_total=info["falls"].astype(jnp.float32),
            would_falls=info["would_falls"].astype(jnp.float32),
            blowups=info["blowups"].astype(jnp.float32),
            **{k: info[k].astype(jnp.float32) for k in STOPS if k in info},  # on-robot conditions only
            **learn_metrics,
        )
        if batched:  # one number per step, as one environment gives: counts summed over the environments, the rest averaged
            step_metrics = {k: (jnp.sum(v, axis=0) if k in SUMMED else jnp.nanmean(v, axis=0)) if jnp.ndim(v) else v
                            for k, v in step_metrics.items()}
        carry = carry.replace(env_state=env_state, agent_state=agent_state, buffer=buffer, key=key,
                              episode_return=jnp.where(done, 0.0, episode_return), falls=falls)
        return carry, step_metrics

    act = lambda agent_state, obs: agent.act(agent_state, obs, None, deterministic=True)
    evaluate, gait_record = evaluation.make_evaluation(env, act, config.eval_steps, config.gait_seconds)

    def chunk(carry: Carry, start_step):
        """`chunk_steps` environment steps with learning, then one evaluation; metrics are per seed.

        A seed whose agent or metrics go non-finite keeps the carry it had before the chunk
        from then on (its metrics are NaN), so one diverging seed does not sink the others.
        """
        before = carry
        carry, metrics = run_chunk(carry, start_step)
        frozen = (before.diverged_at >= 0) | ~_finite(carry.agent_state, metrics)
        carry = jax.tree.map(lambda old, new: jnp.where(frozen, old, new), before, carry)
        carry = carry.replace(diverged_at=jnp.where(
            before.diverged_at >= 0, before.diverged_at,
            jnp.where(frozen, start_step + config.chunk_steps, -1)).astype(jnp.int32))
        metrics = {k: jnp.where(frozen, jnp.nan, v) for k, v in metrics.items()}
        return carry, metrics

    def run_chunk(carry: Carry, start_step):
        carry, steps = jax.lax.scan(env_step, carry, start_step + jnp.arange(config.chunk_steps))
        episodes = jnp.sum(steps["episode_end"])
        # nanmean: the step of a physics blow-up (train/blowups) has no motion to average.
        metrics = {f"train/{k}": jnp.nanmean(steps[k]) for k in ("forward_velocity", "lateral_velocity", "yaw_rate",
                                                                "height", "reward", "desired_velocity",
                                                                "command_lateral_velocity", "desired_error")}
        metrics.update({f"train/{k}": jnp.nanmean(steps[k]) for k in ESTIMATED if k in steps})  # sensing envs only
        if "estimated_desired_velocity" in steps:  # the estimate's second moments: its gain over the run (analysis.py)
            true, estimate = steps["desired_velocity"], steps["estimated_desired_velocity"]
            metrics.update({"train/true_squared": jnp.nanmean(true * true),
                            "train/estimate_squared": jnp.nanmean(estimate * estimate),
                            "train/true_times_estimate": jnp.nanmean(true * estimate)})
        metrics.update({f"train/{k}": steps[k][-1] for k in STOPS if k in steps})
        metrics.update({k: steps[k][-1] for k in steps if k.startswith("curriculum/")})
        metrics.update({k: jnp.nanmean(v) for k, v in steps.items() if k.startswith("reward/")})
        metrics.update({f"train/{k}": jnp.nanmean(steps[k]) for k in ("critic_loss", "q_mean", "actor_loss",
                                                                     "entropy", "alpha")})
        metrics["train/episode_return"] = jnp.where(episodes > 0, jnp.sum(steps["finished_return"]) / episodes,
                                                    jnp.nan)
        metrics["train/episodes"] = episodes
        metrics["train/falls"] = steps["falls"][-1]
        metrics["train/falls_total"] = steps["falls_total"][-1]
        metrics["train/would_falls"] = steps["would_falls"][-1]
        metrics["train/blowups"] = steps["blowups"][-1]
        metrics["train/updates"] = jnp.sum(steps["updates"])
        metrics.update(evaluate(carry.agent_state, carry.eval_key))
        return carry, metrics

    def train(key):
        """The whole run for one seed: metrics stacked over chunks."""
        starts = jnp.arange(config.num_chunks) * config.chunk_steps
        return jax.lax.scan(chunk, init(key), starts)

    def evaluate_carry(carry: Carry):
        """The evaluation every chunk ends with, alone (evaluation.py)."""
        return evaluate(carry.agent_state, carry.eval_key)

    def gait(carry: Carry):
        """After training: the gait record of the seed's deterministic policy (evaluation.py)."""
        return gait_record(carry.agent_state, carry.eval_key)

    return Trainer(config=config, env=env, init=init, step=env_step, chunk=chunk, train=train, evaluate=evaluate_carry, gait=gait)


def _finite(agent_state, metrics: dict) -> jnp.ndarray:
    """True while every float of the agent is finite and no metric is infinite (NaN metrics can be honest: no episode ended)."""
    leaves = [x for x in jax.tree.leaves(agent_state) if jnp.issubdtype(x.dtype, jnp.inexact)]
    # One reduction over everything: a reduction per leaf becomes a chain of ands that XLA copies into
    # every select of the freeze below, a quarter of the chunk's compile time (benchmarks/bench_compile.py).
    finite = jnp.all(jnp.isfinite(jnp.concatenate([jnp.ravel(x) for x in leaves])))
    return finite & ~jnp.any(jnp.isinf(jnp.stack(list(metrics.values()))))
