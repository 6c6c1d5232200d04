"""Host side of a training run: compile once, run chunk by chunk, show progress, write results."""

import collections
import contextlib
import dataclasses
import shutil
import json
import os
import sys
import time
from pathlib import Path
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec
from tqdm import tqdm

from mjx_badger import checkpoints, locks, policy, results, stops
from mjx_badger.cluster import agreed_max, gather, writes
from mjx_badger import tensorboard as event_files
from mjx_badger.train import TrainConfig, make_train
from mjx_badger.validation import Refused


def seeds_chunk(trainer, num_seeds: int):
    """The chunk over a leading seed axis: vmapped, or for one seed the unbatched program.

    XLA:CPU compiles a vmapped batch of one about twice as slow as the plain program
    (batch-renorm gradients and the replay gather lose their fast paths), so a single
    seed runs unbatched behind the same (1, ...) carry layout.
    """
    if num_seeds > 1:
        return jax.vmap(trainer.chunk, in_axes=(0, None))

    def single(carry, start):
        carry, metrics = trainer.chunk(jax.tree.map(lambda x: x[0], carry), start)
        return jax.tree.map(lambda x: x[None], (carry, metrics))

    return single


def seed_sharding(num_seeds: int) -> NamedSharding | None:
    """The seed axis split over every device (a 1-D mesh named `seeds`); None on one device or for one seed."""
    devices = jax.devices()
    if len(devices) == 1 or num_seeds == 1:
        return None
    check_seeds_divide(num_seeds, len(devices))
    return NamedSharding(Mesh(np.array(devices), ("seeds",)), PartitionSpec("seeds"))


def check_seeds_divide(num_seeds: int, num_devices: int) -> None:
    """ValueError unless the seeds split evenly over the devices (one seed alone runs on the first device)."""
    if num_seeds > 1 and num_seeds % num_devices:
        raise ValueError(f"{num_seeds} seeds do not split evenly over {num_devices} devices: choose a multiple of "
                         f"{num_devices} (--seeds), or fewer devices (CUDA_VISIBLE_DEVICES, or "
                         "XLA_FLAGS=--xla_force_host_platform_device_count on a CPU)")


# The programs of the last few configurations this process compiled, by (config, seed count): a later
# run of the same shapes (a test suite, a resumed or repeated run) neither traces nor compiles again.
_PROGRAMS: collections.OrderedDict = collections.OrderedDict()
KEPT_PROGRAMS = 6


class Program(NamedTuple):
    """One configuration's compiled functions for a number of seeds on one device."""

    init: Callable
    """jit(vmap(init)) over the seeds' keys."""
    chunk: Callable
    """The compiled chunk; it donates its carry (the caller's carry is invalid after the call)."""
    gait: Callable
    """jit(vmap(gait)): the gait record after training."""


def program(trainer, num_seeds: int) -> tuple[Program, float]:
    """(`trainer`'s program for `num_seeds` seeds, seconds spent compiling it now: 0 when this process had it)."""
    key = (trainer.config, num_seeds)
    if key in _PROGRAMS:
        _PROGRAMS.move_to_end(key)
        return _PROGRAMS[key], 0.0
    init = jax.jit(jax.vmap(trainer.init))
    carry = jax.eval_shape(init, jax.vmap(jax.random.PRNGKey)(jnp.arange(num_seeds)))
    t0 = time.perf_counter()
    chunk = jax.jit(seeds_chunk(trainer, num_seeds), donate_argnums=0).lower(carry, 0).compile()
    built = Program(init, chunk, jax.jit(jax.vmap(trainer.gait)))
    _PROGRAMS[key] = built
    while len(_PROGRAMS) > KEPT_PROGRAMS:
        _PROGRAMS.popitem(last=False)
    return built, time.perf_counter() - t0


