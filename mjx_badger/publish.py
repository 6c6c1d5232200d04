"""Complete results copied into a reference folder (the committed `figures/data/`), each with its best seed's policy.

A run's saved policy holds every seed (a few MB at 10 seeds); the copy keeps the best seed's
actor only (`analysis.best_seed`), so `evaluate` and `render` work on the reference results
straight from a clone. Incomplete runs, TensorBoard files and the whole agents stay behind.
"""

from pathlib import Path

from mjx_badger import analysis, policy, results


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
        document = results.read(path)
        out = Path(target) / path.relative_to(source)
        if not document.get("complete"):
            done.append((out, "skipped: incomplete"))
            continue
        if out.exists() and results.read(out).get("wall_clock", {}).get("started") == document["wall_clock"]["started"]:
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
    whose every metric and gait record are identical (benchmarks/rerun_and_compare.py): the policy is
    then the one the reference run would have saved. Returns the seed kept; ValueError if they differ."""
    old, new = results.read(reference), results.read(rerun)
    for field in ("config", "seeds", "steps", "metrics", "gait"):
        if old.get(field) != new.get(field):
            raise ValueError(f"{rerun} is not a number-for-number rerun of {reference}: its {field} is not the same")
    seed, _ = analysis.best_seed(results.read(reference, leave_out_diverged=True))
    name = Path(reference).with_suffix(".policy.npz").name
    policy.keep_seeds(Path(rerun).parent / new["policy"], Path(reference).parent / name, [seed])
    results.write(reference, dict(old, policy=name, published_policy_seeds=[seed]))
    return seed
