"""The compiled programs: one per configuration and seed count, one seed unbatched, this machine's speed timed."""

import time

import jax
import numpy as np
import pytest

from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.learning import programs, runner
from mjx_badger.learning.train import make_train
from tests.conftest import COMPILES, TINY_TRAIN, run_all_chunks, seed_keys, traced


def test_a_run_reuses_the_process_compiled_chunk_and_same_seed_gives_same_numbers(train_fns, tmp_path):
    """The chunk takes its start step as an argument (one program serves every chunk), and a later run of
    the same configuration and seed count in this process traces and compiles nothing of it again."""
    _, first = run_all_chunks(train_fns, [5, 7])
    since = len(COMPILES)
    document = runner.run(TINY_TRAIN, [5, 7], tmp_path / "again.json", progress=False, tensorboard=False)
    assert traced(since, "chunk") == 0 and document["wall_clock"]["compile_s"] == 0.0
    assert traced(since, "gait") <= 1  # its gait program: built once per process (here, or by an earlier test's run)
    since = len(COMPILES)
    runner.run(TINY_TRAIN, [5, 7], tmp_path / "third.json", progress=False, tensorboard=False)
    assert traced(since, "") == 0, COMPILES[since:]
    second = [{name: np.array(values[i], float) for name, values in document["metrics"].items()} for i in range(3)]
    for a, b in zip(first, second):
        for name in a:
            np.testing.assert_array_equal(np.asarray(a[name], float).round(5), b[name], err_msg=name)


def test_single_seed_runs_the_unbatched_program_with_the_same_numbers(tmp_path, train_fns):
    """programs.seeds_chunk skips vmap for one seed (faster on CPU); the warm-up chunk agrees to float rounding
    with seed 4 of a vmapped pair."""
    document = runner.run(TINY_TRAIN, [4], tmp_path / "one.json", progress=False)
    init, chunk = train_fns
    _, metrics = chunk(init(seed_keys([4, 5])), 0)
    for name, values in document["metrics"].items():
        expected = float(metrics[name][0])
        got = values[0][0]
        if got is None:
            assert np.isnan(expected), name
        else:
            # The stiff contacts of the thesis-code model (the reset drop) grow float32 summation-order
            # differences to ~1e-3 over a chunk; a wrong key or carry would differ at order one.
            np.testing.assert_allclose(got, expected, rtol=2e-2, atol=2e-3, err_msg=name)


def test_the_timed_chunk_evaluates_as_long_per_learning_step_as_the_run():
    config = TINY_TRAIN
    cut = programs.short_run(config, 20, evaluation=True)
    assert cut.eval_steps / cut.chunk_steps == pytest.approx(config.eval_steps / config.chunk_steps, rel=0.05)
    assert programs.short_run(config, 20).eval_steps == 1  # the learner's own rate (benchmarks)


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_a_short_chunk_is_timed_on_this_machine():
    measured = programs.measure_speed(TINY_TRAIN, [0, 1], steps=20)
    assert measured["compile_s"] > 0  # the short program is its own: compiled here
    # Its rate is what a chunk of that program takes here, timed apart (within a loaded machine's spread).
    carry, chunk, compile_s = programs.compiled(make_train(programs.short_run(TINY_TRAIN, 20)), [0, 1])
    assert compile_s == 0.0  # the process kept it
    carry, _ = jax.block_until_ready(chunk(carry, 0))
    started = time.perf_counter()
    jax.block_until_ready(chunk(carry, 20))
    timed = 2 * 20 / (time.perf_counter() - started)
    assert timed / 3 < measured["seed_steps_per_s"] < 3 * timed


class _Recording:
    """A trainer of one number whose tracing is logged beside JAX's cache clearing."""

    def __init__(self, log):
        self.config, self.log = ("recording", id(self)), log

    def init(self, key):
        self.log.append("traced")
        return {"x": jax.random.uniform(key, (2,))}

    def chunk(self, carry, start):
        return {"x": carry["x"] + start}, {"sum": carry["x"].sum()}

    def gait(self, carry):
        return carry["x"]


def test_a_new_program_is_traced_from_a_clean_slate(monkeypatch):
    """What the process traced before must not shape the module (the compile cache's key); see the slow test."""
    log = []
    monkeypatch.setattr(programs.jax, "clear_caches", lambda: log.append("cleared"))
    built, _ = programs.program(_Recording(log), 2)
    assert log[0] == "cleared" and log.count("cleared") == 1 and "traced" in log
    carry, metrics = built.chunk(built.init(seed_keys([0, 1])), 3)
    np.testing.assert_allclose(np.asarray(metrics["sum"]) + 6, np.asarray(carry["x"]).sum(axis=1))


@pytest.mark.slow  # three CPG and JT programs traced (no compile): a minute or two
def test_a_programs_module_does_not_depend_on_what_the_process_traced_before():
    """Traced after JT-OEF's chunk without a clean slate, CPG-D's smoke chunk lowers to another module (8.48 MB of
    text against 8.46 MB), so a requeued or resumed run in a new process would miss the compile cache."""
    experiment = EXPERIMENTS["real-outdoor-omni"]
    trainers = {run.approach: make_train(experiment.train_config(run, "smoke")) for run in experiment.runs}
    first = programs.lowered_chunk(trainers["cpg-d"], 2).as_text()
    programs.lowered_chunk(trainers["jt-oef"], 2)
    assert programs.lowered_chunk(trainers["cpg-d"], 2).as_text() == first
