"""Memory per seed: the replay buffer and the whole carry (what a checkpoint stores) of every experiment's runs.

    python benchmarks/bench_memory.py  -> benchmarks/results/memory.json

Sizes come from the carry's shapes (`jax.eval_shape` of the run's init: nothing is compiled or
allocated), for the quick and full profiles. A checkpoint stores the carry of every seed, so its
size is at most seeds x carry bytes; the measured size of real checkpoints is printed beside.
"""

import json
import math
from pathlib import Path

import jax

from mjx_badger import checkpoints
from mjx_badger.experiments import EXPERIMENTS, PROFILES
from mjx_badger.train import make_train

OUT = Path(__file__).parent / "results" / "memory.json"
MIB = 2**20


def nbytes(tree) -> int:
    return sum(math.prod(x.shape) * x.dtype.itemsize for x in jax.tree.leaves(tree))


def carry_sizes(config) -> dict:
    """Bytes per seed of the replay buffer, the agent (networks and optimiser states) and the whole carry."""
    carry = jax.eval_shape(make_train(config).init, jax.random.PRNGKey(0))
    return {"replay_bytes": nbytes(carry.buffer), "agent_bytes": nbytes(carry.agent_state),
            "carry_bytes": nbytes(carry)}


def measured_checkpoints(results_dir: Path) -> list[dict]:
    """Size on disk of any checkpoint left under `results_dir` (an interrupted or running run), beside its carry's."""
    from mjx_badger import results

    found = []
    for folder in sorted(Path(results_dir).glob("**/*.ckpt")):
        steps = [p for p in folder.iterdir() if p.name.isdigit()]
        document_path = folder.with_suffix(".json")
        if not steps or not document_path.exists():
            continue
        newest = max(steps, key=lambda p: int(p.name))
        document = results.read(document_path)
        sizes = carry_sizes(results.train_config(document))
        found.append({"run": str(document_path.relative_to(results_dir)), "chunks_done": int(newest.name),
                      "seeds": len(document["seeds"]),
                      "on_disk_mib": round(sum(f.stat().st_size for f in newest.rglob("*") if f.is_file()) / MIB, 1),
                      "carry_mib": round(sizes["carry_bytes"] * len(document["seeds"]) / MIB, 1)})
    return found


def main():
    rows = []
    for profile_name in ("quick", "full"):
        profile = PROFILES[profile_name]
        for experiment in EXPERIMENTS.values():
            for run in experiment.runs:
                config = experiment.train_config(run, profile_name)
                sizes = carry_sizes(config)
                rows.append({"profile": profile_name, "experiment": experiment.name, "approach": run.approach,
                             "algo": run.algo, "steps": config.total_steps, "seeds": profile.seeds, **sizes,
                             "checkpoint_mib": round(sizes["carry_bytes"] * profile.seeds / MIB, 1)})
                print(f"{profile_name:5} {experiment.name:15} {run.approach:6} {run.algo:9} "
                      f"replay {sizes['replay_bytes'] / MIB:6.1f} MiB/seed, carry {sizes['carry_bytes'] / MIB:6.1f} "
                      f"MiB/seed, checkpoint <= {rows[-1]['checkpoint_mib']:7.1f} MiB")
    measured = measured_checkpoints(Path("results"))
    for m in measured:
        print(f"checkpoint on disk: {m['run']} after {m['chunks_done']} chunks: {m['on_disk_mib']} MiB "
              f"(carry {m['carry_mib']} MiB)")
    OUT.write_text(json.dumps({"what": "bytes per seed from the carry's shapes (jax.eval_shape of init), thesis-code "
                                       "protocol; a checkpoint holds every seed's carry",
                               "checkpoints_kept_per_run": checkpoints.KEEP, "runs": rows,
                               "measured_checkpoints": measured}, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
