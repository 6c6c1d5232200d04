"""What an on-robot run reports: the results document with its timing summary, and the per-step trace.

Schema `mjx_badger.realtime/1`, the document `loop.run` writes to <out>/<approach>_<algo>_<task>.json:
    schema                     "mjx_badger.realtime/1"
    config                     the RealtimeConfig, its agent settings resolved, and hz, the control rate it ran at
    complete                   whether all config.steps were taken (false after Ctrl-C; the next run resumes)
    steps                      transitions stored, over this session and those it resumed
    falls                      safety trips, each of which damped the motors and ended its episode
    episodes                   episodes ended, by a safety trip, the time limit, the operator or a lost link
    link_gaps                  episodes a lost link ended (no reply in time, or the robot damped itself)
    gap_minutes                wall-clock minutes spent waiting for the robot after them (not training time)
    train_minutes              wall-clock minutes of control, the operator's resets excluded
    minutes_with_resets        the same with the resets
    updates                    learner updates
    updates_per_learning_step  updates per step after the warm-up
    timing                     this session's control ticks: a period runs from one tick's start to the next,
                               wake is how long after its deadline a tick started (the scheduler and the GIL),
                               work from a tick's start to its sleep (read, estimate, act, command, store):
      nominal_period_ms          1000 / hz
      period_p50_ms, _p99_ms     period percentiles (null before the second tick)
      period_error_*_ms          p50, p99 and max of |period - nominal|
      missed_deadlines           ticks whose work ran past the next tick's start, so that their command was late
      ticks                      control ticks, each episode's first (which stores nothing) included
      work_p50_ms, _p99_ms, _max_ms
      wake_p99_ms, wake_max_ms
      worst_periods              the five farthest from nominal: step, period_ms, wake_ms, unix_time
      scheduling                 FIFO_LABEL where the control thread ran in SCHED_FIFO, else ORDINARY_LABEL
      memory_locked              whether the process's pages were locked in memory
      major_page_faults          page faults that waited for the disk during the session
      period_histogram           edges_ms and counts around the nominal period; below, above: the outliers
    rows                       every LOG_EVERY_STEPS steps: step, train_minutes, and means over those steps
                               of estimated_velocity, true_velocity (null without a ground truth) and reward;
                               falls, updates so far
    evaluation                 the deterministic run after training, null if incomplete or eval_seconds is 0:
                               seconds, fell (the trip or null), estimated_velocity, true_velocity (means),
                               true_peak_1s (best one-second mean of the true velocity)
    link                       null in-process; over a link: address, requests, round_trip_p50_ms, _p99_ms, _max_ms
                               (one request and its reply, this session), robot_damps (the robot's own damps)
    wall_clock                 started / updated (ISO 8601), compile_s
    versions                   python and package versions
    git_commit                 commit of the code that ran, "+dirty" when it had local changes
    hardware                   platform, cpu count, jax devices, peak resident memory (MiB)

The trace, <out>/<name>.trace.npy, float32 (steps, len(TRACE)), one row per stored step:
    step                       the step's number, from 1
    train_s                    training seconds when it was stored (resets excluded)
    estimated_vx, estimated_vy the estimator's trunk-frame velocity (m/s)
    true_vx, true_vy           the true one (NaN where the robot has no ground truth)
    reward                     the task's reward of the step
    fall                       1 where a safety trip ended the episode, else 0
"""

import time
from pathlib import Path

import numpy as np

from mjx_badger.core import safe_io
from mjx_badger.records import results

SCHEMA = "mjx_badger.realtime/1"
LOG_EVERY_STEPS = 200
"""Steps per row of the results document (5 s at 40 Hz)."""
TRACE = ("step", "train_s", "estimated_vx", "estimated_vy", "true_vx", "true_vy", "reward", "fall")
"""Columns of the per-step trace saved beside the results document (<name>.trace.npy)."""
FIFO_LABEL = "SCHED_FIFO"
ORDINARY_LABEL = "ordinary, compute threads niced"


def column(trace: np.ndarray, name: str) -> np.ndarray:
    """One TRACE column of trace rows."""
    return trace[:, TRACE.index(name)]


def timing_log(fifo: bool, locked: bool, page_faults: int) -> dict:
    """The per-tick timing record of a session, filled in by the control loop; `major_page_faults`
    holds the count at the start until the session ends and it becomes the difference."""
    return {"periods": [], "wake": [], "at_step": [], "at_time": [], "work": [], "late": 0, "ticks": 0,
            "scheduling": FIFO_LABEL if fifo else ORDINARY_LABEL, "memory_locked": locked,
            "major_page_faults": page_faults}


def row(progress, updates: int) -> dict:
    """One results row: means over the last LOG_EVERY_STEPS steps."""
    recent = progress.trace[max(progress.step - LOG_EVERY_STEPS, 0):progress.step]
    true = column(recent, "true_vx")
    return {"step": progress.step, "train_minutes": progress.train_seconds / 60,
            "estimated_velocity": float(column(recent, "estimated_vx").mean()),
            "true_velocity": float(np.nanmean(true)) if np.isfinite(true).any() else None,
            "reward": float(column(recent, "reward").mean()), "falls": progress.falls, "updates": updates}


