"""Trained policies on native MuJoCo against the MJX training env: the same policy, start and command on both engines.

    python docs/cli/native_vs_mjx.py RESULTS.json ... [--seconds 10]  -> docs/cli/native_vs_mjx.json

For every seed of every results file with a saved policy: velocity along and across the command,
yaw rate, falls and gait frequency from `evaluate --engine native` and `--engine mjx`
(native.run_native / run_mjx), and their differences. tests/sim/test_native.py holds a fixed
random policy to 0.03 m/s, 0.1 rad/s and 0.3 Hz; this is the same comparison for trained ones,
where a gait on the edge of falling can make the engines part ways.
"""

import argparse
import json
from pathlib import Path

from mjx_badger.learning.config import from_results
from mjx_badger.records import policy, results
from mjx_badger.sim import native

OUT = Path(__file__).with_suffix(".json")
COMPARED = ("velocity_along_command", "velocity_across_command", "yaw_rate", "falls", "gait_hz")


def compare(path: Path, seconds: float) -> list[dict]:
    document = results.read(path, leave_out_diverged=True)
    env = native.evaluation_env(from_results(document), seconds)
    command = list(next(iter(env.task.eval_commands.values())))
    rows = []
    for seed in document["seeds"]:
        actor = policy.load(path.parent / document["policy"], seed)
        mjx, nat = (run(env, actor, command, seconds) for run in (native.run_mjx, native.run_native))
        rows.append({"run": path.name, "protocol": document["config"]["protocol"], "seed": seed, "command": command,
                     **{f"mjx_{k}": mjx.get(k) for k in COMPARED}, **{f"native_{k}": nat.get(k) for k in COMPARED}})
        print({k: (round(v, 3) if isinstance(v, float) else v) for k, v in rows[-1].items()}, flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_files", type=Path, nargs="+")
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    rows = [row for path in args.results_files for row in compare(path, args.seconds)]
    OUT.write_text(json.dumps({"seconds": args.seconds, "rows": rows, "git_commit": results.git_commit(),
                               "hardware": results.hardware(), "updated": results.now()}, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
