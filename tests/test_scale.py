"""Seeds split over devices: the same numbers as on one device (a 2-device CPU in a subprocess)."""

import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import TINY_TRAIN
from mjx_badger import results, runner

TWO_CPU_DEVICES = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2")


def _train(out, seeds, env):
    command = [sys.executable, "-m", "mjx_badger", "train", "--approach", TINY_TRAIN.approach, "--task",
               TINY_TRAIN.task, "--total-steps", str(TINY_TRAIN.total_steps), "--chunk-steps",
               str(TINY_TRAIN.chunk_steps), "--warmup-steps", str(TINY_TRAIN.warmup_steps), "--eval-steps",
               str(TINY_TRAIN.eval_steps), "--seeds", str(seeds), "--out", str(out), "--quiet", "--no-tensorboard"]
    return subprocess.run(command, env=env, capture_output=True, text=True)


def test_seeds_sharded_over_two_devices_give_the_numbers_of_one_device(tmp_path):
    """Each device runs the one-device program of its seeds: 2 seeds on 2 devices are two one-seed runs."""
    done = _train(tmp_path / "sharded", 2, TWO_CPU_DEVICES)
    assert done.returncode == 0, done.stderr[-2000:]
    sharded = results.read(tmp_path / "sharded" / f"{TINY_TRAIN.name}.json")
    assert sharded["hardware"]["jax_devices"] == ["cpu:0", "cpu:1"]
    alone = []
    for seed in (0, 1):
        path = tmp_path / f"seed{seed}" / f"{TINY_TRAIN.name}.json"
        runner.run(TINY_TRAIN, [seed], path, progress=False, tensorboard=False)
        alone.append(results.read(path))
    assert alone[0]["hardware"]["jax_devices"] == ["cpu:0"]
    assert sharded["metrics"].keys() == alone[0]["metrics"].keys()
    together = {name: np.array([one["metrics"][name] for one in alone], float)[:, :, 0].T  # [chunk][seed]
                for name in sharded["metrics"]}
    for name, rows in together.items():
        np.testing.assert_array_equal(np.array(sharded["metrics"][name], float), rows, err_msg=name)
    for name in ("contacts", "forward_velocity"):  # the gait record after training, per seed
        assert sharded["gait"][name] == alone[0]["gait"][name] + alone[1]["gait"][name]


def test_seeds_that_do_not_split_over_the_devices_are_refused_before_anything_compiles(tmp_path):
    done = _train(tmp_path, 3, TWO_CPU_DEVICES)
    assert done.returncode == 2
    assert "3 seeds do not split evenly over 2 devices" in done.stderr and "Traceback" not in done.stderr
    with pytest.raises(ValueError, match="multiple of 2"):
        runner.check_seeds_divide(5, 2)
    runner.check_seeds_divide(1, 2)  # one seed runs on the first device


def test_the_full_profile_estimate_is_measured_once_per_algorithm(monkeypatch):
    from mjx_badger import cli
    from mjx_badger.experiments import EXPERIMENTS

    timed = []

    def fake_measure(config, seeds):
        timed.append((config.algo, len(seeds)))
        return {"seed_steps_per_s": 100.0 if config.algo == "crossq" else 10.0, "compile_s": 60.0}

    monkeypatch.setattr(runner, "measure", fake_measure)
    experiment = EXPERIMENTS["algo-comparison"]
    todo = [(experiment, run, None) for run in experiment.runs]
    args = cli.Reproduce(profile="full")
    line = cli.measured_estimate(todo, args, seeds=10)
    assert sorted(timed) == sorted((run.algo, 10) for run in experiment.runs)  # one short chunk per algorithm
    expected_s = sum(experiment.steps(run, "full") * 10 / (100.0 if run.algo == "crossq" else 10.0) + 60.0
                     for run in experiment.runs)
    assert f"about {expected_s / 3600:.1f} h for these 4 runs" in line


def test_a_short_chunk_is_timed_on_this_machine():
    measured = runner.measure(TINY_TRAIN, [0, 1], steps=20)
    assert measured["seed_steps_per_s"] > 0 and measured["compile_s"] > 0


RESUME_SHARDED = """
import sys, jax, numpy as np
from pathlib import Path
sys.path.insert(0, {tests!r})
from conftest import TINY_TRAIN
from mjx_badger import checkpoints, runner
from mjx_badger.train import make_train
carry, chunk, _ = runner.compiled(make_train(TINY_TRAIN), [0, 1])
carry, _ = chunk(carry, 0)
saved = checkpoints.Checkpoints(Path({path!r}), {{"config": "tiny", "seeds": [0, 1]}})
saved.save(1, carry)
done, restored = saved.restore(carry)
_, straight = chunk(carry, 100)
_, resumed = chunk(restored, 100)
same = all(np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
           for a, b in zip(jax.tree.leaves(straight), jax.tree.leaves(resumed)))
print(done, len(restored.diverged_at.sharding.device_set), same)
"""


def test_a_sharded_carry_checkpoints_and_resumes_sharded(tmp_path):
    code = RESUME_SHARDED.format(tests=os.path.dirname(__file__), path=str(tmp_path / "run.json"))
    done = subprocess.run([sys.executable, "-c", code], env=TWO_CPU_DEVICES, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split()[-3:] == ["1", "2", "True"]  # restored after chunk 1, on both devices, same next chunk
