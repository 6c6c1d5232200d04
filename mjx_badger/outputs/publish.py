"""Complete results copied into a reference folder (the committed `figures/data/`), each with its best seed's policy.

A run's saved policy holds every seed (a few MB at 10 seeds); the copy keeps the best seed's
actor only (`analysis.best_seed`), so `evaluate` and `render` work on the reference results
straight from a clone. Incomplete runs, TensorBoard files and the whole agents stay behind.
"""

import json
from pathlib import Path

from mjx_badger.records import analysis, policy, results


def published(document: dict, path: Path) -> dict:
    """The document as a reference folder keeps it: its policy the best seed's, no agents folder."""
    seed, _ = analysis.best_seed(results.read(path, leave_out_diverged=True))
    kept = {k: v for k, v in document.items() if k != "agents"}
    return dict(kept, published_policy_seeds=[seed])


def publish(source: Path, target: Path) -> list[tuple[Path, str]]:
    """Copy every complete results file under `source` (<experiment>/<run>.json) to the same place under
    `target`, with its best seed's policy; returns (target file, what was done) per file found."""
    done = []
    for path in sorted(Path(source).glob("*/*.json")):
        document = results.read_or_skip(path)
        out = Path(target) / path.relative_to(source)
        if document is None:
            done.append((out, "skipped: cannot be read"))
            continue
        if not document.get("complete"):
            done.append((out, "skipped: incomplete"))
            continue
        before = results.read_or_skip(out) if out.exists() else None
        if before is not None and (before.get("wall_clock") or {}).get("started") == document["wall_clock"]["started"]:
            done.append((out, "unchanged"))
            continue
        if "policy" not in document or not (path.parent / document["policy"]).exists():
            done.append((out, "skipped: no saved policy"))
            continue
        copy = published(document, path)
        policy.keep_seeds(path.parent / document["policy"], out.parent / document["policy"],
                          copy["published_policy_seeds"])
        results.write(out, copy)
        done.append((out, f"published with seed {copy['published_policy_seeds'][0]}'s policy"))
    return done


def attach_policy(reference: Path, rerun: Path) -> int:
    """Give the committed `reference` results file its best seed's policy from `rerun`, a rerun of it
    whose every metric (of those the reference has) and gait record are identical (tools/rerun_and_compare.py): the policy is
    then the one the reference run would have saved. Returns the seed kept; ValueError if they differ."""
    reference, rerun = Path(reference), Path(rerun)
    old, new = results.read(reference), results.read(rerun)
    # The rerun's schema may have grown: every config field and metric the reference has must be in it, the same.
    shared = {name: new["metrics"].get(name) for name in old["metrics"]}
    config = {name: new["config"].get(name) for name in old["config"]}
    for field, mine, theirs in (("config", old["config"], config), ("seeds", old["seeds"], new["seeds"]),
                                ("steps", old["steps"], new["steps"]), ("metrics", old["metrics"], shared),
                                ("gait", old.get("gait"), new.get("gait"))):
        if mine != theirs:
            raise ValueError(f"{rerun} is not a number-for-number rerun of {reference}: its {field} is not the same")
    seed, _ = analysis.best_seed(results.read(reference, leave_out_diverged=True))
    name = reference.with_suffix(".policy.npz").name
    policy.keep_seeds(rerun.parent / new["policy"], reference.parent / name, [seed])
    as_stored = json.loads(reference.read_text())  # not upgraded: the file keeps its own schema and numbers
    results.write(reference, dict(as_stored, policy=name, published_policy_seeds=[seed]))
    return seed
