"""Host side of a training run: compile once, run chunk by chunk, show progress, write results."""

import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
from tqdm import tqdm

from mjx_badger import results
from mjx_badger.train import TrainConfig, make_train


def seeds_chunk(trainer, num_seeds: int):
    """The chunk over a leading seed axis: vmapped, or for one seed the unbatched program.

    XLA:CPU compiles a vmapped batch of one about twice as slow as the plain program
    (batch-renorm gradients and the replay gather lose their fast paths), so a single
    seed runs unbatched behind the same (1, ...) carry layout.
    """
    if num_seeds > 1:
        return jax.vmap(trainer.chunk, in_axes=(0, None))

    def single(carry, start):
        carry, metrics = trainer.chunk(jax.tree.map(lambda x: x[0], carry), start)
        return jax.tree.map(lambda x: x[None], (carry, metrics))

    return single


def run(config: TrainConfig, seeds: list[int], out_path: Path, progress: bool = True) -> dict:
    """Train `config` for every seed in one vmapped program; returns the results document."""
    started = results.now()
    trainer = make_train(config)
    keys = jax.vmap(jax.random.PRNGKey)(jnp.asarray(seeds))
    carry = jax.jit(jax.vmap(trainer.init))(keys)
    t0 = time.perf_counter()
    chunk = jax.jit(seeds_chunk(trainer, len(seeds)), donate_argnums=0).lower(carry, 0).compile()
    compile_s = time.perf_counter() - t0

    control_hz = config.env_config.control_hz
    document = {
        "schema": results.SCHEMA,
        "config": results.config_dict(config),
        "seeds": list(seeds),
        "complete": False,
        "steps": [],
        "sim_minutes": [],
        "metrics": {},
        "wall_clock": {"started": started, "compile_s": round(compile_s, 2)},
        "versions": results.versions(),
        "git_commit": results.git_commit(),
    }
    label = f"{config.approach} {config.algo} {config.task} x{len(seeds)}"
    bar = tqdm(total=config.num_chunks * config.chunk_steps, desc=label, unit="step", file=sys.stderr,
               disable=not progress, dynamic_ncols=True, mininterval=2.0)
    run_s = 0.0
    for index in range(config.num_chunks):
        start = index * config.chunk_steps
        t0 = time.perf_counter()
        carry, metrics = chunk(carry, start)
        metrics = jax.device_get(metrics)
        run_s += time.perf_counter() - t0
        steps = start + config.chunk_steps
        document["steps"].append(steps)
        document["sim_minutes"].append(round(steps / control_hz / 60, 4))
        for name, values in metrics.items():
            document["metrics"].setdefault(name, []).append(np.asarray(values, dtype=float).round(5).tolist())
        document["complete"] = index == config.num_chunks - 1
        document["wall_clock"].update(updated=results.now(), run_s=round(run_s, 2),
                                      seed_steps_per_s=round(steps * len(seeds) / run_s, 1))
        document["hardware"] = results.hardware()
        results.write(out_path, document)
        bar.update(config.chunk_steps)
        bar.set_postfix(v=f"{np.mean(metrics['train/forward_velocity']):.2f}",
                        eval_v=f"{np.mean(metrics['eval/forward_velocity']):.2f}",
                        falls=f"{np.mean(metrics['train/falls']):.1f}")
    bar.close()
    return document
