"""What a profile's runs cost on this machine, read from their results files: per run wall time, compile,
training and peak memory, and the whole profile in CPU hours beside the estimate `reproduce` printed.
A run's own hours are its compile, training and checkpoint seconds; its wall span (first start to last
update) also counts pauses and, for a resumed run, the time between its attempts. A pause (SIGSTOP) inside
a chunk counts in the chunk's seconds too, as the stopped process's clock runs on: with a pause log, each
run says how long it was paused and, when it ran in one attempt, its own seconds without the pauses
(in a resumed run, a pause of an earlier attempt counts only if that attempt checkpointed after it).

    python -m tools.profile_time RESULTS/full/thesis-code --estimate-h 24.7 --rss-log rss.log \
        --pauses pauses.txt --out tools/results/full_profile_time.json

Pauses: a log of lines "ISO_TIME WORD ...": "START attempt" starts the runs' process; STOP and CONT pause
and continue it; RESTART, STOPPED, session, DONE or exit say it ended. Other lines (other processes)
are skipped. A STOP that no CONT ends (the process was killed while stopped, or a CONT "... only"
continued another) costs no run anything: its unfinished chunk was lost, not counted.

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

from mjx_badger.records import results


def seconds(stamp: str) -> float:
    return datetime.datetime.fromisoformat(stamp).timestamp()


def rss_peaks(log: Path | None, start: float, end: float) -> float | None:
    """The highest resident memory (MiB) sampled in [start, end], or None without samples there."""
    if log is None or not log.exists():
        return None
    found = [int(kib) / 1024 for t, kib in (line.split() for line in log.read_text().splitlines() if len(line.split()) == 2)
             if start <= int(t) <= end]
    return round(max(found), 1) if found else None


def starts_attempt(line: str) -> bool:
    """Whether a pause-log line starts an attempt of the runs' process."""
    return line.partition(" ")[2].startswith("START attempt")


def pause_intervals(lines: list[str]) -> list[tuple[float, float]]:
    """The (stop, cont) times of every SIGSTOP of the runs' process that a SIGCONT ended."""
    intervals, state, stopped = [], "gone", 0.0
    for line in lines:
        stamp, _, rest = line.partition(" ")
        word = rest.split(" ", 1)[0]
        if starts_attempt(line):
            state = "running"
        elif word in ("RESTART", "STOPPED", "session", "DONE", "exit"):
            state = "gone"  # that process ended: a chunk it had not finished was never counted
        elif word == "STOP" and state == "running":
            state, stopped = "stopped", seconds(stamp)
        elif word == "CONT" and state == "stopped" and " only" in rest:
            state = "gone"  # another process went on; this one stayed stopped until it was killed
        elif word == "CONT" and state == "stopped":
            state = "running"
            intervals.append((stopped, seconds(stamp)))
    return intervals


def paused_seconds(intervals, start: float, end: float) -> float:
    """How much of [start, end] the pauses cover."""
    return sum(max(0.0, min(b, end) - max(a, start)) for a, b in intervals)


def attempt_starts(lines: list[str]) -> list[float]:
    """When each attempt of the runs' process started ("START attempt" lines)."""
    return [seconds(line.partition(" ")[0]) for line in lines if starts_attempt(line)]


def run_cost(document: dict, rss_log: Path | None, pauses: list[tuple[float, float]] = (),
             starts: list[float] = ()) -> dict:
    clock = document["wall_clock"]
    start, end = seconds(clock["started"]), seconds(clock["updated"])
    own = round(sum(clock.get(k) or 0.0 for k in results.OWN_SECONDS), 1)
    paused = round(paused_seconds(pauses, start, end), 1)
    one_attempt = not any(start < s < end for s in starts)
    return {"complete": document["complete"], "seeds": len(document["seeds"]), "steps": document["steps"][-1],
            "wall_s": round(end - start, 1), "cost_s": own, "paused_s": paused,
            "cost_s_less_pauses": round(own - paused, 1) if one_attempt else None,
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
    parser.add_argument("--pauses", type=Path, help="pause log of the runs' process (format above)")
    parser.add_argument("--note", default="", help="what else shared the machine (pauses, other jobs)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    log = args.pauses.read_text().splitlines() if args.pauses else []
    pauses, starts = pause_intervals(log), attempt_starts(log)
    runs, first = {}, {}
    for path in sorted(args.folder.glob("*/*.json"), key=lambda p: p.stat().st_mtime):  # a copy after its twin
        name, document = str(path.relative_to(args.folder)), results.read(path)
        runs[name] = run_cost(document, args.rss_log, pauses, starts)
        # reproduce copies a run two experiments share: the copy cost nothing of its own.
        twin = first.setdefault(results.run_key(document), name)
        if twin != name:
            runs[name].update(copy_of=twin, cost_s=0.0, paused_s=0.0, cost_s_less_pauses=0.0)
    runs = dict(sorted(runs.items()))
    done = [r for r in runs.values() if r["complete"] and "copy_of" not in r]
    own_h = sum(r["cost_s"] for r in done) / 3600
    summary = {
        "what": "cost of each run of a profile on this machine, from its results files (tools/profile_time.py)",
        "folder": str(args.folder), "date": datetime.date.today().isoformat(),
        "machine": f"{os.cpu_count()} CPU cores, no GPU", "note": args.note,
        "estimate_line": args.estimate_line, "estimate_h": args.estimate_h,
        "runs_complete": len(done), "runs_copied": sum("copy_of" in r for r in runs.values()),
        "runs_found": len(runs),
        "hours_complete": round(own_h, 2),
        "cpu_hours_complete": round(own_h * (os.cpu_count() or 1), 1),
        "wall_span_h_complete": round(sum(r["wall_s"] for r in done) / 3600, 2),
        "paused_h_complete": round(sum(r["paused_s"] for r in done) / 3600, 2),
        "compile_s_median": statistics.median(r["compile_s"] for r in done) if done else None,
        "training_h_complete": round(sum(r["training_s"] for r in done) / 3600, 2),
        "runs": runs,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(summary, indent=1) + "\n")
    copies = summary["runs_copied"]  # reproduce copies only a complete run
    print(f"{len(done) + copies} of {len(runs)} runs complete ({len(done)} trained, {copies} copied): {own_h:.2f} h of their own"
          + (f" against an estimate of {args.estimate_h:.1f} h for all" if args.estimate_h else "") + f"; wrote {args.out}")


if __name__ == "__main__":
    main()
