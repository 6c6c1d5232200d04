"""The full profile's wall time on a cluster of 1, 4 and 25 nodes like this 2-core CPU, one or two runs per node, from the committed full runs' own clocks.

    python -m tools.cluster_plan                      # prints the table, writes tools/results/cluster_plan.json

Each unique run of the full profile (thesis-code) costs its committed compile and training seconds (run_s, as
measured on this machine; a run shared by two experiments is trained once). Runs go to nodes longest first (each
to the node that frees first); with two runs per node each run is slower by the factor measured here with
`reproduce --runs-per-device 2` beside one run at a time (`--share-slowdown`). The bound of each row is named: the
whole work spread over the nodes, or the longest single run, which no number of nodes shortens (its 50k control
steps are sequential).
"""

import argparse
import heapq
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FULL = ROOT / "figures" / "data" / "full" / "thesis-code"
OUT = ROOT / "tools" / "results" / "cluster_plan.json"
SHARE_SLOWDOWN = 1.21
"""A run's time with a second run on the same 2-core node over its time alone: smoke-size real-outdoor-omni runs,
`reproduce --runs-per-device 2` (22.2 and 23.2 s) beside one after the other (19.0 and 18.6 s), this machine."""


def run_costs(folder: Path = FULL) -> dict:
    """Seconds (compile + training) of each unique full run, by configuration, from the committed results."""
    costs = {}
    for path in sorted(folder.glob("*/*.json")):
        document = json.loads(path.read_text())
        key = json.dumps(document["config"], sort_keys=True)
        clock = document["wall_clock"]
        costs.setdefault(key, (f"{path.parent.name}/{path.stem}", clock["compile_s"] + clock["run_s"]))
    return dict(costs.values())


def makespan(seconds: list[float], slots: int) -> float:
    """Longest-first onto whichever slot frees first: the time the last one ends."""
    free = [0.0] * slots
    for cost in sorted(seconds, reverse=True):
        heapq.heappush(free, heapq.heappop(free) + cost)
    return max(free)


def plan(costs: dict, nodes: tuple, slowdown: float) -> list[dict]:
    rows, longest = [], max(costs.values())
    for count in nodes:
        for per_node in (1, 2):
            factor = 1.0 if per_node == 1 else slowdown
            hours = makespan([c * factor for c in costs.values()], count * per_node) / 3600
            bound = "the longest run" if abs(hours - longest * factor / 3600) < 1e-6 else "the work over the nodes"
            rows.append({"nodes": count, "runs_per_node": per_node, "wall_h": round(hours, 2), "bound": bound,
                         "node_hours": round(count * hours, 1)})
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[1, 4, 25])
    parser.add_argument("--share-slowdown", type=float, default=SHARE_SLOWDOWN)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    costs = run_costs()
    rows = plan(costs, tuple(args.nodes), args.share_slowdown)
    longest = max(costs, key=costs.get)
    document = {"what": __doc__.split("\n\n")[0].replace("\n", " "), "runs": len(costs),
                "total_h": round(sum(costs.values()) / 3600, 1), "longest_run": longest,
                "longest_run_h": round(costs[longest] / 3600, 2),
                "share_slowdown": args.share_slowdown, "rows": rows}
    print(f"{len(costs)} unique full runs, {document['total_h']} h of this CPU in all; the longest, {longest}, "
          f"{document['longest_run_h']} h")
    print("| nodes | runs per node | wall time | bound by |\n|---|---|---|---|")
    for row in rows:
        print(f"| {row['nodes']} | {row['runs_per_node']} | {row['wall_h']:.1f} h | {row['bound']} |")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
