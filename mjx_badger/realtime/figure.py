"""The figure of an on-robot run, from its results document and per-step trace (report.py's schema)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mjx_badger.core import safe_io
from mjx_badger.realtime.report import column  # noqa: E402


def _rolling(x, window: int):
    """Trailing mean over `window` samples (shorter at the start)."""
    cumulative = np.cumsum(np.insert(np.asarray(x, np.float64), 0, 0.0))
    index = np.arange(1, len(x) + 1)
    return (cumulative[index] - cumulative[np.maximum(index - window, 0)]) / np.minimum(index, window)


def draw(document: dict, trace: np.ndarray, out: Path) -> Path:
    """An on-robot run: velocity (estimated and true) over training time with the falls, the
    estimator's bias over ten seconds (as thesis Fig 2.1), and the control-period spread."""
    config, timing = document["config"], document["timing"]
    hz = config["hz"]
    true, estimated = column(trace, "true_vx"), column(trace, "estimated_vx")
    minutes = column(trace, "train_s") / 60
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2), gridspec_kw={"width_ratios": [2.2, 1.6, 1.2]})
    ax = axes[0]
    window = int(5 * hz)
    ax.plot(minutes, _rolling(true, window), color="tab:blue", lw=1.6, label="true (simulator)")
    ax.plot(minutes, _rolling(estimated, window), color="tab:orange", lw=1.6, label="estimated (Kalman)")
    if config["task"] == "forward":
        ax.axhline(config["target_velocity"], color="k", ls="--", lw=1, label=f"target {config['target_velocity']} m/s")
    for fall_minute in minutes[column(trace, "fall") > 0]:
        ax.axvline(fall_minute, color="tab:red", alpha=0.25, lw=0.8)
    ax.plot([], [], color="tab:red", alpha=0.5, label=f"safety stop ({document['falls']})")
    ax.set_xlabel("training minutes (resets excluded)")
    ax.set_ylabel("forward velocity [m/s], 5 s mean")
    ax.set_title(f"{config['algo']} {config['approach']} on the simulated HB40, {hz:g} Hz", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)

    ax = axes[1]
    last = slice(-int(10 * hz), None)
    seconds = column(trace, "train_s")[last] - column(trace, "train_s")[last][0]
    ax.plot(seconds, true[last], color="tab:blue", lw=1.2, label="true")
    ax.plot(seconds, estimated[last], color="tab:orange", lw=1.2, label="estimated")
    bias = np.nanmean(estimated[last] - true[last])
    ax.set_title(f"last 10 s of training: estimate - truth = {bias:+.3f} m/s", fontsize=10)
    ax.set_xlabel("seconds")
    ax.set_ylabel("forward velocity [m/s]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)

    ax = axes[2]
    histogram = timing["period_histogram"]
    edges = np.asarray(histogram["edges_ms"])
    ax.bar(edges[:-1], histogram["counts"], width=np.diff(edges), align="edge", color="tab:gray")
    ax.axvline(timing["nominal_period_ms"], color="k", ls="--", lw=1)
    ax.set_yscale("log")
    ax.set_xlabel("control period [ms]")
    ax.set_title(f"p50 {timing['period_p50_ms']:.2f} ms, p99 error {timing['period_error_p99_ms']:.2f} ms, "
                 f"{timing['missed_deadlines']} late" if timing["period_p50_ms"] is not None
                 else "no control period timed in this session", fontsize=10)
    outside = histogram["below"] + histogram["above"]
    notes = [f"largest period error {timing['period_error_max_ms']:.1f} ms"]
    if outside:
        notes.insert(0, f"{outside} periods outside the axis")
    if timing.get("scheduling"):
        notes.append(f"control thread: {timing['scheduling']}")
    ax.text(0.02, 0.95, "\n".join(notes), transform=ax.transAxes, fontsize=8, va="top")
    evaluation = document.get("evaluation") or {}
    summary = (f"{document['steps']} steps, {document['train_minutes']:.1f} min training "
               f"({document['minutes_with_resets']:.1f} with resets), {document['falls']} falls, "
               f"{document['updates_per_learning_step']:.2f} updates per learning step")
    if evaluation.get("true_velocity") is not None:
        summary += f"; evaluation {evaluation['true_velocity']:.2f} m/s mean"
        # No best second when the evaluation ended (a fall) before its first second.
        if evaluation.get("true_peak_1s") is not None:
            summary += f", {evaluation['true_peak_1s']:.2f} m/s best second"
    if evaluation.get("fell"):
        summary += f"; fell after {evaluation['seconds']:.1f} s ({evaluation['fell']})"
    fig.suptitle(summary, fontsize=10)
    fig.tight_layout()
    try:
        safe_io.save_figure(fig, out, dpi=110)
    finally:
        plt.close(fig)
    return out
