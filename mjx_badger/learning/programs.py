"""The compiled programs of a training run: its chunk for a number of seeds, on one device or split over several,
kept per process so that a run of the same shapes neither traces nor compiles again; and this machine's speed."""

import collections
import dataclasses
import time
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train


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


def fresh_trace() -> None:
    """Forget what this process traced before, so a program's module is the one a new process builds.

    JAX reuses the traces of its jitted helpers (jnp.remainder, ...) from bounded caches: after another large
    program, some are traced anew and lowered as separate functions, so the module, and with it the compile
    cache's key, depends on what ran before (a CPG-D chunk after JT-OEF's: 8.48 MB against 8.46 MB of text). A
    resumed or requeued run in a new process would then miss the cache a sequential run wrote, and compile again.
    The price: this process's other jitted functions trace again and load from the compile cache.
    """
    jax.clear_caches()


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


def lowered_chunk(trainer, num_seeds: int):
    """`trainer`'s chunk for `num_seeds` seeds, traced from a clean slate (fresh_trace) and lowered, not compiled."""
    fresh_trace()
    carry = jax.eval_shape(jax.vmap(trainer.init), jax.vmap(jax.random.PRNGKey)(jnp.arange(num_seeds)))
    return jax.jit(seeds_chunk(trainer, num_seeds), donate_argnums=0).lower(carry, 0)


def program(trainer, num_seeds: int) -> tuple[Program, float]:
    """(`trainer`'s program for `num_seeds` seeds, seconds spent compiling it now: 0 when this process had it)."""
    key = (trainer.config, num_seeds)
    if key in _PROGRAMS:
        _PROGRAMS.move_to_end(key)
        return _PROGRAMS[key], 0.0
    t0 = time.perf_counter()
    chunk = lowered_chunk(trainer, num_seeds).compile()
    built = Program(jax.jit(jax.vmap(trainer.init)), chunk, jax.jit(jax.vmap(trainer.gait)))
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
    fresh_trace()
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
