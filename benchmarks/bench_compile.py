"""Where compile time goes: tracing and lowering in Python against compiling in XLA, per program.

    python -m benchmarks.bench_compile [--out benchmarks/results/compile.json] [--durations FILE]

For a tiny and a quick configuration of JT-OEF and CPG-D with CrossQ (2 seeds, as `train` vmaps
them), each of the three programs a run compiles (the training chunk, whose evaluation is part of
it; the evaluation alone; the gait record) is traced, lowered and compiled by XLA with the
persistent cache off, each phase timed, and the MJX steps counted: the constraint solver's
while loops inside the `mjx_step` scope (env.py), over those of one `mjx.step` compiled alone.
Then the same `train` run twice into one cache folder, in two processes: time to the first chunk
with an empty and with a warm cache. With `--durations` (the output of `pytest --durations=0`)
and `--compile-log` (the folder its processes wrote with MJX_BADGER_COMPILE_LOG set), the share of the
test suite's time spent compiling.
"""

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import jax
import jax.numpy as jnp

from benchmarks.common import RESULTS
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.programs import seeds_chunk
from mjx_badger.learning.train import make_train
from mjx_badger.records import results
from mjx_badger.sim.env import HB40Env

CONFIGS = {
    "tiny": dict(total_steps=300, chunk_steps=100, warmup_steps=100, eval_steps=20),
    "quick": dict(total_steps=20_000, chunk_steps=1_000, warmup_steps=1_000, eval_steps=400),
}
"""tiny: the tests' training run (conftest.TINY_TRAIN); quick: the quick profile's shapes."""
APPROACHES = ("jt-oef", "cpg-d")
SEEDS = 2


def solver_loops(compiled_text: str) -> int:
    """While loops of the compiled program that belong to an MJX step (op names under the `mjx_step` scope)."""
    return sum("mjx_step" in line for line in compiled_text.splitlines() if re.search(r"\swhile\(", line))


def phases(fn, *args) -> dict:
    """Seconds to trace, lower and XLA-compile `jit(fn)(*args)`, the jaxpr's size and the MJX steps inside."""
    t0 = time.perf_counter()
    traced = jax.jit(fn).trace(*args)
    t1 = time.perf_counter()
    lowered = traced.lower()
    t2 = time.perf_counter()
    compiled = lowered.compile()
    t3 = time.perf_counter()
    text = compiled.as_text()
    return {"trace_s": round(t1 - t0, 2), "lower_s": round(t2 - t1, 2), "xla_compile_s": round(t3 - t2, 2),
            "jaxpr_equations": _equations(traced.jaxpr.jaxpr), "hlo_lines": text.count("\n"),
            "solver_loops": solver_loops(text)}


def _equations(jaxpr) -> int:
    """Equations of a jaxpr, those of the sub-jaxprs (scan and cond bodies, calls) included."""
    count = 0
    for equation in jaxpr.eqns:
        count += 1
        for value in equation.params.values():
            for sub in value if isinstance(value, (tuple, list)) else (value,):
                inner = getattr(sub, "jaxpr", sub)
                if hasattr(inner, "eqns"):
                    count += _equations(inner)
    return count


def one_step_loops() -> int:
    """Solver while loops of one MJX step, compiled alone inside the same scope."""
    env = HB40Env("jt-oef", "forward")
    from mujoco import mjx

    def step(data):
        with jax.named_scope("mjx_step"):
            return mjx.step(env.mjx_model, data)

    return solver_loops(jax.jit(step).lower(env._init_data).compile().as_text())


def programs(approach: str, shape: str) -> dict:
    """The three programs of one configuration, measured."""
    config = TrainConfig(approach=approach, algo="crossq", task="forward", **CONFIGS[shape])
    trainer = make_train(config)
    keys = jax.vmap(jax.random.PRNGKey)(jnp.arange(SEEDS))
    carry = jax.jit(jax.vmap(trainer.init))(keys)
    return {"chunk": phases(seeds_chunk(trainer, SEEDS), carry, 0),
            "evaluation": phases(jax.vmap(trainer.evaluate), carry),
            "gait": phases(jax.vmap(trainer.gait), carry)}


