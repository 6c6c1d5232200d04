"""Host side of a training run: compile once, run chunk by chunk, show progress, write results, checkpoint, stop.

The parts: the compiled programs (programs.py), the results documents (documents.py), the progress
display (progress.py), the checkpoint schedule (checkpoints.py) and, with several processes, the
agreement on when to checkpoint and stop (core/cluster.py).
"""

import contextlib
import shutil
import sys
import time
from pathlib import Path
from typing import Callable

import jax

from mjx_badger.core import locks, stops
from mjx_badger.core.cluster import agree, agreed_max, gather, writes
from mjx_badger.core.validation import Refused
from mjx_badger.learning import checkpoints, documents
from mjx_badger.learning import tensorboard as event_files
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.documents import Member
from mjx_badger.learning.programs import compiled, program, seed_sharding
from mjx_badger.learning.progress import progress_bar, progress_figures
from mjx_badger.learning.train import make_train
from mjx_badger.records import results


def run(config: TrainConfig, seeds: list[int], out_path: Path, progress: bool = True, resume: bool = True,
        tensorboard: bool = True, keep_landed_since: str | None = None) -> dict:
    """Train `config` for every seed in one vmapped program; returns the results document.

    The carry is checkpointed as it goes (checkpoints.py); with `resume` a run of the same
    configuration and seeds that was interrupted continues from its last checkpoint, and
    ends with the numbers an uninterrupted run gives. The checkpoints go once the run is complete.
    With `tensorboard`, the metrics also go to event files beside the results (tensorboard.py).
    While it runs it holds the lock of `out_path` (locks.py): a second run into the same file is
    refused. SIGINT or SIGTERM stop it after the chunk at hand, saved (stops.py). With `keep_landed_since` (an
    ISO time; "" for any), a run that already landed (complete results of this configuration and seeds, started
    since then) is not trained again: a requeued cluster task returns the document of a run it had finished.
    """
    with writing(out_path), stops.graceful():
        if resume:
            documents.check_resumable(out_path)
        done = documents.landed(out_path, config, seeds, keep_landed_since)
        if done is not None:
            return done
        started = results.now()
        trainer = make_train(config)
        carry, chunk, compile_s = compiled(trainer, seeds)
        member = Member(config, list(seeds), out_path, trainer.env)
        carry, (document,) = train_loop([member], carry, chunk, lambda carry, metrics: [(metrics, carry.diverged_at)],
                                        out_path, started, compile_s, progress, resume, tensorboard)
        gait = gather(_gait(trainer, len(seeds))(carry))
        document = documents.finish(member, document, gait, carry.agent_state)
        remove_checkpoints(out_path)
        return document


@contextlib.contextmanager
def writing(out_path: Path):
    """The lock of `out_path`, held by the process that writes it (process 0 of several, the others told if it
    is refused, so that none waits for it)."""
    with contextlib.ExitStack() as held:
        refused = None
        if writes():
            try:
                held.enter_context(locks.hold(out_path))
            except Refused as error:
                refused = error
        if jax.process_count() > 1 and agreed_max(float(refused is not None))[0]:
            refused = refused or Refused(f"{out_path} is being written by another run (process 0 found its lock)")
        if refused is not None:
            raise refused
        yield


def remove_checkpoints(checkpoint_path: Path) -> None:
    """A complete run keeps no checkpoints: they go once its policy, agents and final results are written."""
    if writes():
        shutil.rmtree(checkpoints.folder(checkpoint_path), ignore_errors=True)


def _gait(trainer, num_seeds: int) -> Callable:
    """The gait record's program: this process's own on one device, a fresh one for seeds split over devices."""
    return program(trainer, num_seeds)[0].gait if seed_sharding(num_seeds) is None else jax.jit(jax.vmap(trainer.gait))