def compiled(trainer, seeds: list[int]):
    """(the seeds' initial carry, the compiled chunk, compile seconds); on several devices both split by seed."""
    keys = jax.vmap(jax.random.PRNGKey)(jnp.asarray(seeds))
    sharding = seed_sharding(len(seeds))
    if sharding is None:
        built, compile_s = program(trainer, len(seeds))
        return built.init(keys), built.chunk, compile_s
    init = jax.jit(jax.vmap(trainer.init))
    # Each device runs the one-device program of its own seeds (the same HLO, so the same numbers as
    # one device running them); the carry and metrics are global arrays sharded on the seed axis. An
    # SPMD program (jit or shard_map over the mesh) fuses differently and rounds differently. With
    # several processes (jax.distributed), each runs the programs of its own devices only. Each device's
    # program is lowered from shapes with that device as the default, as `program` lowers a one-device run
    # (the same module text), and donates its carry as that one does; where JAX's compile cache leaves the
    # device out of its key (on GPUs), the devices after the first load the first's.
    devices = list(sharding.mesh.devices.flat)
    local = len(seeds) // len(devices)
    mine = [(i, device) for i, device in enumerate(devices) if device.process_index == jax.process_index()]
    per_device = jax.jit(seeds_chunk(trainer, local), donate_argnums=0)
    shapes = jax.eval_shape(init, keys[:local])
    parts, programs, compile_s = [], [], 0.0
    for i, device in mine:
        with jax.default_device(device):
            parts.append(init(keys[i * local:(i + 1) * local]))
            t0 = time.perf_counter()
            programs.append(per_device.lower(shapes, 0).compile())
            compile_s += time.perf_counter() - t0
    devices = [device for _, device in mine]

    def chunk(carry, start):
        outputs = [run(part, start) for run, part in zip(programs, _per_device(carry, devices))]
        return _sharded(outputs, sharding)

    return _sharded(parts, sharding), chunk, compile_s


def _per_device(tree, devices: list) -> list:
    """One tree per device, of that device's shard of every leaf."""
    shards = [{shard.device: shard.data for shard in leaf.addressable_shards} for leaf in jax.tree.leaves(tree)]
    structure = jax.tree.structure(tree)
    return [jax.tree.unflatten(structure, [by_device[device] for by_device in shards]) for device in devices]


def _sharded(parts: list, sharding: NamedSharding):
    """The per-device trees `parts` joined into global arrays split along the leading (seed) axis."""
    def join(*leaves):  # every device holds as many seeds; the other processes' devices too
        shape = (leaves[0].shape[0] * sharding.mesh.size,) + leaves[0].shape[1:]
        return jax.make_array_from_single_device_arrays(shape, sharding, list(leaves))

    return jax.tree.map(join, *parts)


def measure_speed(config: TrainConfig, seeds: list[int], steps: int = 200, evaluation: bool = False) -> dict:
    """This machine's speed for `config`: a chunk of `steps` learning steps (updates from the first), timed
    after a first one; seed-steps/s and compile seconds (of the short program: a real run's is close).
    With `evaluation` the chunk ends with `config`'s evaluation cut in proportion, as a whole run's chunks do."""
    carry, chunk, compile_s = compiled(make_train(short_run(config, steps, evaluation)), seeds)
    return timed_chunk(carry, chunk, steps, len(seeds), compile_s)


def short_run(config: TrainConfig, steps: int, evaluation: bool = False) -> TrainConfig:
    """`config` cut to two chunks of `steps` learning steps, the shortest run worth timing; its evaluation
    one step long, or with `evaluation` as long per learning step as `config`'s."""
    eval_steps = max(1, round(config.eval_steps * steps / config.chunk_steps)) if evaluation else 1
    return dataclasses.replace(config, total_steps=2 * steps, chunk_steps=steps, warmup_steps=0, eval_steps=eval_steps)


def timed_chunk(carry, chunk, steps: int, seed_count: int, compile_s: float) -> dict:
    """Seed-steps/s of the second chunk of a compiled program (the first is untimed), and its compile seconds."""
    carry, _ = jax.block_until_ready(chunk(carry, 0))
    t0 = time.perf_counter()
    jax.block_until_ready(chunk(carry, steps))
    return {"seed_steps_per_s": seed_count * steps / (time.perf_counter() - t0), "compile_s": compile_s}


class Member(NamedTuple):
    """One results file a program writes: its configuration, seeds, path and (concrete) environment."""

    config: TrainConfig
    seeds: list
    out_path: Path
    env: object


def progress_wanted() -> bool:
    """Whether a command shows the progress bar: on a terminal, or anywhere but a CI job."""
    return sys.stderr.isatty() or os.environ.get("CI") is None