def document(config, progress, timing, updates, compile_s, started, complete, evaluation, link=None) -> dict:
    """The results document of a run (the schema above)."""
    periods = np.asarray(timing["periods"]) * 1000
    work = np.asarray(timing["work"]) * 1000
    wake = np.asarray(timing["wake"]) * 1000
    nominal = 1000 / config.hz
    error = np.abs(periods - nominal) if len(periods) else np.zeros(1)
    worst = np.argsort(error)[::-1][:5] if len(periods) else []
    learning_steps = max(progress.step - config.warmup_steps, 1)
    return {
        "schema": SCHEMA,
        "config": dict(config.as_dict(), hz=config.hz),
        "complete": complete,
        "steps": progress.step,
        "falls": progress.falls,
        "episodes": progress.episodes,
        "link_gaps": progress.gaps,
        "gap_minutes": progress.gap_seconds / 60,
        "train_minutes": progress.train_seconds / 60,
        "minutes_with_resets": (progress.train_seconds + progress.reset_seconds) / 60,
        "updates": updates,
        "updates_per_learning_step": updates / learning_steps,
        "timing": {
            "nominal_period_ms": nominal,
            "period_p50_ms": float(np.percentile(periods, 50)) if len(periods) else None,
            "period_p99_ms": float(np.percentile(periods, 99)) if len(periods) else None,
            "period_error_p50_ms": float(np.percentile(error, 50)),
            "period_error_p99_ms": float(np.percentile(error, 99)),
            "period_error_max_ms": float(error.max()),
            "missed_deadlines": timing["late"],
            "ticks": timing["ticks"],
            "work_p50_ms": float(np.percentile(work, 50)) if len(work) else None,
            "work_p99_ms": float(np.percentile(work, 99)) if len(work) else None,
            "work_max_ms": float(work.max()) if len(work) else None,
            "wake_p99_ms": float(np.percentile(wake, 99)) if len(wake) else None,
            "wake_max_ms": float(wake.max()) if len(wake) else None,
            "worst_periods": [{"step": int(timing["at_step"][i]), "period_ms": float(periods[i]),
                               "wake_ms": float(wake[i]), "unix_time": _unix_time(timing["at_time"][i])}
                              for i in worst],
            "scheduling": timing["scheduling"],
            "memory_locked": timing["memory_locked"],
            "major_page_faults": timing["major_page_faults"],
            "period_histogram": histogram(periods, nominal),
        },
        "rows": progress.rows,
        "evaluation": evaluation,
        "link": link,
        "wall_clock": {"started": started, "updated": results.now(), "compile_s": round(compile_s, 1)},
        "versions": results.versions(),
        "git_commit": results.git_commit(),
        "hardware": results.hardware(),
    }


def link_summary(bot) -> dict | None:
    """The link's round trips and the robot's own damps, for a robot behind a link (linked_robot.py); else None."""
    trips = getattr(bot, "round_trips", None)
    if trips is None:
        return None
    ms = np.asarray(trips) * 1000 if trips else np.full(1, np.nan)
    return {"address": bot.address, "requests": len(trips), "round_trip_p50_ms": float(np.percentile(ms, 50)),
            "round_trip_p99_ms": float(np.percentile(ms, 99)), "round_trip_max_ms": float(ms.max()),
            "robot_damps": bot.robot.get("damps")}


def _unix_time(perf_counter_time: float) -> float:
    """A time.perf_counter() reading as seconds since the epoch (to line up with other logs)."""
    return time.time() - (time.perf_counter() - perf_counter_time)


def histogram(periods_ms, nominal_ms, half_width_ms: float = 5.0, bins: int = 80) -> dict:
    """Control periods binned around the nominal one; the outliers counted apart."""
    edges = np.linspace(nominal_ms - half_width_ms, nominal_ms + half_width_ms, bins + 1)
    counts, _ = np.histogram(periods_ms, edges)
    return {"edges_ms": edges.round(4).tolist(), "counts": counts.tolist(),
            "below": int(np.sum(periods_ms < edges[0])), "above": int(np.sum(periods_ms > edges[-1]))}


def document_path(out_dir: Path, config) -> Path:
    return Path(out_dir) / f"{config.name}.json"


def trace_path(out_dir: Path, config) -> Path:
    return Path(out_dir) / f"{config.name}.trace.npy"


def save(out_dir: Path, config, document: dict, progress) -> None:
    """The results document and the trace of the steps taken so far."""
    results.write(document_path(out_dir, config), document)
    safe_io.save_npy(trace_path(out_dir, config), progress.trace[:progress.step].astype(np.float32))


def load_trace(out_dir: Path, config) -> np.ndarray:
    """The per-step trace of a run, (steps, len(TRACE))."""
    return np.load(trace_path(out_dir, config))
