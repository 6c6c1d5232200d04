"""What the robot's senses cost the vmapped env step: the step without sensing, and with the sensor model and
each velocity estimator, at batch 1 and 64 (JT-OEF, forward task, thesis-code).

The sensors' own cost is the step with `integration` (a trivial estimator) less the step without
sensing. Prints a table and writes benchmarks/results/bench_estimators.json.
Run: `python benchmarks/bench_estimators.py [--learned FILE ...]`.
"""

import argparse
import json
from pathlib import Path

import jax
import jax.numpy as jnp

from bench_spine import timed  # the script's own folder is on sys.path
from mjx_badger import estimators, evaluation, results, sensors
from mjx_badger.env import EnvConfig, HB40Env

OUT = Path(__file__).parent / "results" / "bench_estimators.json"
STEPS = 40


def env_steps_per_s(sensing, batch: int, on_robot=None) -> float:
    """Control steps per second of jit(vmap(scan of env.step)) over `batch` robots (`on_robot`: conditions)."""
    env = HB40Env("jt-oef", "forward", EnvConfig(sensing=sensing, conditions=on_robot))
    actions = 0.3 * jnp.sin(jnp.arange(STEPS)[:, None] * 0.2 + jnp.arange(env.action_size))

    def rollout(key):
        # Every leaf made to depend on the key: vmap would otherwise step the key-free physics once for the batch.
        state = evaluation.batched_like(env.reset(key), key)
        return jax.lax.scan(lambda s, a: (env.step(s, a), None), state, actions)[0].obs

    run = jax.jit(jax.vmap(rollout))
    keys = jax.random.split(jax.random.PRNGKey(0), batch)
    return batch * STEPS / timed(run, keys)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--learned", nargs="*", type=Path, default=[], help="fitted estimator files to time too")
    args = parser.parse_args()
    cases = [("none", None)] + [(name, sensors.Sensing(estimator=name)) for name in estimators.ESTIMATORS]
    cases += [(f"learned ({path.name})", sensors.Sensing(estimator="learned", estimator_file=str(path)))
              for path in args.learned]
    rows = {}
    for name, sensing in cases:
        rows[name] = {f"batch_{b}": round(env_steps_per_s(sensing, b), 1) for b in (1, 64)}
        print(f"{name:40s} " + "  ".join(f"batch {b}: {rows[name][f'batch_{b}']:8.1f} env-steps/s" for b in (1, 64)),
              flush=True)
    document = {"what": results.what(__doc__), "date": results.now()[:10], "git_commit": results.git_commit(),
                "hardware": results.hardware(), "unit": "control steps per second (each 5 physics steps at 40 Hz)",
                "env_steps_per_s": rows}
    OUT.write_text(json.dumps(document, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