def run(config: TrainConfig, seeds: list[int], out_path: Path, progress: bool = True, resume: bool = True,
        tensorboard: bool = True) -> dict:
    """Train `config` for every seed in one vmapped program; returns the results document.

    The carry is checkpointed as it goes (checkpoints.py); with `resume` a run of the same
    configuration and seeds that was interrupted continues from its last checkpoint, and
    ends with the numbers an uninterrupted run gives. The checkpoints go once the run is complete.
    With `tensorboard`, the metrics also go to event files beside the results (tensorboard.py).
    While it runs it holds the lock of `out_path` (locks.py): a second run into the same file is
    refused. SIGINT or SIGTERM stop it after the chunk at hand, saved (stops.py).
    """
    with writing(out_path), stops.graceful():
        if resume:
            check_resumable(out_path)
        started = results.now()
        trainer = make_train(config)
        carry, chunk, compile_s = compiled(trainer, seeds)
        member = Member(config, list(seeds), out_path, trainer.env)
        carry, (document,) = train_loop([member], carry, chunk, lambda carry, metrics: [(metrics, carry.diverged_at)],
                                        out_path, started, compile_s, progress, resume, tensorboard)
        gait = gather(_gait(trainer, len(seeds))(carry))
        document = finish(member, document, gait, carry.agent_state)
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


def check_resumable(path: Path) -> None:
    """Refused, before anything compiles, if a results file to resume from is there but cannot be read."""
    if Path(path).exists():
        _partial(path, None)


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
    documents = [{
        "schema": results.SCHEMA,
        "config": results.config_dict(m.config),
        "seeds": list(m.seeds),
        "complete": False,
        "steps": [],
        "sim_minutes": [],
        "metrics": {},
        "wall_clock": {"started": started, "compile_s": round(compile_s, 2)},
        "versions": results.versions(),
        "git_commit": results.git_commit(),
    } for m in members]
    identity = [{"config": d["config"], "seeds": d["seeds"]} for d in documents]
    saved = checkpoints.Checkpoints(checkpoint_path, identity[0] if len(members) == 1 else {"members": identity})
    first = 0
    if not resume:
        saved.remove()
    else:
        found = saved.restore(carry)
        previous = [_partial(m.out_path, d) for m, d in zip(members, documents)]
        if found is not None and all(p is not None and len(p["steps"]) >= found[0] for p in previous):
            first, carry = found
            documents = [_truncated(p, first) for p in previous]
            for document in documents:  # its wall_clock counts both sittings from here on
                document["wall_clock"]["resumed_at_step"] = first * config.chunk_steps
            print(f"resuming {checkpoint_path.name} at step {first * config.chunk_steps} from {saved.path}",
                  file=sys.stderr)
    events = [event_files.Writer(m.out_path, m.seeds, d) if tensorboard and writes() else None
              for m, d in zip(members, documents)]
    seeds = sum(len(m.seeds) for m in members)
    label = f"{config.approach} {config.algo} {config.task} x{seeds}"
    bar = tqdm(total=config.num_chunks * config.chunk_steps, initial=first * config.chunk_steps, desc=label,
               unit="step", file=sys.stderr, disable=not (progress and writes()), dynamic_ncols=True, mininterval=2.0)
    run_s = documents[0]["wall_clock"].get("run_s", 0.0)
    save_s = documents[0]["wall_clock"].get("checkpoint_s", 0.0)
    every, since_saved = 1, 0
    try:
        for index in range(first, config.num_chunks):
            start = index * config.chunk_steps
            t0 = time.perf_counter()
            carry, metrics = chunk(carry, start)
            metrics = gather(metrics)
            chunk_s = time.perf_counter() - t0
            run_s += chunk_s
            steps = start + config.chunk_steps
            complete = index == config.num_chunks - 1
            for member, document, writer, (own, diverged_at) in zip(members, documents, events, views(carry, metrics)):
                document["steps"].append(steps)
                document["sim_minutes"].append(round(steps / member.env.control_hz / 60, 4))
                for name, values in own.items():
                    document["metrics"].setdefault(name, []).append(np.asarray(values, dtype=float).round(5).tolist())
                document["complete"] = False  # until `finish` has written the policy and agents too
                note_divergence(document, gather(diverged_at), member.out_path)
                document["wall_clock"].update(updated=results.now(), run_s=round(run_s, 2),
                                              checkpoint_s=round(save_s, 2),
                                              seed_steps_per_s=round(steps * seeds / run_s, 1))
                document["hardware"] = results.hardware()
                if writes():  # before the checkpoint: the file never runs behind it
                    results.write(member.out_path, document)
                if writer is not None:
                    t0 = time.perf_counter()
                    writer.write(own, steps)
                    document["wall_clock"]["tensorboard_s"] = round(document["wall_clock"].get("tensorboard_s", 0.0)
                                                                    + time.perf_counter() - t0, 3)
            since_saved += 1
            stop = stops.requested() is not None and not complete
            if jax.process_count() > 1:  # every process stops at the same chunk
                stop = bool(agreed_max(float(stop))[0])
            if stop:
                saved.save(index + 1, carry)
                signum = stops.requested() or stops.SIGNALS[1]
                raise stops.Interrupted(signum, f"stopped by {stops.name(signum)} at step {steps} of "
                                        f"{config.num_chunks * config.chunk_steps}: results in {members[0].out_path}"
                                        f"{' and its sweep members' if len(members) > 1 else ''}, checkpoint in "
                                        f"{saved.path}; run the same command again to resume")
            if not complete and since_saved >= every:
                t0 = time.perf_counter()
                saved.save(index + 1, carry)
                took = time.perf_counter() - t0
                save_s += took
                took, slowest_chunk_s = agreed_max(took, chunk_s)  # all processes checkpoint on the same chunks
                every, since_saved = checkpoints.interval(took, slowest_chunk_s), 0
            bar.update(config.chunk_steps)
            bar.set_postfix(progress_figures(views(carry, metrics)[0][0]))
    finally:  # also when a write fails or a signal stops the run: files closed, the checkpoints' manager too
        bar.close()
        for writer in events:
            if writer is not None:
                writer.close()
        saved.close()
    return carry, documents


