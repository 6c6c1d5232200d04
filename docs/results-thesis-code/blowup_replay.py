"""Replay a training run up to its first physics blow-up, then step that state again outside the training program.

The quick thesis-code JT runs see about one non-finite MJX state per 20-60k seed-steps
(`train/blowups`). This replays the quick JT-NF forward run (seeds 0-2, the same program but
10-step chunks) until a seed's blow-up counter moves, then takes the state and action of the
step that blew up and steps them again: unbatched with `env.step` and batched with
`vmap(env.step)`, both in float32 MJX. If those stay finite, the blow-up is a rounding
knife-edge of the compiled training program, not a state the physics cannot integrate.
Writes docs/results-thesis-code/blowup_replay.json. Run: `python docs/results-thesis-code/blowup_replay.py [--steps 3000]`.
"""

import argparse
import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents.agent import make_agent
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.programs import seeds_chunk
from mjx_badger.learning.train import make_train
from mjx_badger.records import results

OUT = Path(__file__).with_suffix(".json")
SEEDS = (0, 1, 2)


def config(chunk_steps: int) -> TrainConfig:
    # The quick profile's run; evaluation shortened, which leaves the training carry untouched.
    return TrainConfig(approach="jt-nf", algo="crossq", task="forward", total_steps=20_000, chunk_steps=chunk_steps,
                       warmup_steps=1_000, eval_steps=1)


def blowups(metrics) -> np.ndarray:
    return np.asarray(metrics["train/blowups"])


def find_blowup(steps: int):
    """(carry before the chunk, start step, seed) of the first blow-up, running 10-step chunks."""
    trainer = make_train(config(10))
    carry = jax.jit(jax.vmap(trainer.init))(jax.vmap(jax.random.PRNGKey)(jnp.asarray(SEEDS)))
    chunk = jax.jit(seeds_chunk(trainer, len(SEEDS)))
    for start in range(0, steps, 10):
        before = carry
        carry, metrics = chunk(carry, start)
        if blowups(metrics).any():
            return before, start, int(np.argmax(blowups(metrics) > 0))
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000)
    args = parser.parse_args()
    found = find_blowup(args.steps)
    report = {"run": "quick thesis-code JT-NF forward, seeds 0-2", "searched_steps": args.steps}
    if found is None:
        report["blowup"] = None
    else:
        carry, start, seed = found
        trainer = make_train(config(1))
        env = trainer.env
        chunk = jax.jit(seeds_chunk(trainer, len(SEEDS)))
        for step in range(start, start + 10):  # single steps: which one blew up
            before = carry
            carry, metrics = chunk(carry, step)
            if blowups(metrics)[seed] > np.asarray(before.env_state.info["blowups"])[seed]:
                break
        agent = make_agent(trainer.config.agent_config, env.observation_size, env.action_size)
        actions = jnp.stack([agent.act(jax.tree.map(lambda x: x[s], before.agent_state), before.env_state.obs[s],
                                       jax.random.split(before.key[s], 4)[1]) for s in range(len(SEEDS))])
        unbatched = jax.jit(env.step)(jax.tree.map(lambda x: x[seed], before.env_state), actions[seed])
        batched = jax.jit(jax.vmap(env.step))(before.env_state, actions)
        state = jax.tree.map(lambda x: x[seed], before.env_state.pipeline_state)
        report["blowup"] = {
            "seed": SEEDS[seed], "step": step,
            "in_training_program": bool(blowups(metrics)[seed] > 0),
            "trunk_height_m": round(float(state.qpos[2]), 4),
            "max_abs_qvel": round(float(jnp.abs(state.qvel).max()), 3),
            "restepped_unbatched_blew_up": bool(unbatched.info["blew_up"]),
            "restepped_batched_blew_up": bool(np.asarray(batched.info["blew_up"])[seed]),
        }
    report.update(hardware=results.hardware(), versions=results.versions(), git_commit=results.git_commit(),
                  date=results.now())
    print(json.dumps(report["blowup"], indent=1))
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(report, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
