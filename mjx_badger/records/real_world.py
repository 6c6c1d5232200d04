"""The real-world experiments' numbers (thesis Tables 5.3-5.5, 6.1, 6.2) from results files learned under
on-robot conditions: evaluation speed (true, and as the robot estimated it), yaw control in the thesis's
categories, falls, and the run's duration with its resets.

Yaw control: the thesis judged it by eye from video, in four categories of heading drift. We
measure the heading the robot turned through over its final evaluation run, |mean yaw rate| x
the run's seconds, in degrees, and put it in the same bins: very good < 10, good 10-30, medium
30-60, poor > 60. Falls are every safety stop from step 0, warm-up included, as a robot counts
them. Duration: the simulated seconds of the 20k steps plus each fall's reset time
(Conditions.reset_seconds).
"""

import math

import numpy as np

from mjx_badger.protocol.conditions import get as get_conditions
from mjx_badger.records.analysis import final, series

FIRST_STEPS = 10_000
"""§5.2.2's count of early falls runs to here."""
YAW_BINS = ((10.0, "very good"), (30.0, "good"), (60.0, "medium"), (math.inf, "poor"))
"""Heading drift (degrees) below which each category holds (thesis §5.2)."""


def yaw_category(degrees: float) -> str:
    return next(name for limit, name in YAW_BINS if degrees < limit)


def summary(document: dict) -> dict:
    """A real-world run's row: seeds x steps, true and estimated evaluation speed, heading drift, falls, minutes."""
    config = document["config"]
    metrics = document["metrics"]
    eval_seconds = config["eval_steps"] / config["env"]["control_hz"]
    true_speed = final(document, "eval/desired_velocity")
    estimated = (final(document, "eval/estimated_desired_velocity")
                 if "eval/estimated_desired_velocity" in metrics else np.full_like(true_speed, np.nan))
    drift = np.degrees(np.abs(final(document, "eval/yaw_rate")) * eval_seconds)
    falls = series(document, "train/falls_total")[-1]
    reset = get_conditions(config.get("conditions", "sim"), tuple(map(tuple, config.get("condition_changes", ())))
                           ).reset_seconds
    minutes = (document["sim_minutes"][-1] * 60 + falls * reset) / 60
    # §5.2.2 counts "over 100 terminations within the first 10k steps": the falls by then, beside the whole run's.
    by_10k = [i for i, step in enumerate(document["steps"]) if step <= FIRST_STEPS]
    falls_10k = series(document, "train/falls_total")[by_10k[-1]] if by_10k else np.full_like(falls, np.nan)
    # §6.4: the stops at which the truth shows no fall yet, and those the sensors' noise alone made (None in files
    # from before the robot's stop read its senses).
    stops = {name: float(np.mean(series(document, f"train/{name}")[-1])) if f"train/{name}" in metrics else None
             for name in ("stops_before_fall", "premature_stops")}
    return {"seeds": len(document["seeds"]), "steps": document["steps"][-1], "complete": document["complete"],
            "velocity": float(np.nanmean(true_speed)), "velocity_range": (float(np.nanmin(true_speed)),
                                                                          float(np.nanmax(true_speed))),
            "estimated_velocity": float(np.nanmean(estimated)),
            "yaw_drift_deg": float(np.nanmean(drift)), "yaw": yaw_category(float(np.nanmean(drift))),
            "falls": float(np.mean(falls)), "falls_range": (float(falls.min()), float(falls.max())),
            "minutes": float(np.mean(minutes)), "eval_seconds": eval_seconds,
            "falls_10k": float(np.mean(falls_10k)), **stops}


LOOP_FOLDERS = {"real-office": ("realtime", "office"), "real-outdoor": ("realtime", "outdoor")}
"""Where, beside a results folder's profiles, `realtime --conditions <office|outdoor>` runs are looked for, by the
vmapped experiment they sit beside: results/realtime/office and results/realtime/outdoor."""


def loop_summary(document: dict) -> dict:
    """An on-robot loop run's row (realtime results file): falls, final evaluation's true and estimated speed and how
    it ended, minutes with each fall's reset at the conditions' reset time (as the vmapped rows count them), updates
    per learning step."""
    config = document["config"]
    reset = get_conditions(config["conditions"], tuple(map(tuple, config.get("condition_changes", ())))).reset_seconds
    evaluation = document.get("evaluation") or {}
    nan = float("nan")
    true = evaluation.get("true_velocity")
    return {"steps": document["steps"], "complete": document["complete"], "falls": float(document["falls"]),
            "velocity": nan if true is None else float(true), "estimated_velocity": evaluation.get("estimated_velocity", nan),
            "minutes": document["train_minutes"] + document["falls"] * reset / 60,
            "updates_per_step": document["updates_per_learning_step"], "protocol": config["protocol"],
            "evaluation": _evaluation_words(evaluation)}


def _evaluation_words(evaluation: dict) -> str:
    """How the loop's one evaluation ended: a speed read over a tumble is not a walk's."""
    if "seconds" not in evaluation:
        return "-"
    return f"fell after {evaluation['seconds']:.2f} s" if evaluation.get("fell") else f"{evaluation['seconds']:.0f} s"
