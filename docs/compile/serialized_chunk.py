"""Whether the tiny run's compiled chunk survives `jax.experimental.serialize_executable` between processes.

    PYTHONPATH=. python docs/compile/serialized_chunk.py

Keeping the traced and compiled chunk on disk would let a warm start skip tracing and lowering (about 7 s of
the quick run's 8.8 s to its first chunk). One process compiles and serializes the chunk, a second loads it
and runs three chunks; each prints its seconds and a hash of the metrics. Writes
docs/compile/serialized_chunk.json with both processes' exit codes and output.
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

from mjx_badger.records import results

PROCESS = """
import hashlib, pickle, sys, time
t0 = time.perf_counter()
import jax, jax.numpy as jnp, numpy as np
from jax.experimental import serialize_executable
from mjx_badger.learning import programs
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
mode, path = sys.argv[1], sys.argv[2]
trainer = make_train(TrainConfig(approach="jt-oef", algo="crossq", task="forward", total_steps=300, chunk_steps=100,
                                 warmup_steps=100, eval_steps=20))
keys = jax.vmap(jax.random.PRNGKey)(jnp.arange(2))
init = jax.jit(jax.vmap(trainer.init))
if mode == "save":
    chunk = jax.jit(programs.seeds_chunk(trainer, 2)).lower(jax.eval_shape(init, keys), 0).compile()
    with open(path, "wb") as file:
        pickle.dump(serialize_executable.serialize(chunk), file)
else:
    with open(path, "rb") as file:
        chunk = serialize_executable.deserialize_and_load(*pickle.load(file))
print("program ready after", round(time.perf_counter() - t0, 2), "s", flush=True)
carry, digest = init(keys), hashlib.sha256()
for start in (0, 100, 200):
    carry, metrics = chunk(carry, start)
    for leaf in jax.tree.leaves(metrics):
        digest.update(np.asarray(leaf).tobytes())
print("three chunks after", round(time.perf_counter() - t0, 2), "s, metrics hash", digest.hexdigest()[:16])
"""


def main():
    with tempfile.TemporaryDirectory() as folder:
        path = str(Path(folder) / "chunk.pkl")
        runs = {}
        for mode in ("save", "load"):
            done = subprocess.run([sys.executable, "-c", PROCESS, mode, path], capture_output=True, text=True)
            runs[mode] = {"returncode": done.returncode, "stdout": done.stdout.strip().splitlines()}
            print(mode, runs[mode])
        runs["serialized_bytes"] = Path(path).stat().st_size
    runs.update(date=results.now(), git_commit=results.git_commit(), versions=results.versions())
    out = Path(__file__).with_suffix(".json")
    out.write_text(json.dumps(runs, indent=1) + "\n")
    print("wrote", out)


if __name__ == "__main__":
    main()
