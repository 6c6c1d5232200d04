"""Deterministic evaluation runs and the gait record of a policy, as pure functions over an env.

`make_evaluation(env, act, eval_steps, gait_seconds)` returns `evaluate(policy_state, key) ->
eval/ metrics` and `gait(policy_state, key) -> record` (foot contacts and forward velocity at
the physics rate), where `act(policy_state, obs)` is the deterministic policy.

One schema whatever the task: one deterministic run per evaluation command of the task (one
for the forward tasks, four directions x two speeds for the omni ones), each reported as
`eval/{run}/{metric}` for every metric of RUN_METRICS, and `eval/{metric}` over all runs: the
mean, falls summed. `desired_velocity` is the trunk velocity along the command (the forward
velocity for the forward tasks), the `_mae` metrics its error and the lateral and yaw errors.
A run longer than an episode restarts from standing at the episode's time limit, under its own command.
"""

import copy
from typing import Callable

import jax
import jax.numpy as jnp

RUN_METRICS = ("return", "desired_velocity", "lateral_velocity", "yaw_rate", "desired_mae", "lateral_mae", "yaw_mae",
               "falls")


def batched_like(tree, key: jax.Array):
    """`tree` unchanged, each leaf made to depend on `key`: under vmap over keys every leaf is then batched.

    A scan whose initial carry has unbatched leaves (a reset's constants) that its body turns batched is
    batched twice by vmap, and here the body is the whole MJX step: this saves seconds of tracing per compile.
    """
    same = jnp.all(key == key)
    return jax.tree.map(lambda x: jnp.where(same, x, x), tree)


def holding(env, command):
    """`env` whose every episode runs under `command`: a run longer than an episode restarts (the episode's time
    limit) under the command it is scored against, not one the task draws (a random direction, the curriculum's)."""
    held = copy.copy(env)
    held.task = env.task._replace(command=lambda task_state, _key: (task_state, command))
    return held


def make_evaluation(env, act: Callable, eval_steps: int, gait_seconds: float):
    """(evaluate, gait) of the policy `act` on `env`; see the module docstring."""
    names = tuple(env.task.eval_commands)
    commands = jnp.asarray([env.task.eval_commands[name] for name in names], dtype=jnp.float32)

    def run(policy_state, key, command):
        """Deterministic policy from a fresh episode under `command`; the steps after a first fall are ignored."""
        held = holding(env, command)

        def body(state, _):
            state = held.step(state, act(policy_state, state.obs))
            m = state.metrics
            return state, (state.reward, m["desired_velocity"], m["command_lateral_velocity"], m["yaw_rate"],
                           state.info["terminated"], m.get("estimated_desired_velocity"))

        _, (reward, along, lateral, yaw, terminated, estimated) = jax.lax.scan(
            body, batched_like(held.reset(key, command), key), None, length=eval_steps)
        upright = jnp.cumsum(terminated) == 0
        mean = lambda x: jnp.sum(jnp.where(upright, x, 0.0)) / jnp.maximum(jnp.sum(upright), 1)
        speed = jnp.linalg.norm(command[:2])
        return {
            "return": jnp.sum(jnp.where(upright, reward, 0.0)),
            "desired_velocity": mean(along),
            "lateral_velocity": mean(lateral),
            "yaw_rate": mean(yaw),
            "desired_mae": mean(jnp.abs(along - speed)),
            "lateral_mae": mean(jnp.abs(lateral)),
            "yaw_mae": mean(jnp.abs(yaw)),
            "falls": jnp.any(terminated).astype(jnp.float32),
            # What the robot believed it walked, where it senses (the thesis judged the real runs by video).
            **({} if estimated is None else {"estimated_desired_velocity": mean(estimated)}),
        }

    def evaluate(policy_state, key):
        """The task's evaluation runs as eval/{run}/{metric} and eval/{metric} (see the module docstring)."""
        if len(names) == 1:  # unbatched: the very arithmetic of a single run
            runs = jax.tree.map(lambda x: x[None], run(policy_state, key, commands[0]))
        else:
            runs = jax.vmap(run, in_axes=(None, None, 0))(policy_state, key, commands)
        metrics = {f"eval/{name}/{k}": v[i] for k, v in runs.items() for i, name in enumerate(names)}
        metrics.update({f"eval/{k}": jnp.sum(v) if k == "falls" else jnp.mean(v) for k, v in runs.items()})
        return metrics

    def gait(policy_state, key):
        """A deterministic run under the first evaluation command, traced at the physics rate.

        Returns the last `gait_seconds / 2` of foot contacts (T, 4) and trunk forward velocity (T,).
        """

        def body(state, _):
            return env.traced_step(state, act(policy_state, state.obs))

        steps = int(round(gait_seconds / env.control_dt))
        _, (contacts, velocity) = jax.lax.scan(body, batched_like(env.reset(key, commands[0]), key), None,
                                               length=steps)
        keep = steps * env.substeps // 2
        return {"contacts": contacts.reshape(-1, 4)[-keep:].astype(jnp.int8),
                "forward_velocity": velocity.reshape(-1)[-keep:]}

    return evaluate, gait
