"""What a profile's runs cost on this machine, read from their results files: per run wall time, compile,
training and peak memory, and the whole profile in CPU hours beside the estimate `reproduce` printed.
A run's own hours are its compile, training and checkpoint seconds; its wall span (first start to last
update) also counts pauses and, for a resumed run, the time between its attempts.

    python benchmarks/profile_time.py RESULTS/full/thesis-code --estimate-h 24.7 --rss-log rss.log \
        --out benchmarks/results/full_profile_time.json

Peak memory: a results file records its process's peak (`hardware.peak_memory_mib`), which for the
second and later runs of one `reproduce` process is the peak so far; with `--rss-log` (lines
"unix_time rss_kib", sampled while the runs went) each run's own peak is read from the samples
between its start and its last update.
"""

import argparse
import datetime
import json
import os
import statistics
from pathlib import Path

from mjx_badger import results


def seconds(stamp: str) -> float:
    return datetime.datetime.fromisoformat(stamp).timestamp()


def rss_peaks(log: Path | None, start: float, end: float) -> float | None:
    """The highest resident memory (MiB) sampled in [start, end], or None without samples there."""
    if log is None or not log.exists():
        return None
    found = [int(kib) / 1024 for t, kib in (line.split() for line in log.read_text().splitlines() if len(line.split()) == 2)
             if start <= int(t) <= end]
    return round(max(found), 1) if found else None


def run_cost(document: dict, rss_log: Path | None) -> dict:
    clock = document["wall_clock"]
    start, end = seconds(clock["started"]), seconds(clock["updated"])
    return {"complete": document["complete"], "seeds": len(document["seeds"]), "steps": document["steps"][-1],
            "wall_s": round(end - start, 1), "cost_s": round(sum(clock.get(k) or 0.0 for k in results.OWN_SECONDS), 1),
            "resumed_at_step": clock.get("resumed_at_step"),
            "compile_s": clock.get("compile_s"), "training_s": clock.get("run_s"),
            "checkpoint_s": clock.get("checkpoint_s"), "seed_steps_per_s": clock.get("seed_steps_per_s"),
            "peak_memory_mib_process": document.get("hardware", {}).get("peak_memory_mib"),
            "peak_memory_mib_sampled": rss_peaks(rss_log, start, end), "git_commit": document.get("git_commit")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="one protocol's results at one profile: <experiment>/<run>.json")
    parser.add_argument("--estimate-h", type=float, help="the estimate reproduce printed before the runs, hours")
    parser.add_argument("--estimate-line", help="that line as printed")
    parser.add_argument("--rss-log", type=Path)
    parser.add_argument("--note", default="", help="what else shared the machine (pauses, other jobs)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    runs, first = {}, {}
    for path in sorted(args.folder.glob("*/*.json"), key=lambda p: p.stat().st_mtime):  # a copy after its twin
        name, document = str(path.relative_to(args.folder)), results.read(path)
        runs[name] = run_cost(document, args.rss_log)
        # reproduce copies a run two experiments share: the copy cost nothing of its own.
        twin = first.setdefault(results.run_key(document), name)
        if twin != name:
            runs[name].update(copy_of=twin, cost_s=0.0)
    runs = dict(sorted(runs.items()))
    done = [r for r in runs.values() if r["complete"] and "copy_of" not in r]
    own_h = sum(r["cost_s"] for r in done) / 3600
    summary = {
        "what": "cost of each run of a profile on this machine, from its results files (benchmarks/profile_time.py)",
        "folder": str(args.folder), "date": datetime.date.today().isoformat(),
        "machine": f"{os.cpu_count()} CPU cores, no GPU", "note": args.note,
        "estimate_line": args.estimate_line, "estimate_h": args.estimate_h,
        "runs_complete": len(done), "runs_copied": sum("copy_of" in r for r in runs.values()),
        "runs_found": len(runs),
        "hours_complete": round(own_h, 2),
        "cpu_hours_complete": round(own_h * (os.cpu_count() or 1), 1),
        "wall_span_h_complete": round(sum(r["wall_s"] for r in done) / 3600, 2),
        "compile_s_median": statistics.median(r["compile_s"] for r in done) if done else None,
        "training_h_complete": round(sum(r["training_s"] for r in done) / 3600, 2),
        "runs": runs,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(summary, indent=1) + "\n")
    print(f"{len(done)} of {len(runs)} runs complete: {own_h:.2f} h of their own"
          + (f" against an estimate of {args.estimate_h:.1f} h for all" if args.estimate_h else "") + f"; wrote {args.out}")


if __name__ == "__main__":
    main()
