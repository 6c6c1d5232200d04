"""What each on-robot condition costs the vmapped env step: sim, office, outdoor (cobblestones, feet only), outdoor
on flat ground, and outdoor with the calves also colliding with the stones (a height field's cost grows with
(geom size / cell)^2), at batch 1 and 64 (JT-OEF, forward task, thesis-code).

Prints a table and writes benchmarks/results/bench_conditions.json. Run: `python -m benchmarks.bench_conditions`.
"""

import json

from benchmarks.common import RESULTS, env_steps_per_s
from mjx_badger.protocol import conditions
from mjx_badger.records import results

OUT = RESULTS / "bench_conditions.json"
CASES = {
    "sim": None,
    "office": conditions.OFFICE,
    "outdoor (cobblestones, feet collide)": conditions.OUTDOOR,
    "outdoor on flat ground": conditions.OUTDOOR.replace(**{"ground.terrain": "flat"}),
    "outdoor, calves collide too": conditions.OUTDOOR.replace(**{"ground.contacts": ("calf", "foot")}),
}


def main():
    rows = {}
    for name, on_robot in CASES.items():
        rows[name] = {f"batch_{b}": round(env_steps_per_s(None, b, on_robot), 1) for b in (1, 64)}
        print(f"{name:40s} " + "  ".join(f"batch {b}: {rows[name][f'batch_{b}']:8.1f} env-steps/s" for b in (1, 64)),
              flush=True)
    document = {"what": results.what(__doc__), "date": results.now()[:10], "git_commit": results.git_commit(),
                "hardware": results.hardware(), "unit": "control steps per second (40 or 50 Hz, 200 Hz physics)",
                "env_steps_per_s": rows}
    OUT.write_text(json.dumps(document, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
