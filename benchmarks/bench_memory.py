"""Memory per seed: the replay buffer and the whole carry (what a checkpoint stores) of every experiment's runs,
and the estimate the commands check before compiling (memory.py) against the measured peak of real runs.

    python -m benchmarks.bench_memory          -> benchmarks/results/memory.json
    python -m benchmarks.bench_memory --peaks  -> benchmarks/results/memory_peak.json (minutes: two real runs)

Sizes come from the carry's shapes (`jax.eval_shape` of the run's init: nothing is compiled or
allocated), for the quick and full profiles. A checkpoint stores the carry of every seed, so its
size is at most seeds x carry bytes; the measured size of real checkpoints is printed beside.
"""

import argparse
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import jax

from benchmarks.common import RESULTS, ROOT
from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES
from mjx_badger.learning import checkpoints, programs
from mjx_badger.learning.config import from_results
from mjx_badger.learning.train import make_train

OUT = RESULTS / "memory.json"
PEAKS = RESULTS / "memory_peak.json"
MIB = 2**20
# The runs measured: the suite's tiny run whole, and a thesis-length buffer (50k steps) for 16 seeds up to its
# first checkpoint. Every buffer is allocated when the run starts, so the peak is reached by then: the compile,
# the carry, one chunk (its output beside the donated input) and the checkpoint's host copy.
MEASURED = (
    {"what": "tiny run, whole", "seeds": 2, "chunks": None,
     "config": {"approach": "jt-oef", "algo": "crossq", "task": "forward", "total_steps": 300, "chunk_steps": 100,
                "warmup_steps": 100, "eval_steps": 20}},
    {"what": "50k-step buffer x 16 seeds, to its first checkpoint", "seeds": 16, "chunks": 1,
     "config": {"approach": "jt-oef", "algo": "crossq", "task": "forward", "total_steps": 50_000,
                "chunk_steps": 1000, "warmup_steps": 1000}},
)


def nbytes(tree) -> int:
    return sum(math.prod(x.shape) * x.dtype.itemsize for x in jax.tree.leaves(tree))


def carry_sizes(config) -> dict:
    """Bytes per seed of the replay buffer, the agent (networks and optimiser states) and the whole carry."""
    carry = jax.eval_shape(make_train(config).init, jax.random.PRNGKey(0))
    return {"replay_bytes": nbytes(carry.buffer), "agent_bytes": nbytes(carry.agent_state),
            "carry_bytes": nbytes(carry)}


def measured_checkpoints(results_dir: Path) -> list[dict]:
    """Size on disk of any checkpoint left under `results_dir` (an interrupted or running run), beside its carry's."""
    from mjx_badger.records import results

    found = []
    for folder in sorted(Path(results_dir).glob("**/*.ckpt")):
        steps = [p for p in folder.iterdir() if p.name.isdigit()]
        document_path = folder.with_suffix(".json")
        if not steps or not document_path.exists():
            continue
        newest = max(steps, key=lambda p: int(p.name))
        document = results.read(document_path)
        sizes = carry_sizes(from_results(document))
        found.append({"run": str(document_path.relative_to(results_dir)), "chunks_done": int(newest.name),
                      "seeds": len(document["seeds"]),
                      "on_disk_mib": round(sum(f.stat().st_size for f in newest.rglob("*") if f.is_file()) / MIB, 1),
                      "carry_mib": round(sizes["carry_bytes"] * len(document["seeds"]) / MIB, 1)})
    return found


def child(spec: dict) -> dict:
    """In a fresh process: the run of `spec` (whole, or up to its first checkpoint) and this process's peak memory."""
    from mjx_badger.learning import memory, runner
    from mjx_badger.learning.config import TrainConfig
    from mjx_badger.records import results

    config, seeds = TrainConfig(**spec["config"]), list(range(spec["seeds"]))
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "run.json"
        if spec["chunks"] is None:
            runner.run(config, seeds, out, progress=False, tensorboard=False)
        else:
            carry, chunk, _ = programs.compiled(make_train(config), seeds)
            for index in range(spec["chunks"]):
                carry, _ = jax.block_until_ready(chunk(carry, index * config.chunk_steps))
            checkpoints.Checkpoints(out, {"seeds": seeds}).save(spec["chunks"], carry)
    return {"peak_mib": round(results.peak_memory_mib(), 1), "estimate_mib": round(memory.estimate(config, len(seeds)) / MIB, 1),
            "carry_mib_per_seed": round(memory.carry_sizes(config)["carry_bytes"] / MIB, 2)}


def peaks() -> None:
    """Each run of MEASURED in its own process: estimate against measured peak, to benchmarks/results/memory_peak.json."""
    from mjx_badger.learning import memory

    rows = []
    for spec in MEASURED:
        done = subprocess.run([sys.executable, "-m", "benchmarks.bench_memory", "--child", json.dumps(spec)], cwd=ROOT,
                              capture_output=True, text=True)
        if done.returncode:
            raise SystemExit(done.stderr[-3000:])
        found = json.loads(done.stdout.strip().splitlines()[-1])
        rows.append({**spec, **found, "estimate_over_peak": round(found["estimate_mib"] / found["peak_mib"], 2)})
        print(f"{spec['what']}: peak {found['peak_mib']:.0f} MiB, estimate {found['estimate_mib']:.0f} MiB "
              f"(x{rows[-1]['estimate_over_peak']})", flush=True)
    from mjx_badger.records import results

    PEAKS.write_text(json.dumps({
        "what": "peak resident memory of a process running each run (ru_maxrss) against memory.estimate, which "
                "`train`, `sweep` and `reproduce` check before compiling: the carry's bytes x CARRY_COPIES + "
                "OVERHEAD_BYTES", "carry_copies": memory.CARRY_COPIES, "overhead_mib": memory.OVERHEAD_BYTES / MIB,
        "machine": results.hardware(), "git_commit": results.git_commit(), "date": results.now(), "runs": rows},
        indent=1) + "\n")
    print(f"wrote {PEAKS}")


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
    parser = argparse.ArgumentParser()
    parser.add_argument("--peaks", action="store_true", help="measure the peak memory of real runs (minutes)")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.child:
        print(json.dumps(child(json.loads(options.child))))
    elif options.peaks:
        peaks()
    else:
        main()
