"""The smoke profile's runs three ways: here one after another, two at once in processes of their own, and as a
SLURM job array on a one-node SLURM started here, one task requeued mid-run; the numbers agree seed for seed.

One experiment of the smoke profile (real-outdoor-omni: two runs) keeps it to two compiled programs; the second and
third ways load them from the compile cache the first wrote.
"""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests import slurm_here

EXPERIMENT = "real-outdoor-omni"
COMMAND = [sys.executable, "-m", "mjx_badger", "reproduce", "--profile", "smoke", "--experiments", EXPERIMENT,
           "--no-tensorboard"]


def numbers(results_dir: Path) -> dict:
    """Each run's steps and metrics, by file name (what a seed learned, not when or how fast)."""
    folder = results_dir / "smoke" / "thesis-code" / EXPERIMENT
    documents = {path.name: json.loads(path.read_text()) for path in sorted(folder.glob("*.json"))}
    assert documents and all(d["complete"] for d in documents.values())
    return {name: (d["seeds"], d["steps"], d["metrics"]) for name, d in documents.items()}


def wait_for(condition, timeout_s: float, what: str) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.2)


@pytest.fixture(scope="module")
def here(tmp_path_factory) -> Path:
    """The runs made here, one after another in this process's way (the reference)."""
    folder = tmp_path_factory.mktemp("here")
    subprocess.run(COMMAND + ["--results-dir", str(folder), "--no-draw"], check=True, capture_output=True)
    return folder


def test_two_runs_per_device_give_the_numbers_of_two_runs_one_after_the_other(here, tmp_path):
    done = subprocess.run(COMMAND + ["--results-dir", str(tmp_path), "--no-draw", "--runs-per-device", "2"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "2 runs to train (local, 2 per device)" in done.stdout and "2 of 2 runs ended" in done.stdout
    assert numbers(tmp_path) == numbers(here)


def test_the_smoke_profile_on_slurm_with_a_task_requeued_mid_run_equals_the_runs_made_here(here, tmp_path):
    why = slurm_here.unavailable()
    if why:
        pytest.skip(why)
    results = tmp_path / "results"
    with slurm_here.cluster(tmp_path / "slurm") as env:
        launched = subprocess.Popen(COMMAND + ["--results-dir", str(results), "--launcher", "slurm", "--slurm-cpus",
                                               "1", "--slurm-mem-gb", "6", "--slurm-time-min", "30"],
                                    env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            # Task 0 trains the experiment's first run: once its first chunk is saved, it is stopped there and
            # sent submitit's time-out signal, then let go: it checkpoints, requeues itself and exits.
            first = results / "smoke" / "thesis-code" / EXPERIMENT / "jt-oef_crossq_omni-random"
            saved = lambda: any(step.name.isdigit() for step in first.with_suffix(".ckpt").glob("*"))  # finalised
            wait_for(saved, 900, "the first run's first checkpoint")
            task = next((results / "slurm").glob("*_0")).name
            for sent in ("STOP", "USR2", "CONT"):
                subprocess.run(["scancel", f"--signal={sent}", task], env=env, check=True)
            # SLURM holds a requeued job two minutes before it may start again; the test lets it go at once.
            wait_for(lambda: slurm_here.restarts(env, task) == 1, 120, "the task's requeue")
            subprocess.run(["scontrol", "update", f"JobId={task}", "StartTime=now"], env=env, check=True)
            output, _ = launched.communicate(timeout=1200)
            requeued = slurm_here.restarts(env, task)
        finally:
            launched.kill()
    assert launched.returncode == 0, output[-3000:]
    assert requeued == 1, output[-3000:]
    log = "".join(path.read_text() for path in (results / "slurm" / task).glob("*_log.err"))
    assert "resuming jt-oef_crossq_omni-random.json at step" in log, log[-3000:]
    assert "2 of 2 tasks ended" in output and "FAILED" not in output
    assert numbers(results) == numbers(here)
    # Drawn here once every task has landed, as a local run draws them.
    assert (results / "figures" / "claims_smoke.md").is_file()
    assert os.listdir(results / "figures" / "thesis-code")
