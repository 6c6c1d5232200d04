"""Does pretraining in MJX cut on-robot falls and time? The on-robot loop on the simulated HB40, from scratch and from a sim-trained agent.

    python -m benchmarks.bench_pretrained [--results RESULTS.json] [--runs 3] [--steps 10000]
        -> benchmarks/results/pretrained.json and pretrained.png

Each run is `realtime` as a user runs it: 40 Hz wall clock, CrossQ learning beside the robot,
the Kalman estimator's velocity in the observation and the reward, sensor noise, safety stops
with a 2 s manual reset. Run k from scratch uses seed k; run k pretrained starts from seed k of
`--results` (a thesis-text JT-OEF CrossQ forward run with saved agents) and learns on. The
command is `--target` m/s forward. Times are training seconds (resets excluded) until the
trunk's true forward velocity, averaged over the last 2 s, first reaches 90 % of 0.25 and of
0.5 m/s (the 90 % the simulation claims use, analysis.REACHED_FRACTION).
"""

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from benchmarks.common import RESULTS
from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.estimation import sensors
from mjx_badger.realtime import loop, report
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.report import load_trace
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.records import results
from mjx_badger.records.analysis import REACHED_FRACTION

OUT = RESULTS / "pretrained.json"
DEFAULT_RESULTS = Path("results/quick/thesis-text/forward/jt-oef_crossq_forward.json")
THRESHOLDS = (0.25, 0.5)
WINDOW_S = 2.0


def first_reached(train_s: np.ndarray, velocity: np.ndarray, threshold: float, hz: float) -> float | None:
    """Training seconds when the trailing WINDOW_S mean of `velocity` first reaches 90 % of `threshold`."""
    window = int(round(WINDOW_S * hz))
    if len(velocity) < window:
        return None
    mean = np.convolve(velocity, np.ones(window) / window, mode="valid")
    hits = np.flatnonzero(mean >= REACHED_FRACTION * threshold)
    return None if hits.size == 0 else round(float(train_s[hits[0] + window - 1]), 1)


def one_run(config: RealtimeConfig, folder: Path) -> dict:
    bot = SimulatedHB40(noise=sensors.SensorModel(), reset_seconds=2.0, seed=config.seed, spec=config.robot_spec)
    document = loop.run(config, bot, folder, resume=False, view=False)
    trace = load_trace(folder, config)
    train_s, true_vx = report.column(trace, "train_s"), report.column(trace, "true_vx")
    falls_at = train_s[report.column(trace, "fall") > 0]
    reached = {f"seconds_to_{t}": first_reached(train_s, true_vx, t, config.hz) for t in THRESHOLDS}
    per_second = [round(float(np.mean(true_vx[(train_s >= s) & (train_s < s + 1)])), 3)
                  for s in range(int(train_s[-1]))]
    return {"seed": config.seed, "init_seed": config.init_seed if config.init_from else None,
            **reached, "falls": document["falls"],
            **{f"falls_before_{t}": (None if reached[f"seconds_to_{t}"] is None
                                     else int(np.sum(falls_at <= reached[f"seconds_to_{t}"]))) for t in THRESHOLDS},
            "train_minutes": document["train_minutes"], "updates_per_learning_step": document["updates_per_learning_step"],
            "missed_deadlines": document["timing"]["missed_deadlines"], "scheduling": document["timing"]["scheduling"],
            "evaluation": document["evaluation"], "true_velocity_per_second": per_second}


def summary(runs: list[dict]) -> dict:
    """Mean falls, and per threshold how many runs reached it and their median time."""
    out = {"runs": len(runs), "falls_mean": round(float(np.mean([r["falls"] for r in runs])), 2),
           "falls": [r["falls"] for r in runs]}
    for t in THRESHOLDS:
        times = [r[f"seconds_to_{t}"] for r in runs if r[f"seconds_to_{t}"] is not None]
        out[f"reached_{t}"] = f"{len(times)} of {len(runs)}"
        out[f"median_seconds_to_{t}"] = None if not times else float(np.median(times))
    return out


def figure(document: dict, out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4), constrained_layout=True)
    for mode, color in (("scratch", "tab:gray"), ("pretrained", "tab:blue")):
        for i, run in enumerate(document[mode]["runs"]):
            v = np.asarray(run["true_velocity_per_second"], dtype=float)
            ax.plot(np.arange(len(v)) / 60, v, color=color, lw=1, alpha=0.8,
                    label=f"{mode} (falls {document[mode]['summary']['falls']})" if i == 0 else None)
    for t in THRESHOLDS:
        ax.axhline(t, color="k", ls="--", lw=0.8)
    ax.set_xlabel("training minutes on the simulated robot (resets excluded)")
    ax.set_ylabel("true forward velocity, 1 s means [m/s]")
    ax.set_title(f"On-robot learning from scratch vs from an MJX-trained agent, simulated HB40\n{document['setup']}",
                 fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, default=DEFAULT_RESULTS)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--target", type=float, default=0.5)
    parser.add_argument("--modes", nargs="+", default=["scratch", "pretrained"])
    parser.add_argument("--warmup-steps", type=int, default=1000, help="random actions from scratch (the thesis's)")
    parser.add_argument("--pretrained-warmup-steps", type=int, default=256,
                        help="steps of the pretrained policy's own actions before learning: one batch")
    args = parser.parse_args()
    enable_compilation_cache()
    trained = results.read(args.results)
    base = dict(approach=trained["config"]["approach"], algo=trained["config"]["algo"], task="forward",
                target_velocity=args.target, steps=args.steps)
    document = json.loads(OUT.read_text()) if OUT.exists() else {}
    document.update(setup=f"{base['algo']} {base['approach']}, command {args.target} m/s, {args.steps} steps per run, "
                          "estimator in the loop, sensor noise", pretrained_from=str(args.results),
                    pretrained_run=results.left_out_words(trained) or f"{len(trained['seeds'])} seeds x "
                    f"{trained['steps'][-1]} steps, {trained['config']['protocol']}")
    for mode in args.modes:
        runs = []
        for k in range(args.runs):
            extra = dict(init_from=str(args.results), init_seed=trained["seeds"][k % len(trained["seeds"])],
                         warmup_steps=args.pretrained_warmup_steps) if mode == "pretrained" else dict(
                warmup_steps=args.warmup_steps)
            config = RealtimeConfig(**base, seed=k, **extra)
            with tempfile.TemporaryDirectory() as folder:
                runs.append(one_run(config, Path(folder)))
            r = runs[-1]
            print(f"{mode} run {k}: falls {r['falls']}, 0.25 m/s at {r['seconds_to_0.25']} s, "
                  f"0.5 m/s at {r['seconds_to_0.5']} s, {r['updates_per_learning_step']} updates/step", flush=True)
        document[mode] = {"runs": runs, "summary": summary(runs)}
        document.update(versions=results.versions(), git_commit=results.git_commit(), hardware=results.hardware(),
                        updated=results.now())
        OUT.write_text(json.dumps(document, indent=1) + "\n")
    if all(m in document for m in ("scratch", "pretrained")):
        print(f"figure: {figure(document, OUT.with_suffix('.png'))}")
    print(json.dumps({m: document[m]["summary"] for m in ("scratch", "pretrained") if m in document}, indent=1))


if __name__ == "__main__":
    main()
