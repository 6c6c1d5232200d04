"""Checkpoints of a training run's whole vmapped carry, so an interrupted run resumes where it stopped.

The carry is everything the run has: agent and optimiser states, replay buffers, RNG keys, env
and curriculum states, for every seed. Restoring it and running the remaining chunks gives
the numbers of an uninterrupted run bit for bit. A run's checkpoints live beside its results
file in `<name>.ckpt/`, one orbax step per checkpoint named by the chunks done, with
`run.json` saying which configuration and seeds they belong to. orbax makes a step visible
only once it is completely written; a step that cannot be read is skipped for an older one.
"""

import json
import math
import os
import shutil
import warnings
from pathlib import Path

import jax
import numpy as np

from mjx_badger.core.cluster import wait_for_peers
from mjx_badger.core.launch import EVERY_CHUNK

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    import orbax.checkpoint as ocp

KEEP = 2
"""Checkpoints kept: the newest and one before it, the fallback if the newest is damaged."""
MAX_OVERHEAD = 0.05
"""Checkpointing may cost at most this fraction of the training time; the interval follows from it."""


def folder(results_path: Path) -> Path:
    return Path(results_path).with_suffix(".ckpt")


def interval(save_s: float, chunk_s: float) -> int:
    """Chunks between checkpoints so that saving costs at most MAX_OVERHEAD of the time."""
    return max(1, math.ceil(save_s / (MAX_OVERHEAD * max(chunk_s, 1e-9))))


class Schedule:
    """When a run checkpoints: after its first chunk, then every `interval` chunks as the last save's cost allows."""

    def __init__(self):
        self.every, self.since_saved = 1, 0

    def due(self) -> bool:
        """Count a chunk done; whether a checkpoint is due after it."""
        self.since_saved += 1
        return self.since_saved >= self.every

    def saved(self, save_s: float, chunk_s: float) -> None:
        """A checkpoint took `save_s` where a chunk takes `chunk_s` (the slowest process's, so all agree)."""
        # A cluster job may be preempted at any moment: it saves every chunk (launch.py).
        every_chunk = os.environ.get(EVERY_CHUNK) == "1"
        self.every, self.since_saved = 1 if every_chunk else interval(save_s, chunk_s), 0


def _sized(leaves: list) -> dict:
    """The leaves orbax can store, by position: it refuses empty arrays (an MJX state has some), which restore as new empty arrays."""
    return {str(i): leaf for i, leaf in enumerate(leaves) if np.size(leaf)}


def _empty_like(leaf):
    """A new empty array of `leaf`'s shape and placement: the restored carry shares no buffer with its template,
    which a compiled chunk may donate."""
    return jax.device_put(np.zeros(leaf.shape, leaf.dtype), leaf.sharding) if hasattr(leaf, "sharding") else leaf


class Checkpoints:
    """The checkpoints of one run: `save(chunks_done, carry)`, `restore(like)`, `remove()`."""

    def __init__(self, results_path: Path, identity: dict):
        self.path = folder(results_path).absolute()
        self.identity = json.loads(json.dumps(identity))
        self._manager = None

    @property
    def manager(self):
        if self._manager is None:
            options = ocp.CheckpointManagerOptions(max_to_keep=KEEP, create=True, enable_async_checkpointing=False)
            self._manager = ocp.CheckpointManager(self.path, options=options)
        return self._manager

    def _same_run(self) -> bool:
        stamp = self.path / "run.json"
        return stamp.exists() and json.loads(stamp.read_text()) == self.identity

    def save(self, chunks_done: int, carry) -> None:
        fresh = not self._same_run()
        wait_for_peers()  # several processes (jax.distributed) share the folder: all look before one writes
        if fresh and jax.process_index() == 0:
            self.remove()
            self.path.mkdir(parents=True)
            (self.path / "run.json").write_text(json.dumps(self.identity))
        wait_for_peers()
        # Steps at or past this one are from a run that could not be resumed from them (unreadable,
        # or written by code whose carry differs): they go, or orbax refuses the step or keeps them as newest.
        for stale in [step for step in self.manager.all_steps() if step >= chunks_done]:
            self.manager.delete(stale)
        self.manager.save(chunks_done, args=ocp.args.StandardSave(_sized(jax.tree.leaves(carry))), force=True)
        self.manager.wait_until_finished()

    def restore(self, like) -> tuple[int, object] | None:
        """(chunks done, carry) of the newest readable checkpoint of this run, or None; `like` gives the structure."""
        if not self.path.exists() or not self._same_run():
            return None
        leaves, structure = jax.tree.flatten(like)
        abstract = jax.tree.map(ocp.utils.to_shape_dtype_struct, _sized(leaves))
        for step in sorted(self.manager.all_steps(), reverse=True):
            try:
                stored = self.manager.restore(step, args=ocp.args.StandardRestore(abstract))
                return step, structure.unflatten([stored[str(i)] if str(i) in stored else _empty_like(leaf)
                                                  for i, leaf in enumerate(leaves)])
            except Exception as error:  # a damaged checkpoint: fall back to the one before
                warnings.warn(f"checkpoint {self.path / str(step)} cannot be read ({error}); trying an older one")
        return None

    def close(self) -> None:
        if self._manager is not None:
            self._manager.close()
            self._manager = None

    def remove(self) -> None:
        self.close()
        shutil.rmtree(self.path, ignore_errors=True)


def agents_folder(results_path: Path) -> Path:
    return Path(results_path).with_suffix(".agents")


def save_agents(results_path: Path, agent_states) -> Path:
    """Every seed's final agent (actor, critic, targets, temperature, optimiser states) beside the results file.

    The saved policy (policy.py) is what acts; this is what goes on learning from where the run
    stopped, e.g. on the robot.
    """
    path = agents_folder(results_path).absolute()
    if jax.process_index() == 0:
        shutil.rmtree(path, ignore_errors=True)
    wait_for_peers()
    with ocp.StandardCheckpointer() as checkpointer:
        checkpointer.save(path, _sized(jax.tree.leaves(agent_states)))
    return path


def load_agents(results_path: Path, like):
    """The agents `save_agents` wrote, in the structure of `like` (the same seeds' freshly initialised agents)."""
    leaves, structure = jax.tree.flatten(like)
    abstract = jax.tree.map(ocp.utils.to_shape_dtype_struct, _sized(leaves))
    with ocp.StandardCheckpointer() as checkpointer:
        stored = checkpointer.restore(agents_folder(results_path).absolute(), abstract)
    return structure.unflatten([stored.get(str(i), leaf) for i, leaf in enumerate(leaves)])