FIRST_CHUNK = """
import sys, time
t0 = time.perf_counter()
from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.learning import programs
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
enable_compilation_cache(sys.argv[1])
imported = time.perf_counter() - t0
config = TrainConfig(approach="jt-oef", algo="crossq", task="forward", total_steps=20000)
carry, chunk, compile_s = programs.compiled(make_train(config), [0, 1])
import jax; jax.block_until_ready(carry)
starts = time.perf_counter() - t0
carry, metrics = chunk(carry, 0)
jax.block_until_ready(metrics)
print(imported, starts, time.perf_counter() - t0, compile_s)
"""


def first_chunk_times() -> dict:
    """A quick JT-OEF CrossQ `train` of 2 seeds to the end of its first chunk, twice in two processes sharing a
    cache folder: seconds from the process start to the imports done, to the first chunk's start (its initial
    carry ready) and to its end, and the compile seconds the runner measured."""
    with tempfile.TemporaryDirectory() as cache:
        runs = []
        for _ in range(2):
            done = subprocess.run([sys.executable, "-c", FIRST_CHUNK, cache], capture_output=True, text=True,
                                  check=True)
            imported, starts, total, compile_s = map(float, done.stdout.split()[-4:])
            runs.append({"imports_s": round(imported, 2), "to_first_chunk_start_s": round(starts, 2),
                         "to_first_chunk_s": round(total, 2), "compile_s": round(compile_s, 2)})
    return {"empty_cache": runs[0], "warm_cache": runs[1]}


def compile_share(durations: Path, compile_log: Path | None) -> dict:
    """The test suite's seconds (`pytest --durations=0` output) and, from the compile log the test processes
    wrote (conftest.py, MJX_BADGER_COMPILE_LOG), the seconds they spent tracing, lowering and in XLA."""
    rows = [float(s) for s in re.findall(r"^([\d.]+)s (?:call|setup|teardown)\s", durations.read_text(), re.M)]
    total = sum(rows)
    share = {"test_seconds": round(total, 1), "tests_over_10_s": sum(s > 10.0 for s in rows)}
    if compile_log is not None:
        spent = {}
        for path in sorted(set(compile_log.glob("*.json")) - set(compile_log.glob("*.programs.json"))):
            for phase, seconds in json.loads(path.read_text()).items():
                spent[phase] = spent.get(phase, 0.0) + seconds
        share |= {k: round(v, 1) for k, v in spent.items()}
        share["compile_share"] = round(sum(spent.values()) / total, 3) if total else None
    return share


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=RESULTS / "compile.json")
    parser.add_argument("--durations", type=Path, help="`pytest --durations=0` output of a test run")
    parser.add_argument("--compile-log", type=Path, help="the MJX_BADGER_COMPILE_LOG folder of that run")
    parser.add_argument("--only", choices=tuple(CONFIGS), help="one configuration shape")
    parser.add_argument("--note", default="", help="what else ran on the machine")
    parser.add_argument("--first-chunk-only", action="store_true",
                        help="time only the first chunk with an empty and a warm cache; update it in --out")
    args = parser.parse_args()
    if args.first_chunk_only:
        measured = json.loads(args.out.read_text())
        measured["first_chunk"] = dict(first_chunk_times(), date=results.now(), git_commit=results.git_commit(),
                                       note=args.note)
        args.out.write_text(json.dumps(measured, indent=1) + "\n")
        print("first chunk", measured["first_chunk"])
        return
    jax.config.update("jax_enable_compilation_cache", False)  # measure XLA, not the disk
    measured = {"what": results.what(__doc__), "date": results.now(), "git_commit": results.git_commit(),
                "hardware": results.hardware(), "note": args.note, "seeds": SEEDS,
                "solver_loops_per_mjx_step": one_step_loops(), "programs": {}}
    for shape in ([args.only] if args.only else CONFIGS):
        for approach in APPROACHES:
            name = f"{approach}-crossq-{shape}"
            measured["programs"][name] = programs(approach, shape)
            print(name, json.dumps(measured["programs"][name]), flush=True)
    measured["first_chunk"] = first_chunk_times()
    print("first chunk", measured["first_chunk"], flush=True)
    if args.durations:
        measured["make_test"] = compile_share(args.durations, args.compile_log)
    measured["hardware"] = results.hardware()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(measured, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
