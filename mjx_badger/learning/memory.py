"""The memory a run needs, from its carry's shapes, checked against this machine's before anything compiles.

A training run holds every seed's carry (replay buffer, agent, env state) for its whole length:
the buffer is allocated at its full size when the run starts, so the peak is known before.
The estimate is the carry's bytes (jax.eval_shape of the run's init: nothing is allocated)
times CARRY_COPIES, plus the process's own OVERHEAD_BYTES; benchmarks/bench_memory.py checks it
against the measured peak of real runs.
The on-robot loop's replay and trace live in host memory (realtime/memory.py).
"""

import functools
import math
import os

import jax

from mjx_badger.learning.train import make_train

GIB = 2**30
MIB = 2**20
OVERHEAD_BYTES = int(2.0 * GIB)
"""Python, JAX, MuJoCo and XLA compiling the chunk (benchmarks/results/memory_peak.json: about 1.5 GiB measured)."""


CARRY_COPIES = 2
"""The carry on the device and one more: the chunk's output before the donated input is freed, or the host
copy a checkpoint writes (on a CPU both are host memory)."""


def nbytes(tree) -> int:
    return sum(math.prod(x.shape) * x.dtype.itemsize for x in jax.tree.leaves(tree))


@functools.lru_cache(maxsize=64)
def carry_sizes(config) -> dict:
    """Bytes per seed of the replay buffer, the agent and the whole carry of a TrainConfig."""
    try:
        carry = jax.eval_shape(make_train(config).init, jax.random.PRNGKey(0))
    except (TypeError, KeyError, IndexError, ZeroDivisionError, AttributeError) as error:
        # A value of the right kind the run still cannot be built from (a protocol field's unknown word).
        raise ValueError(f"the run cannot be built from these settings: {type(error).__name__}: {error}") from None
    return {"replay_bytes": nbytes(carry.buffer), "agent_bytes": nbytes(carry.agent_state),
            "carry_bytes": nbytes(carry)}


def estimate(config, seeds: int, members: int = 1) -> int:
    """Bytes this process needs for `members` configurations like `config`, `seeds` seeds each."""
    share = _local_share(seeds * members)
    return OVERHEAD_BYTES + CARRY_COPIES * math.ceil(carry_sizes(config)["carry_bytes"] * seeds * members * share)


def _local_share(seeds: int) -> float:
    """The share of the seeds this process holds: all of them, unless they are split over several processes."""
    if seeds > 1 and jax.process_count() > 1:
        return jax.local_device_count() / jax.device_count()
    return 1.0


def available() -> tuple[int, int, str]:
    """(bytes available now, bytes in all, 'GPU memory' or 'memory') where the carry lives."""
    stats = jax.local_devices()[0].memory_stats() if jax.default_backend() != "cpu" else None
    if stats and "bytes_limit" in stats:
        return stats["bytes_limit"] - stats.get("bytes_in_use", 0), stats["bytes_limit"], f"{jax.default_backend().upper()} memory"
    return host_available(), host_total(), "memory"


def host_total() -> int:
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def host_available() -> int:
    """MemAvailable (what can be had without swapping), or the free pages where /proc/meminfo is missing."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")


def words(config, seeds: int, members: int = 1) -> str:
    """'memory: ~X GiB estimated (...), Y GiB available of Z GiB' for a plan."""
    sizes = carry_sizes(config)
    need = estimate(config, seeds, members)
    free, total, where = available()
    runs = f"{members} members x {seeds} seeds" if members > 1 else f"{seeds} seeds"
    return (f"memory: ~{need / GIB:.1f} GiB estimated ({runs} x {sizes['carry_bytes'] / MIB:.1f} MiB carry, "
            f"{sizes['replay_bytes'] / MIB:.1f} MiB of it replay, x{CARRY_COPIES}, + {OVERHEAD_BYTES / GIB:.1f} GiB "
            f"for the process); this machine has {free / GIB:.1f} GiB {where} available of {total / GIB:.1f} GiB")


def check(config, seeds: int, members: int = 1) -> None:
    """ValueError with the estimate and the machine's memory unless the run fits in what is available."""
    need = estimate(config, seeds, members)
    free, total, where = available()
    if need > free:
        raise ValueError(f"the run does not fit: {words(config, seeds, members).removeprefix('memory: ')}; "
                         "choose fewer --seeds or --steps")
