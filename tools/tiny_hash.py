"""A hash of the tiny run's metrics (three chunks, two seeds) through `programs.compiled`, to check that a change
keeps every number: run it on the old and the new commit and compare.

    MJX_BADGER_CACHE=$(mktemp -d) python -m tools.tiny_hash jt-oef

With XLA_FLAGS set, it also shows whether an XLA option changes the numbers, and prints the chunk's
compile seconds by phase (tracing, lowering, XLA).
"""

import hashlib
import json
import os
import sys

import jax
import jax.monitoring
import numpy as np

from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.learning import programs
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train

PHASES = {"/jax/core/compile/jaxpr_trace_duration": "trace_s", "/jax/core/compile/jaxpr_to_mlir_module_duration":
          "lower_s", "/jax/core/compile/backend_compile_duration": "xla_compile_s"}
spent = {}


def _count(event: str, duration: float, fun_name: str = "", **_) -> None:
    if event in PHASES and "chunk" in fun_name:
        spent[PHASES[event]] = spent.get(PHASES[event], 0.0) + duration


def main():
    approach = sys.argv[1] if len(sys.argv) > 1 else "jt-oef"
    enable_compilation_cache()
    jax.monitoring.register_event_duration_secs_listener(_count)
    tiny = TrainConfig(approach=approach, algo="crossq", task="forward", total_steps=300, chunk_steps=100,
                       warmup_steps=100, eval_steps=20)
    carry, chunk, compile_s = programs.compiled(make_train(tiny), [0, 1])
    rows = []
    for index in range(tiny.num_chunks):
        carry, metrics = chunk(carry, index * tiny.chunk_steps)
        rows.append({k: np.asarray(v).tolist() for k, v in sorted(jax.device_get(metrics).items())})
    digest = hashlib.sha256(json.dumps(rows).encode()).hexdigest()[:16]
    print(json.dumps({"approach": approach, "xla_flags": os.environ.get("XLA_FLAGS", ""), "hash": digest,
                      "compile_s": round(compile_s, 1), "phases": {k: round(v, 1) for k, v in spent.items()}}))


if __name__ == "__main__":
    main()
