"""Numbers from results files: series, final values, time to target, gait frequency, run summaries, names.

Nothing here draws or trains; figures (plots.py), tables (tables.py) and the claims read these.
"""

import json
import warnings

import numpy as np

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.control.actions import APPROACHES
from mjx_badger.core.paths import REFERENCE
from mjx_badger.sim.gait import GAITS, gait_frequency, gait_name


def display_name(name: str) -> str:
    """How figures and tables name an approach or algorithm (their registries), else the name itself; a
    parameter experiment's run label ('jt-oef min_cutoff=0.5') keeps its NAME=VALUE words after the registry's."""
    entry = APPROACHES.get(name) or ALGORITHMS.get(name)
    if entry is not None:
        return entry.label
    head, _, params = name.partition(" ")
    entry = APPROACHES.get(head) or ALGORITHMS.get(head)
    if entry is not None and params and all("=" in word for word in params.split()):
        return f"{entry.label} {params}"
    if entry is not None and params in ALGORITHMS:  # 'jt-lpf sac-utd20': a run of another algorithm than CrossQ
        return f"{ALGORITHMS[params].label} {entry.label}"
    return name


def display_color(name: str) -> str | None:
    """The colour of an approach or algorithm in figures (their registries); None lets matplotlib choose."""
    entry = APPROACHES.get(name) or ALGORITHMS.get(name)
    return None if entry is None else entry.color


DIRECTIONS = ("forward", "backward", "left", "right")
REACHED_FRACTION = 0.9
"""A run has reached the target once the seed-mean training velocity is >= 90 % of it."""


def series(document: dict, name: str) -> np.ndarray:
    """Metric `name` as an array (chunks, seeds), NaN where undefined."""
    return np.array(document["metrics"][name], dtype=float)


