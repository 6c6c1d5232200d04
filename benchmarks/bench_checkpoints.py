"""What checkpointing costs a training run: the seconds spent saving the carry beside the training seconds.

    python -m benchmarks.bench_checkpoints [--steps 5000] [--seeds 3]  -> benchmarks/results/checkpoints.json

Trains CrossQ JT-NF forward (thesis-code) with checkpoints as `train` takes them and reads the
results file's wall clock: run_s (chunks) and checkpoint_s (saves), and the size of one checkpoint.
"""

import argparse
import json
import platform
import tempfile
import threading
import time
from pathlib import Path

from benchmarks.common import RESULTS
from mjx_badger.learning import checkpoints, runner
from mjx_badger.learning.config import TrainConfig

OUT = RESULTS / "checkpoints.json"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    config = TrainConfig(approach="jt-nf", algo="crossq", task="forward", total_steps=args.steps)
    sizes = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.json"
        done = threading.Event()

        def watch():  # the size of the newest checkpoint while the run goes
            while not done.wait(1.0):
                steps = [p for p in checkpoints.folder(path).glob("*") if p.name.isdigit()]
                if steps:
                    sizes.append(sum(f.stat().st_size for f in max(steps, key=lambda p: int(p.name)).rglob("*")
                                     if f.is_file()))

        watcher = threading.Thread(target=watch, daemon=True)
        watcher.start()
        document = runner.run(config, list(range(args.seeds)), path, progress=True)
        done.set()
    clock = document["wall_clock"]
    report = {"machine": f"{platform.machine()}, {platform.processor() or 'cpu'}, {document['hardware']['cpu_count']} cores",
              "config": f"CrossQ JT-NF forward thesis-code, {args.seeds} seeds x {args.steps} steps",
              "run_s": clock["run_s"], "checkpoint_s": clock["checkpoint_s"],
              "overhead_percent": round(100 * clock["checkpoint_s"] / clock["run_s"], 2),
              "checkpoint_mib": round(max(sizes) / 2**20, 1) if sizes else None,
              "measured": time.strftime("%Y-%m-%d")}
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(report, indent=1))
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
