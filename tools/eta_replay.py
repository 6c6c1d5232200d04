"""How far `reproduce`'s ETA (mjx_badger/experiments/eta.py) was from the time actually left, replayed on what a
profile's runs cost here: after each run, the ETA from the runs before it against the sum of the rest.

    python -m tools.eta_replay  # -> tools/results/eta_replay.json

quick: the committed results (figures/data/quick/thesis-code), each run's training and compile
seconds; smoke: tools/results/smoke_profile_time.json (a fresh clone's smoke profile).
"""

import argparse
import json
from pathlib import Path

from mjx_badger.experiments import eta
from mjx_badger.records import results

ROOT = Path(__file__).parent.parent


def before(runs: list, updates: list) -> list:
    """The ETA reproduce printed until 2026-12-02: training per gradient update and the rest per run, each at
    the mean of the runs done (copies counted as runs)."""
    out = []
    for k in range(1, len(runs)):
        train_s = sum(spent[0] for _, spent in runs[:k])
        other_s = sum(spent[1] for _, spent in runs[:k])
        done, total = sum(updates[:k]), sum(updates)
        out.append((total - done) * train_s / done + (len(runs) - k) * other_s / k)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "tools" / "results" / "eta_replay.json")
    args = parser.parse_args()
    report = {"what": results.what(__doc__), "git_commit": results.git_commit(), "profiles": {}}
    for profile in ("quick", "smoke"):
        costs = eta.measured_costs(profile, ROOT)
        order = eta.profile_plan(profile)
        runs = [(plan, (0.0, 0.0) if plan.copy else costs[name]) for name, plan, _ in order]
        old = before(runs, [updates for *_, updates in order])
        rows = [{"after_run": k, "eta_s": round(left), "left_s": round(actual), "error": round(left / actual - 1, 3),
                 "before_eta_s": round(old[k - 1]), "before_error": round(old[k - 1] / actual - 1, 3)}
                for k, (left, actual) in enumerate(eta.replay(runs), start=1)]
        summary = {"runs": len(runs), "of": len(rows), "rows": rows}
        for key in ("error", "before_error"):
            worst = max(rows, key=lambda row: abs(row[key]))
            within = sum(abs(row[key]) <= 0.25 for row in rows)
            summary[key.replace("error", "within_25_percent")] = within
            summary[key.replace("error", "worst")] = {"after_run": worst["after_run"], "error": worst[key]}
            print(f"{profile} ({'today' if key == 'error' else 'before'}): ETA within 25 % after {within} of "
                  f"{len(rows)} runs; worst {worst[key]:+.0%} after run {worst['after_run']}")
        report["profiles"][profile] = summary
    args.out.write_text(json.dumps(report, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