def last_chunks(document: dict) -> int:
    """How many final chunks count as 'final' (the last tenth of the run, at least one)."""
    return max(1, len(document["steps"]) // 10)


def final(document: dict, name: str) -> np.ndarray:
    """Metric `name` averaged over the final chunks, per seed (seeds,)."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(series(document, name)[-last_chunks(document):], axis=0)


def first_reached(document: dict, target: float) -> int | None:
    """Index of the first chunk whose seed-mean training velocity reaches 90 % of `target`."""
    mean = np.nanmean(series(document, "train/forward_velocity"), axis=1)
    hits = np.flatnonzero(mean >= REACHED_FRACTION * target)
    return int(hits[0]) if hits.size else None


def best_seed(document: dict) -> tuple[int, float]:
    """(seed, its final evaluation return) of the run's best seed: the highest final evaluation return."""
    returns = final(document, "eval/return")
    index = int(np.nanargmax(returns))
    return document["seeds"][index], float(returns[index])


def gait_frequencies(document: dict) -> list[float]:
    """Gait frequency of every seed's gait record, or [] if the file has none."""
    gait = document.get("gait")
    if not gait:
        return []
    return [gait_frequency(c, gait["physics_dt"]) for c in gait["contacts"]]


def gait_names(document: dict) -> list[str]:
    """The gait (sim/gait.py's names) of every seed's gait record, or [] if the file has none."""
    gait = document.get("gait")
    return [gait_name(c, gait["physics_dt"]) for c in gait["contacts"]] if gait else []


def below_target(document: dict, target: float, seconds: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Fig 5.5 per seed over the gait record's last `seconds`: the share of time below `target`, and the
    deepest dip under it (m/s, 0 where it never dips)."""
    gait = document["gait"]
    velocity = np.asarray(gait["forward_velocity"], dtype=float)[:, -int(round(seconds / gait["physics_dt"])):]
    return np.mean(velocity < target, axis=1), np.maximum(target - velocity.min(axis=1), 0.0)


def evaluation_crossed_episode(document: dict) -> bool:
    """Whether the run evaluated an omnidirectional task for longer than an episode: until sim/evaluation.py held
    the command, such an evaluation restarted at the time limit under a command the task drew."""
    config = document["config"]
    env = config.get("env") or {}
    episode = (env.get("protocol") or {}).get("episode_seconds")
    return (config.get("task", "").startswith("omni") and episode is not None
            and config["eval_steps"] / env["control_hz"] > episode + 1e-9
            and not document.get("evaluation_holds_command", False))


GAIN_MOMENTS = ("train/desired_velocity", "train/estimated_desired_velocity", "train/true_squared",
                "train/estimate_squared", "train/true_times_estimate")


def estimate_gain(document: dict) -> dict | None:
    """The onboard estimate against the truth over the whole run, per seed: `slope` (least squares, estimate =
    slope x truth + offset) and `correlation`, pooled over every training step; None where the run did not sense
    or its file predates the moments."""
    if not all(name in document["metrics"] for name in GAIN_MOMENTS):
        return None
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t, e, tt, ee, te = (np.nanmean(series(document, name), axis=0) for name in GAIN_MOMENTS)  # equal chunks
        cov, var_t, var_e = te - t * e, tt - t * t, ee - e * e
        return {"slope": (cov / var_t).tolist(), "correlation": (cov / np.sqrt(var_t * var_e)).tolist()}


def summarize(document: dict, target: float | None) -> dict:
    """Headline numbers of one run: time to target, final velocities, falls (mean and range), gait."""
    falls_curve = series(document, "train/falls")
    falls = falls_curve[-1]
    warmup = document["config"]["warmup_steps"]
    warmup_chunks = [i for i, step in enumerate(document["steps"]) if step <= warmup]
    falls_in_warmup = falls_curve[warmup_chunks[-1]] if warmup_chunks else np.zeros_like(falls)
    reached = None if target is None else first_reached(document, target)
    frequencies, names = gait_frequencies(document), gait_names(document)
    metrics = document["metrics"]
    eval_velocity = final(document, "eval/desired_velocity") if "eval/desired_velocity" in metrics else None
    gain = estimate_gain(document)
    return {
        "steps": document["steps"][-1],
        "minutes": document["sim_minutes"][-1],
        "steps_to_target": None if reached is None else document["steps"][reached],
        "minutes_to_target": None if reached is None else document["sim_minutes"][reached],
        "final_velocity": float(np.nanmean(final(document, "train/forward_velocity"))),
        "final_velocity_max": float(np.nanmax(final(document, "train/forward_velocity"))),
        "final_eval_velocity": None if eval_velocity is None else float(np.nanmean(eval_velocity)),
        "final_eval_velocity_max": None if eval_velocity is None else float(np.nanmax(eval_velocity)),
        "falls_mean": float(falls.mean()),
        "falls_min": float(falls.min()),
        "falls_max": float(falls.max()),
        "falls_after_warmup_mean": float((falls - falls_in_warmup).mean()),
        # Every termination from step 0, whatever the protocol counts (files before it have none).
        "falls_total_mean": float(series(document, "train/falls_total")[-1].mean())
        if "train/falls_total" in metrics else None,
        # Times the JT termination rule started firing, whether or not the protocol ended the episode.
        "would_falls_mean": float(series(document, "train/would_falls")[-1].mean())
        if "train/would_falls" in metrics else None,
        # §6.4: the robot's stops at which the truth shows no fall yet, and those the sensors' noise alone made.
        **{f"{name}_mean": float(series(document, f"train/{name}")[-1].mean()) if f"train/{name}" in metrics
           else None for name in ("stops_before_fall", "premature_stops")},
        "estimate_slope": None if gain is None else float(np.nanmean(gain["slope"])),
        "estimate_correlation": None if gain is None else float(np.nanmean(gain["correlation"])),
        "gait_hz": float(np.nanmean(frequencies)) if frequencies and not np.all(np.isnan(frequencies)) else None,
        # The seeds' most common gait (the first named of a tie, in GAITS' order) and each gait's count.
        "gait": max(GAITS, key=names.count) if names else None,
        "gait_counts": {name: names.count(name) for name in GAITS if name in names},
        "seeds": len(document["seeds"]),
        "complete": document["complete"],
    }


RELEASED_CODE = REFERENCE / "released-code"
"""The thesis's released code run on a 2-core CPU, per experiment (<name>.json); the check for thesis-code at quick."""


def released_code(experiment: str) -> dict | None:
    """The released code's per-seed numbers for `experiment` (RELEASED_CODE), or None where it was not run."""
    path = RELEASED_CODE / f"{experiment}.json"
    return json.loads(path.read_text()) if path.exists() else None


def per_seed_released_measures(document: dict, threshold: float = 0.45, last_steps: int = 3000) -> dict:
    """Per seed, as the released code's numbers were read: the first step whose chunk-mean forward velocity
    reaches `threshold` (None: never), the mean velocity of the last `last_steps`, falls after warm-up."""
    velocity = series(document, "train/forward_velocity")
    steps = document["steps"]
    chunk = steps[0] if len(steps) == 1 else steps[1] - steps[0]
    crossed = [next((steps[i] for i in range(len(steps)) if velocity[i, k] >= threshold), None)
               for k in range(velocity.shape[1])]
    falls = series(document, "train/falls")
    warmup = [i for i, step in enumerate(steps) if step <= document["config"]["warmup_steps"]]
    in_warmup = falls[warmup[-1]] if warmup else np.zeros(falls.shape[1])
    last = max(1, last_steps // chunk)
    return {"steps_to_0.45": crossed, "velocity_last_3k": np.nanmean(velocity[-last:], axis=0).tolist(),
            "falls": (falls[-1] - in_warmup).tolist()}
