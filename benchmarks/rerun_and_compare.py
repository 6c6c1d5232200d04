"""Rerun a results file's configuration and seeds with today's code and compare the two number for number.

    python benchmarks/rerun_and_compare.py results/quick/thesis-code/forward/cpg-vf_crossq_forward.json

A refactor that should not change behaviour passes when every metric the two files share and
the gait record are identical; metrics only one of them has (a schema that grew) are listed.
"""

import argparse
import json
import tempfile
from pathlib import Path

from mjx_badger import results, runner


def compare(old: dict, new: dict) -> dict:
    shared = set(old["metrics"]) & set(new["metrics"])
    return {"metrics_shared": len(shared),
            "metrics_differing": sorted(k for k in shared if old["metrics"][k] != new["metrics"][k]),
            "metrics_in_one_only": sorted(set(old["metrics"]) ^ set(new["metrics"])),
            "gait_identical": old.get("gait") == new.get("gait"), "steps_identical": old["steps"] == new["steps"],
            "old_commit": old.get("git_commit"), "new_commit": new.get("git_commit")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_file", type=Path)
    args = parser.parse_args()
    old = results.read(args.results_file)
    with tempfile.TemporaryDirectory() as folder:
        new = runner.run(results.train_config(old), old["seeds"], Path(folder) / args.results_file.name, progress=True)
    print(json.dumps(compare(old, results.upgrade(new)), indent=1))


if __name__ == "__main__":
    main()
