"""The office-trained JT-OEF policy tested elsewhere, as the thesis tested its office policy in simulation (§5.2.1:
1.5 m/s there, 0.85 on the robot): each saved seed for 20 s on native MuJoCo under the office conditions it trained in,
the office with the true velocity in its observation, and the simulation's conditions.

Writes docs/real-world/office_policy_in_simulation.json. Run:
`python docs/real-world/office_policy_in_simulation.py [RESULTS_FILE]` (default: the committed quick run, best seed only;
a run of your own under results/ has every seed's policy).
"""

import dataclasses
import json
import math
import sys
from pathlib import Path

from mjx_badger.learning.config import from_results
from mjx_badger.records import policy, results
from mjx_badger.sim import native

DEFAULT = Path("figures/data/quick/thesis-code/real-office/jt-oef_crossq_forward.json")
OUT = Path(__file__).with_suffix(".json")
SECONDS = 20.0
TESTS = (("office, as trained", "office", ()),
         ("office, true velocity observed", "office", (("estimate_in_loop", False),)),
         ("simulation's conditions", "sim", ()))


def test(path: Path, seed: int, conditions: str, changes: tuple) -> dict:
    """One seed's policy for SECONDS under `conditions` with `changes`: speeds along and across the command, falls."""
    document = results.read(path)
    actor = policy.load(path.parent / document["policy"], seed)
    config = dataclasses.replace(from_results(document), conditions=conditions, condition_changes=changes)
    env = native.evaluation_env(config, SECONDS)
    report = native.run_native(env, actor, list(next(iter(env.task.eval_commands.values()))), SECONDS)
    along, across = report["velocity_along_command"], report["velocity_across_command"]
    return {"along": along, "planar": math.hypot(along, across), "falls": report["falls"],
            "yaw_rate": report["yaw_rate"]}


def main(path: Path) -> None:
    document = results.read(path)
    seeds = policy.load(path.parent / document["policy"]).meta["seeds"]
    rows = {label: {seed: test(path, seed, conditions, changes) for seed in seeds} for label, conditions, changes in TESTS}
    for label, by_seed in rows.items():
        print(f"{label:34s} " + "  ".join(f"seed {s}: {r['along']:+.2f} along, {r['planar']:.2f} planar m/s, "
                                         f"{r['falls']} falls" for s, r in by_seed.items()))
    OUT.write_text(json.dumps({"source": str(path), "git_commit": document.get("git_commit"), "seconds": SECONDS,
                               "engine": "native", "note": "along: net displacement along the command / time (a turning "
                               "robot covers less); planar: net displacement in any direction / time", "tests": rows},
                              indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else DEFAULT)
