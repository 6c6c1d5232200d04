"""Rerun a results file's configuration and seeds with today's code and compare the two number for number.

    python -m tools.rerun_and_compare results/quick/thesis-code/forward/cpg-vf_crossq_forward.json

A refactor that should not change behaviour passes when every metric the two files share and
the gait record are identical; metrics only one of them has (a schema that grew) are listed. Comparisons kept
so far: tools/results/rerun_identical*.json (with --json).
"""

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from mjx_badger.learning import runner
from mjx_badger.learning.config import from_results
from mjx_badger.records import results


def largest_difference(old_rows, new_rows) -> float:
    """The largest absolute difference between two metrics' [chunk][seed] rows (null as NaN; NaN where only one is)."""
    a, b = (np.array(rows, dtype=float) for rows in (old_rows, new_rows))
    if a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
        return float("nan")
    return float(np.nanmax(np.abs(a - b), initial=0.0))


def compare(old: dict, new: dict) -> dict:
    shared = set(old["metrics"]) & set(new["metrics"])
    return {"metrics_shared": len(shared),
            "metrics_differing": {k: largest_difference(old["metrics"][k], new["metrics"][k])
                                  for k in sorted(shared) if old["metrics"][k] != new["metrics"][k]},
            "metrics_in_one_only": sorted(set(old["metrics"]) ^ set(new["metrics"])),
            "gait_identical": old.get("gait") == new.get("gait"), "steps_identical": old["steps"] == new["steps"],
            "old_commit": old.get("git_commit"), "new_commit": new.get("git_commit")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_file", type=Path)
    parser.add_argument("--keep", type=Path, help="a folder to keep the rerun in (its results, policy and agents)")
    parser.add_argument("--json", type=Path, help="also write the comparison here")
    args = parser.parse_args()
    old = results.read(args.results_file)
    with tempfile.TemporaryDirectory() as scratch:
        path = Path(args.keep or scratch) / args.results_file.name
        runner.run(from_results(old), old["seeds"], path, progress=True)
        new = results.read(path)  # as written: JSON's null where the run had NaN, like the old file
    report = {"file": str(args.results_file), **compare(old, new)}
    print(json.dumps(report, indent=1))
    if args.json:
        args.json.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