def finish(member: Member, document: dict, gait: dict, agent_states) -> dict:
    """The results file completed: the gait record, the saved policy and the agents beside it."""
    document["gait"] = gait_record(member, gait)
    document["agents"] = checkpoints.save_agents(member.out_path, agent_states).name  # every process: orbax's own
    document["policy"] = policy.path_for(member.out_path).name
    actor = gather((agent_states.actor_params, agent_states.actor_stats))  # every process takes part
    if writes():
        save_policy(member, actor, document)
        document["complete"] = True  # last: a run stopped before this point resumes from its checkpoint
        results.write(member.out_path, document)
    return document


def save_policy(member: Member, actor: tuple, document: dict) -> Path:
    """Every seed's final actor (parameters, statistics) beside the results file, in policy.py's NumPy format."""
    env = member.env
    params, stats = actor
    meta = {"seeds": document["seeds"], "config": document["config"], "control_hz": env.control_hz,
            "observation_layout": [list(block) for block in env.observation_layout],
            "observation_size": env.observation_size, "action_size": env.action_size}
    return policy.save(policy.path_for(member.out_path), params, stats, meta)


def _partial(path: Path, fresh: dict) -> dict | None:
    """The incomplete results file of this very configuration and seeds at `path`, or None."""
    if not Path(path).exists():
        return None
    try:
        previous = results.read(path)
    except ValueError as error:
        raise Refused(f"cannot resume: {error}; move it away, or start the run over (train, sweep: --restart; "
                      "reproduce: --force)") from None
    if fresh is None:
        return previous
    same = previous["config"] == json.loads(json.dumps(fresh["config"])) and previous["seeds"] == fresh["seeds"]
    return previous if same and not previous.get("complete") else None


def _truncated(document: dict, chunks: int) -> dict:
    """`document` as it was after `chunks` chunks (the rows past the checkpoint are run again)."""
    document["steps"], document["sim_minutes"] = document["steps"][:chunks], document["sim_minutes"][:chunks]
    document["metrics"] = {name: rows[:chunks] for name, rows in document["metrics"].items()}
    return document


def note_divergence(document: dict, diverged_at, out_path: Path) -> None:
    """Record each seed's `diverged_at_step` (train.py freezes such a seed) and say so once when one diverges."""
    steps = [None if step < 0 else int(step) for step in np.asarray(diverged_at).reshape(-1)]
    before = document.get("diverged_at_step") or [None] * len(steps)
    for seed, old, new in zip(document["seeds"], before, steps):
        if old is None and new is not None:
            tqdm.write(f"{out_path.name}: seed {seed} went non-finite by step {new}; frozen there, the others go on",
                       file=sys.stderr)
    document["diverged_at_step"] = steps


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


def gait_record(member: Member, trace: dict) -> dict:
    """Foot contacts and forward velocity at the physics rate from a deterministic run after training (`trace`)."""
    env = member.env
    return {
        "physics_dt": env.mj_model.opt.timestep,
        "seconds": member.config.gait_seconds / 2,
        "command": list(map(float, next(iter(env.task.eval_commands.values())))),
        "contacts": np.asarray(trace["contacts"], dtype=int).tolist(),
        "forward_velocity": np.asarray(trace["forward_velocity"], dtype=float).round(4).tolist(),
    }
