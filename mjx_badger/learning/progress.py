"""What a training run shows while it runs: a progress bar with the seeds' headline figures beside it."""

import json
import os
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from mjx_badger.core.cluster import writes


def progress_bar(config, first_chunk: int, seeds: int, shown: bool) -> tqdm:
    """The run's progress bar over its steps, from the chunk it starts at (on stderr; hidden unless `shown` and this
    process writes)."""
    label = f"{config.approach} {config.algo} {config.task} x{seeds}"
    return tqdm(total=config.num_chunks * config.chunk_steps, initial=first_chunk * config.chunk_steps, desc=label,
                unit="step", file=sys.stderr, disable=not (shown and writes()), dynamic_ncols=True, mininterval=2.0)


def progress_wanted() -> bool:
    """Whether a command shows the progress bar: on a terminal, or anywhere but a CI job."""
    return sys.stderr.isatty() or os.environ.get("CI") is None


def progress_figures(metrics: dict) -> dict:
    """Seed means shown beside the progress bar (frozen seeds left out): velocity along the command, evaluation, falls."""
    mean = lambda name: np.nanmean(metrics[name]) if np.any(np.isfinite(metrics[name])) else np.nan
    shown = {"v": mean("train/desired_velocity")}
    if any(name.startswith("eval/forward_full/") for name in metrics):  # the omni tasks' eight runs
        shown["eval_mae"] = mean("eval/desired_mae")
    else:
        shown["eval_v"] = mean("eval/desired_velocity")
    if "curriculum/learned_bins" in metrics:
        shown["bins"] = mean("curriculum/learned_bins")
    shown["falls"] = mean("train/falls")
    if np.nansum(np.asarray(metrics.get("train/blowups", 0))) > 0:
        shown["blowups"] = mean("train/blowups")
    return {k: f"{v:.2f}" for k, v in shown.items()}


def run_progress(path, total_steps: int) -> str:
    """A run's progress read from its results file (what a process or cluster task running it last saved): steps done,
    rate and time left; '' before its first save and once it is complete (nothing to add to what is said then)."""
    try:
        document = json.loads(Path(path).read_text())
        done, run_s = document["steps"][-1], document["wall_clock"]["run_s"]
    except (OSError, ValueError, KeyError, IndexError, TypeError):  # not written yet, or caught mid-replace
        return ""
    if document.get("complete"):
        return ""
    rate = done / run_s if run_s > 0 else 0.0
    if done >= total_steps:  # trained; the gait record, the policy and the summary are still to be written
        return f"{done:,} of {total_steps:,} steps ({rate:.1f} steps/s), finishing"
    left = f", {time_left((total_steps - done) / rate)}" if rate > 0 else ""
    return f"{done:,} of {total_steps:,} steps ({rate:.1f} steps/s{left})"


def time_left(seconds: float) -> str:
    """'~t left' as a person reads it: minutes under an hour, hours above."""
    return f"~{seconds / 3600:.1f} h left" if seconds >= 3600 else f"~{seconds / 60:.0f} min left"
