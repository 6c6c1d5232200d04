"""How well `reproduce --profile full`'s estimate predicts a run's rate: per experiment, the seed-steps/s of a
short timed chunk without its evaluation (the estimate up to 2026-12-04), with its evaluation cut in proportion
(since), and of one whole chunk of the run (1,000 learning steps, then the run's own evaluation).

    python -m benchmarks.bench_estimate --out benchmarks/results/estimate_evaluation.json
    python -m benchmarks.bench_estimate --experiments forward --seeds 2 --out /tmp/estimate.json  # a short try

Each rate is its own compiled program's second chunk (programs.measure_speed), so the three differ only in how
much evaluation follows the learning steps. Pause any other training first: this machine has 2 cores.
"""

import argparse
import json
from pathlib import Path

from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.learning import programs
from mjx_badger.records import results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiments", nargs="+", default=["forward-max", "omni-random"], choices=sorted(EXPERIMENTS))
    parser.add_argument("--approach", default="jt-lpf", help="the run of each experiment to time")
    parser.add_argument("--seeds", type=int, default=10, help="vmapped seeds (the full profile's 10)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    for name in args.experiments:  # before anything compiles
        approaches = sorted(r.approach for r in EXPERIMENTS[name].runs)
        if args.approach not in approaches:
            parser.error(f"--approach {args.approach} is not a run of {name}: one of {', '.join(approaches)}")

    seeds, rows = list(range(args.seeds)), []
    for name in args.experiments:
        experiment = EXPERIMENTS[name]
        run = next(r for r in experiment.runs if r.approach == args.approach)
        config = experiment.train_config(run, "full")
        rates = {"without_evaluation": programs.measure_speed(config, seeds),
                 "with_evaluation": programs.measure_speed(config, seeds, evaluation=True),
                 # A chunk as long as the run's has the run's whole evaluation after it.
                 "whole_chunk": programs.measure_speed(config, seeds, config.chunk_steps, evaluation=True)}
        row = {"experiment": name, "run": experiment.result_name(run), "seeds": args.seeds,
               "evaluation_commands": len(config.make_task().eval_commands), "eval_steps": config.eval_steps,
               **{f"{k}_seed_steps_per_s": round(v["seed_steps_per_s"], 1) for k, v in rates.items()},
               **{f"{k}_compile_s": round(v["compile_s"], 1) for k, v in rates.items()}}
        rows.append(row)
        whole = rates["whole_chunk"]["seed_steps_per_s"]
        print(f"{name} {run.approach} x{args.seeds}: " + ", ".join(
            f"{k.replace('_', ' ')} {v['seed_steps_per_s']:.0f} seed-steps/s ({v['seed_steps_per_s'] / whole:.2f} of "
            "the whole chunk's)" for k, v in rates.items() if k != "whole_chunk") + f"; whole chunk {whole:.0f}",
            flush=True)
    document = {"what": results.what(__doc__), "rows": rows, "measured": results.now(),
                "versions": results.versions()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
