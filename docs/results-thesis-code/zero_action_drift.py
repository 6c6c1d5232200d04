"""Where each approach goes at zero action: trunk velocity over 8 s after a 2 s settle, per protocol.

Under random directions the track_xy reward is zero unless the robot is within 0.5 m/s of the
command, so an approach that drifts at zero action is rewarded first for commands along its
drift. This measures that drift (MJX env, the protocol's own gains, rate and action pipeline)
and the random-direction reward a drifting robot would collect for a 0.5 m/s command forward and backward.
Writes docs/results-thesis-code/zero_action_drift.json. Run: `python docs/results-thesis-code/zero_action_drift.py`.
"""

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.experiments.registry import THESIS_APPROACHES
from mjx_badger.protocol import protocols
from mjx_badger.records import results
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.tasks import locomotion as tasks

OUT = Path(__file__).with_suffix(".json")
SETTLE_S, MEASURE_S = 2.0, 8.0


def drift(approach: str, protocol: protocols.Protocol) -> tuple:
    """Mean trunk (vx, vy) in m/s at zero action, after the settle."""
    env = HB40Env(approach, "forward", EnvConfig(protocol=protocol.replace(episode_seconds=SETTLE_S + MEASURE_S + 1)))
    reset, step = jax.jit(env.reset), jax.jit(env.step)
    state = reset(jax.random.PRNGKey(0))
    zero = jnp.zeros(env.action_size)
    for _ in range(int(SETTLE_S * env.control_hz)):
        state = step(state, zero)
    start = np.asarray(state.pipeline_state.qpos[:2])
    for _ in range(int(MEASURE_S * env.control_hz)):
        state = step(state, zero)
    return tuple(float(v) for v in (np.asarray(state.pipeline_state.qpos[:2]) - start) / MEASURE_S)


def omni_reward(velocity: tuple, command: tuple, protocol: protocols.Protocol) -> float:
    """The protocol's random-direction reward for a level, non-turning robot moving at `velocity`."""
    task = tasks.make_task("omni-random", protocol.rewards)
    motion = tasks.Motion(jnp.array([*velocity, 0.0]), jnp.zeros(3), 0.0, 0.0, jnp.zeros(12))
    return float(task.reward(motion, jnp.array([*command, 0.0]))[0])


def main():
    table = {}
    for name, protocol in protocols.PROTOCOLS.items():
        for approach in THESIS_APPROACHES:
            vx, vy = drift(approach, protocol)
            rewards = {"forward": omni_reward((vx, vy), (0.5, 0.0), protocol),
                       "backward": omni_reward((vx, vy), (-0.5, 0.0), protocol)}
            table.setdefault(approach, {})[name] = {"vx": vx, "vy": vy, "omni_reward": rewards}
            print(f"{approach:7s} {name:12s} drift vx {vx:+.3f} vy {vy:+.3f} m/s; omni reward at 0.5 m/s "
                  f"forward {rewards['forward']:.2f}, backward {rewards['backward']:.2f}", flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps({"settle_s": SETTLE_S, "measure_s": MEASURE_S, "drift": table,
                               "hardware": results.hardware(), "versions": results.versions(),
                               "git_commit": results.git_commit(), "date": results.now()}, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
