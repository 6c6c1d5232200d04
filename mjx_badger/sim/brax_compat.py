"""brax's own trainers (`brax.training.agents.ppo.train`, `sac.train`) on the HB40 env.

Two things stand between brax 0.14.2 and our env, and this module mends both:

1. brax's trainers call `jax.device_put_replicated`, which jax 0.10 removed (google/brax#671,
   open; its workaround, jax 0.9.2, would change the stack every result here was produced
   with). Importing this module puts back an equivalent built on `NamedSharding`, the
   replacement jax's pmap migration guide gives; it touches jax only where the name is missing.
2. brax's default wrapper (`brax.envs.training.wrap`) stacks an episode counter and an
   auto-reset on top of the env, but HB40Env ends and resets its own episodes: brax would
   then reset a second time (restoring the *first* episode's observation, whose command is
   stale under random or curriculum commands) and read the env's time limit as a fall
   (`truncation` 0), so SAC and PPO would bootstrap through time limits wrongly. `wrap`
   is the wrapper to pass as `wrap_env_fn`: it vmaps the env and only translates its
   episode bookkeeping into the names brax reads (`truncation`, `steps`, `episode_done`,
   `episode_metrics`); the env's own auto-reset is the only one.
"""

import jax
import jax.numpy as jnp
import numpy as np
from brax.envs.base import State, Wrapper
from brax.envs.wrappers.training import VmapWrapper
from jax.sharding import Mesh, NamedSharding, PartitionSpec


def device_put_replicated(tree, devices):
    """One copy of every leaf of `tree` per device, stacked on a new leading axis sharded over `devices`."""
    sharding = NamedSharding(Mesh(np.array(devices), ("replica",)), PartitionSpec("replica"))
    return jax.tree.map(lambda leaf: jax.device_put(jnp.stack([jnp.asarray(leaf)] * len(devices)), sharding), tree)


if not hasattr(jax, "device_put_replicated"):  # jax >= 0.10: the name is gone (its hook raises AttributeError)
    jax.device_put_replicated = device_put_replicated


class EpisodeBookkeeping(Wrapper):
    """The info brax's trainers and evaluator read, from the env's own episode ends (no second reset)."""

    def reset(self, rng: jax.Array) -> State:
        state = self.env.reset(rng)
        zeros = jnp.zeros(rng.shape[:-1])
        state.info.update(steps=zeros, truncation=zeros, episode_done=zeros,
                          episode_metrics={name: zeros for name in ("sum_reward", "length", *state.metrics)})
        return state

    def step(self, state: State, action: jax.Array) -> State:
        finished = state.info["episode_done"]
        kept = {name: state.info[name] for name in ("steps", "truncation", "episode_done", "episode_metrics")}
        nstate = self.env.step(state, action)
        # An episode that ended on the previous step starts its sums and step count afresh.
        sums = {name: value * (1 - finished) for name, value in kept["episode_metrics"].items()}
        sums["sum_reward"] += nstate.reward
        sums["length"] += 1
        for name, value in nstate.metrics.items():
            if name != "reward":  # brax's evaluator adds the reward as a metric; it is summed above
                sums[name] += value
        nstate.info.update(steps=kept["steps"] * (1 - finished) + 1,
                           truncation=nstate.info["truncated"].astype(jnp.float32),
                           episode_done=nstate.done, episode_metrics=sums)
        return nstate


def wrap(env, episode_length: int, action_repeat: int = 1, randomization_fn=None):
    """brax's `wrap_env_fn` for HB40Env: vmap plus `EpisodeBookkeeping`; the env's own time limit and auto-reset rule."""
    if episode_length != env.episode_steps:
        raise ValueError(f"episode_length={episode_length}, but this HB40Env's episodes are {env.episode_steps} "
                         "control steps (its protocol's episode_seconds); pass episode_length=env.episode_steps")
    if action_repeat != 1:
        raise ValueError(f"action_repeat={action_repeat}: HB40Env runs its own physics substeps per control step; "
                         "pass action_repeat=1 (or change the env's control rate)")
    if randomization_fn is not None:
        raise ValueError("randomization_fn is not supported: HB40Env steps its own model, not state.sys")
    return EpisodeBookkeeping(VmapWrapper(env))
