"""The on-robot checkpoint: policy, optimiser state, replay buffer and counters, so a stopped run resumes."""

import json
from pathlib import Path

import flax.serialization
import numpy as np

COUNTERS = ("step", "falls", "episodes", "train_seconds", "reset_seconds", "rows")
"""The run's progress counters the checkpoint keeps (progress.json, beside the settings and updates)."""


def path(out_dir: Path, config) -> Path:
    """The checkpoint folder of `config`'s run: <out>/<name>.checkpoint."""
    return Path(out_dir) / f"{config.name}.checkpoint"


def exists(checkpoint: Path) -> bool:
    return (checkpoint / "state.msgpack").exists()


def settings(config) -> dict:
    """What a checkpoint must match to be resumed (the evaluation's length may differ)."""
    return json.loads(json.dumps(dict(config.as_dict(), eval_seconds=None)))


def save(checkpoint: Path, config, agent_state, task_state, key, updates, buffer, progress) -> None:
    """Policy, optimiser state, replay buffer and counters, so a later run resumes."""
    checkpoint.mkdir(parents=True, exist_ok=True)
    state = {"agent": agent_state, "task_state": task_state, "key": key}
    (checkpoint / "state.msgpack").write_bytes(flax.serialization.to_bytes(state))
    buffer.save(checkpoint / "replay.npz")
    np.save(checkpoint / "trace.npy", progress.trace[:progress.step])
    counters = {"settings": settings(config), "updates": updates, **{name: getattr(progress, name) for name in COUNTERS}}
    (checkpoint / "progress.json").write_text(json.dumps(counters))


def load(checkpoint: Path, config, agent_state, task_state, key, buffer, progress):
    """Restore the buffer and `progress` in place; returns the agent state, task state, key and update count."""
    counters = json.loads((checkpoint / "progress.json").read_text())
    if counters.get("settings") != settings(config):
        raise ValueError(f"{checkpoint} holds a run with other settings; start over with --restart "
                         "or pick another --out folder")
    template = {"agent": agent_state, "task_state": task_state, "key": key}
    state = flax.serialization.from_bytes(template, (checkpoint / "state.msgpack").read_bytes())
    buffer.load(checkpoint / "replay.npz")
    for name in COUNTERS:
        setattr(progress, name, counters[name])
    done = np.load(checkpoint / "trace.npy")
    progress.trace[:len(done)] = done
    return state["agent"], state["task_state"], state["key"], counters["updates"]