def train_loop(members: list, carry, chunk, views, checkpoint_path: Path, started: str, compile_s: float,
               progress: bool, resume: bool, tensorboard: bool) -> tuple:
    """Run `chunk` over all chunks, writing each member's results file as it goes: (final carry, documents).

    `views(carry, metrics)` gives each member's (metrics, diverged_at) with a leading seed axis.
    One checkpoint of the whole carry beside `checkpoint_path` serves every member.
    """
    config = members[0].config
    fresh = [documents.new(m, started, compile_s) for m in members]
    identity = [{"config": d["config"], "seeds": d["seeds"]} for d in fresh]
    saved = checkpoints.Checkpoints(checkpoint_path, identity[0] if len(members) == 1 else {"members": identity})
    first, carry, docs = resumed(saved, members, fresh, carry, resume, checkpoint_path, config.chunk_steps)
    events = [event_files.Writer(m.out_path, m.seeds, d) if tensorboard and writes() else None
              for m, d in zip(members, docs)]
    clock = {"run_s": docs[0]["wall_clock"].get("run_s", 0.0), "checkpoint_s": docs[0]["wall_clock"].get(
        "checkpoint_s", 0.0), "seeds": sum(len(m.seeds) for m in members)}
    bar = progress_bar(config, first, clock["seeds"], progress)
    schedule = checkpoints.Schedule()
    try:
        for index in range(first, config.num_chunks):
            start = index * config.chunk_steps
            t0 = time.perf_counter()
            carry, metrics = chunk(carry, start)
            metrics = gather(metrics)
            chunk_s = time.perf_counter() - t0
            clock["run_s"] += chunk_s
            steps = start + config.chunk_steps
            complete = index == config.num_chunks - 1
            for member, document, writer, (own, diverged_at) in zip(members, docs, events, views(carry, metrics)):
                documents.add_chunk(document, member, own, diverged_at, steps, clock)
                if writes():  # before the checkpoint: the file never runs behind it
                    results.write(member.out_path, document)
                if writer is not None:
                    t0 = time.perf_counter()
                    writer.write(own, steps)
                    document["wall_clock"]["tensorboard_s"] = round(document["wall_clock"].get("tensorboard_s", 0.0)
                                                                    + time.perf_counter() - t0, 3)
            due = schedule.due()
            if agree(stops.requested() is not None and not complete):  # every process stops at the same chunk
                saved.save(index + 1, carry)
                raise _interrupted(steps, config, members, saved)
            if not complete and due:
                t0 = time.perf_counter()
                saved.save(index + 1, carry)
                took = time.perf_counter() - t0
                clock["checkpoint_s"] += took
                schedule.saved(*agreed_max(took, chunk_s))  # all processes checkpoint on the same chunks
            bar.update(config.chunk_steps)
            bar.set_postfix(progress_figures(views(carry, metrics)[0][0]))
    finally:  # also when a write fails or a signal stops the run: files closed, the checkpoints' manager too
        bar.close()
        for writer in events:
            if writer is not None:
                writer.close()
        saved.close()
    return carry, docs


def resumed(saved, members: list, fresh: list, carry, resume: bool, checkpoint_path: Path, chunk_steps: int) -> tuple:
    """(first chunk to run, carry, documents): from the last checkpoint where every member's results file has got as
    far (the rows past it are run again), else from the start; without `resume` the checkpoints are removed."""
    if not resume:
        saved.remove()
        return 0, carry, fresh
    found = saved.restore(carry)
    before = [documents.previous(m.out_path, d) for m, d in zip(members, fresh)]
    if found is None or not all(p is not None and len(p["steps"]) >= found[0] for p in before):
        return 0, carry, fresh
    first, carry = found
    docs = [documents.truncated(p, first) for p in before]
    for document in docs:  # its wall_clock counts both sittings from here on
        document["wall_clock"]["resumed_at_step"] = first * chunk_steps
    print(f"resuming {checkpoint_path.name} at step {first * chunk_steps} from {saved.path}", file=sys.stderr)
    return first, carry, docs


def _interrupted(steps: int, config, members: list, saved) -> stops.Interrupted:
    """The stop a signal asked for, saying where the results and the checkpoint are and how to go on."""
    signum = stops.requested() or stops.SIGNALS[1]
    return stops.Interrupted(signum, f"stopped by {stops.name(signum)} at step {steps} of "
                             f"{config.num_chunks * config.chunk_steps}: results in {members[0].out_path}"
                             f"{' and its sweep members' if len(members) > 1 else ''}, checkpoint in "
                             f"{saved.path}; run the same command again to resume")
