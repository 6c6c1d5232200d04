"""What the robot's senses cost the vmapped env step: the step without sensing, and with the sensor model and
each velocity estimator, at batch 1 and 64 (JT-OEF, forward task, thesis-code).

The sensors' own cost is the step with `integration` (a trivial estimator) less the step without
sensing. Prints a table and writes benchmarks/results/bench_estimators.json.
Run: `python -m benchmarks.bench_estimators [--learned FILE ...]`.
"""

import argparse
import json
from pathlib import Path

from benchmarks.common import RESULTS, env_steps_per_s
from mjx_badger.estimation import estimators, sensors
from mjx_badger.records import results

OUT = RESULTS / "bench_estimators.json"


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
