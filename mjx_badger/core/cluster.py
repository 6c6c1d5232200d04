"""Several processes, on one host or many, through jax.distributed: who writes, gathering, waiting.

Each process runs the one-device programs of its own devices (learning/programs.py); process 0
gathers every chunk's metrics and writes the results. Checkpoints need a folder all processes
share (orbax writes each process's shards).
"""

import itertools

import jax

WAIT_MS = 6 * 3600 * 1000
"""How long a process waits for the others at a barrier: longer than any chunk or compile."""
_barriers = itertools.count()


def join(coordinator: str | None, num_processes: int | None, process_id: int | None) -> None:
    """Start jax.distributed (every argument None: the cluster JAX detects, Slurm, Open MPI or Cloud TPU)."""
    jax.config.update("jax_cpu_collectives_implementation", "gloo")  # how CPU processes gather
    jax.distributed.initialize(coordinator, num_processes, process_id)


def writes() -> bool:
    """Whether this process writes the results: the only one, or process 0 of several."""
    return jax.process_index() == 0


def wait_for_peers() -> None:
    """Wait for every process (none in one process), through the coordination service's barrier.

    Gloo's own collectives give up after 30 s without the peer, less than a compile can differ
    between processes, so every gather waits here first.
    """
    if jax.process_count() > 1:
        from jax._src import distributed

        distributed.global_state.client.wait_at_barrier(f"mjx_badger_{next(_barriers)}", WAIT_MS)


def gather(tree):
    """`tree` on the host, whole: the seed-sharded arrays of every process joined."""
    if jax.process_count() == 1:
        return jax.device_get(tree)
    from jax.experimental import multihost_utils

    wait_for_peers()
    return multihost_utils.process_allgather(tree, tiled=True)


def agreed_max(*values: float) -> tuple:
    """The largest of each value over all processes, so that every process takes the same decision."""
    if jax.process_count() == 1:
        return values
    import numpy as np
    from jax.experimental import multihost_utils

    wait_for_peers()
    return tuple(np.max(multihost_utils.process_allgather(np.asarray(values, np.float64)), axis=0).tolist())


def agree(flag: bool) -> bool:
    """True on every process once it is on any of them (one process alone: `flag`), so all stop at the same chunk."""
    return bool(agreed_max(float(flag))[0]) if jax.process_count() > 1 else flag
