"""Checkpoints: an interrupted run resumes from its last checkpoint and ends with the numbers of an uninterrupted one."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.cli.main import main
from mjx_badger.core import launch
from mjx_badger.learning import checkpoints
from mjx_badger.records import results
from tests.conftest import TINY_TRAIN

# The tiny run of the other tests (conftest.TINY_TRAIN), two seeds: its program is compiled once per test run.
TRAIN = ["train", "--approach", TINY_TRAIN.approach, "--task", TINY_TRAIN.task, "--steps", str(TINY_TRAIN.total_steps),
         "--chunk-steps", str(TINY_TRAIN.chunk_steps), "--warmup-steps", str(TINY_TRAIN.warmup_steps), "--eval-steps",
         str(TINY_TRAIN.eval_steps), "--seeds", "2", "--quiet"]
RESULT = f"{TINY_TRAIN.name}.json"


def _carry(scale: float):
    return {"weights": jnp.arange(6.0) * scale, "key": jax.random.PRNGKey(7), "count": jnp.int32(3)}


def test_the_newest_readable_checkpoint_is_restored_bit_for_bit(tmp_path):
    saved = checkpoints.Checkpoints(tmp_path / "run.json", {"config": {"a": 1}, "seeds": [0]})
    saved.save(1, _carry(1.0))
    saved.save(2, _carry(2.0))
    step, carry = saved.restore(_carry(0.0))
    assert step == 2 and np.array_equal(carry["weights"], np.arange(6.0) * 2.0)
    assert np.array_equal(carry["key"], jax.random.PRNGKey(7)) and carry["key"].dtype == jnp.uint32
    # Damage the newest: the one before it is used.
    for path in (saved.path / "2").rglob("*"):
        if path.is_file() and path.name != "commit_success.txt":
            path.write_bytes(b"\0garbage")
    with pytest.warns(UserWarning, match="cannot be read.*trying an older one"):
        step, carry = saved.restore(_carry(0.0))
    assert step == 1 and np.array_equal(carry["weights"], np.arange(6.0))
    # Another configuration's checkpoints are not this run's.
    other = checkpoints.Checkpoints(tmp_path / "run.json", {"config": {"a": 2}, "seeds": [0]})
    assert other.restore(_carry(0.0)) is None
    saved.remove()
    assert not saved.path.exists()


def test_checkpoints_another_carry_wrote_are_replaced_when_the_run_starts_over(tmp_path):
    """Code whose carry has another leaf cannot resume from them: the run starts over and saves over them."""
    identity = {"config": {"a": 1}, "seeds": [0]}
    old = checkpoints.Checkpoints(tmp_path / "run.json", identity)
    old.save(1, _carry(1.0))
    old.save(3, _carry(3.0))
    grown = lambda scale: dict(_carry(scale), frozen=jnp.int32(-1))
    new = checkpoints.Checkpoints(tmp_path / "run.json", identity)
    with pytest.warns(UserWarning, match="cannot be read"):
        assert new.restore(grown(0.0)) is None
    new.save(1, grown(5.0))  # orbax used to refuse: step 1 already existed
    assert new.manager.all_steps() == [1]
    step, carry = new.restore(grown(0.0))
    assert step == 1 and np.array_equal(carry["weights"], np.arange(6.0) * 5.0)


def test_final_agents_are_saved_and_loaded_bit_for_bit(tmp_path):
    agents = {"actor": jnp.arange(8.0).reshape(2, 4), "empty": jnp.zeros((2, 0)), "updates": jnp.array([5, 6])}
    checkpoints.save_agents(tmp_path / "run.json", agents)
    like = jax.tree.map(jnp.zeros_like, agents)
    loaded = checkpoints.load_agents(tmp_path / "run.json", like)
    assert all(np.array_equal(a, b) and a.dtype == b.dtype for a, b in zip(jax.tree.leaves(loaded), jax.tree.leaves(agents)))


def test_the_interval_keeps_checkpointing_under_five_percent():
    assert checkpoints.interval(save_s=0.1, chunk_s=20.0) == 1
    assert checkpoints.interval(save_s=3.0, chunk_s=20.0) == 3  # 3 s per 60 s of training = 5 %


def _without_clock(document: dict) -> dict:
    return {k: v for k, v in document.items() if k not in ("wall_clock", "hardware", "versions", "git_commit")}


def test_a_run_killed_mid_way_resumes_to_the_uninterrupted_results(tmp_path):
    """SIGKILL once two of the three chunks are written; the newest checkpoint is dropped, so the run
    resumes from chunk 1 behind its results file (whose later rows must go) and ends as the whole run."""
    assert main([*TRAIN, "--out", str(tmp_path / "whole")]) == 0  # in this process: the suite's tiny program
    env = dict(os.environ, CI="1")
    out = tmp_path / "killed"
    process = subprocess.Popen([sys.executable, "-m", "mjx_badger", *TRAIN, "--out", str(out)], env=env,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ckpt = checkpoints.folder(out / RESULT)
    deadline = time.time() + 900
    while time.time() < deadline and process.poll() is None:
        try:
            done = json.loads((out / RESULT).read_text())["steps"]
        except (FileNotFoundError, json.JSONDecodeError):
            done = []
        if len(done) == 2 and (ckpt / "1").exists():
            break
        time.sleep(0.02)
    assert process.poll() is None, "the run ended before it could be killed mid-way"
    process.send_signal(signal.SIGKILL)
    process.wait()
    shutil.rmtree(ckpt / "2", ignore_errors=True)  # as if killed between writing row 2 and its checkpoint
    interrupted = json.loads((out / RESULT).read_text())
    assert not interrupted["complete"] and len(interrupted["steps"]) == 2

    resumed = subprocess.run([sys.executable, "-m", "mjx_badger", *TRAIN, "--out", str(out)], env=env,
                             capture_output=True, text=True, timeout=900)
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    assert f"resuming {RESULT} at step {TINY_TRAIN.chunk_steps}" in resumed.stderr
    expected, got = (results.read(Path(folder) / RESULT) for folder in (tmp_path / "whole", out))
    assert _without_clock(got) == _without_clock(expected)
    assert not ckpt.exists()  # a complete run keeps no checkpoints


def test_a_cluster_jobs_runs_checkpoint_every_chunk_whatever_saving_costs(monkeypatch):
    schedule = checkpoints.Schedule()
    schedule.saved(save_s=10.0, chunk_s=1.0)  # here: saving is dear, so it waits many chunks
    assert schedule.every > 1
    monkeypatch.setenv(launch.EVERY_CHUNK, "1")
    schedule.saved(save_s=10.0, chunk_s=1.0)
    assert schedule.every == 1 and schedule.due()
