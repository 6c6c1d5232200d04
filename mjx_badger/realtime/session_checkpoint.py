"""The on-robot checkpoint: policy, optimiser state, replay buffer and counters, so a stopped run resumes."""

import json
from pathlib import Path

import flax.serialization
import numpy as np

from mjx_badger.core import safe_io

COUNTERS = ("step", "falls", "episodes", "train_seconds", "reset_seconds", "gaps", "gap_seconds", "rows")
"""The run's progress counters the checkpoint keeps (progress.json, beside the settings and updates)."""


def path(out_dir: Path, config) -> Path:
    """The checkpoint folder of `config`'s run: <out>/<name>.checkpoint."""
    return Path(out_dir) / f"{config.name}.checkpoint"


def exists(checkpoint: Path) -> bool:
    return (safe_io.newest_folder(checkpoint) / "progress.json").exists()


def settings(config) -> dict:
    """What a checkpoint must match to be resumed (the evaluation's length may differ)."""
    return json.loads(json.dumps(dict(config.as_dict(), eval_seconds=None)))


def save(checkpoint: Path, config, agent_state, task_state, key, updates, buffer, progress) -> None:
    """Policy, optimiser state, replay buffer and counters, so a later run resumes; the folder is replaced whole
    (safe_io.replace_folder), so a failed save leaves the one before."""
    state = {"agent": agent_state, "task_state": task_state, "key": key}
    counters = {"settings": settings(config), "updates": updates, **{name: getattr(progress, name) for name in COUNTERS}}

    def fill(folder: Path) -> None:
        safe_io.write_bytes(folder / "state.msgpack", flax.serialization.to_bytes(state))
        buffer.save(folder / "replay.npz")
        safe_io.save_npy(folder / "trace.npy", progress.trace[:progress.step])
        safe_io.write_text(folder / "progress.json", json.dumps(counters))

    safe_io.replace_folder(checkpoint, fill)


def load(checkpoint: Path, config, agent_state, task_state, key, buffer, progress):
    """Restore the buffer and `progress` in place; returns the agent state, task state, key and update count.

    ValueError naming the checkpoint if it holds another run's settings or cannot be read.
    """
    checkpoint = safe_io.newest_folder(checkpoint)
    try:
        counters = json.loads((checkpoint / "progress.json").read_text())
        same = isinstance(counters, dict) and counters.get("settings") == settings(config)
    except (OSError, ValueError) as error:
        raise ValueError(f"{checkpoint} cannot be read ({error}); start over with --restart") from None
    if not same:
        raise ValueError(f"{checkpoint} holds a run with other settings; start over with --restart "
                         "or pick another --out folder")
    try:
        template = {"agent": agent_state, "task_state": task_state, "key": key}
        state = flax.serialization.from_bytes(template, (checkpoint / "state.msgpack").read_bytes())
        done = np.load(checkpoint / "trace.npy")
        if done.ndim != 2 or done.shape[1] != progress.trace.shape[1] or len(done) != counters["step"]:
            raise ValueError(f"trace.npy holds {done.shape}, not {counters['step']} steps")
        buffer.load(checkpoint / "replay.npz")
        for name in COUNTERS:
            setattr(progress, name, counters.get(name, 0) if name in ("gaps", "gap_seconds") else counters[name])
    except Exception as error:  # cut short or edited: msgpack, zip, shape or key errors, whichever came first
        raise ValueError(f"{checkpoint} is damaged ({type(error).__name__}: {error}); start over with --restart") from None
    progress.trace[:len(done)] = done
    return state["agent"], state["task_state"], state["key"], counters["updates"]
