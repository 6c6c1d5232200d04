"""Scale out: seeds split over devices and sweeps in one program, both with the numbers of separate runs."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from mjx_badger.learning import checkpoints, programs, runner, sweep
from mjx_badger.records import results
from tests.conftest import TINY_TRAIN

TWO_CPU_DEVICES = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2")


def _train(out, seeds, env):
    return subprocess.run(_command(out, seeds), env=env, capture_output=True, text=True)


def _command(out, seeds) -> list:
    """`train` of the tiny run with `seeds` seeds into `out`, quiet, without event files."""
    return [sys.executable, "-m", "mjx_badger", "train", "--approach", TINY_TRAIN.approach, "--task",
               TINY_TRAIN.task, "--total-steps", str(TINY_TRAIN.total_steps), "--chunk-steps",
               str(TINY_TRAIN.chunk_steps), "--warmup-steps", str(TINY_TRAIN.warmup_steps), "--eval-steps",
               str(TINY_TRAIN.eval_steps), "--seeds", str(seeds), "--out", str(out), "--quiet", "--no-tensorboard"]


@pytest.fixture(scope="module")
def alone(tmp_path_factory):
    """The tiny run of seed 0 and of seed 1, each on its own, on one device: (results document, results path)."""
    runs = []
    for seed in (0, 1):
        path = tmp_path_factory.mktemp(f"seed{seed}") / f"{TINY_TRAIN.name}.json"
        runner.run(TINY_TRAIN, [seed], path, progress=False, tensorboard=False)
        runs.append((results.read(path), path))
    return runs


def assert_same_numbers(document: dict, separate: list[dict]) -> None:
    """`document`'s metrics and gait record are those of the `separate` documents, seed after seed, to the bit."""
    assert document["metrics"].keys() == separate[0]["metrics"].keys()
    together = {name: np.concatenate([np.array(one["metrics"][name], float) for one in separate], axis=1)
                for name in document["metrics"]}  # [chunk][seed]
    for name, rows in together.items():
        np.testing.assert_array_equal(np.array(document["metrics"][name], float), rows, err_msg=name)
    for name in ("contacts", "forward_velocity"):  # the gait record after training, per seed
        assert document["gait"][name] == sum((one["gait"][name] for one in separate), [])


def test_seeds_sharded_over_two_devices_give_the_numbers_of_one_device(tmp_path, alone):
    """Each device runs the one-device program of its seeds: 2 seeds on 2 devices are two one-seed runs."""
    done = _train(tmp_path / "sharded", 2, TWO_CPU_DEVICES)
    assert done.returncode == 0, done.stderr[-2000:]
    sharded = results.read(tmp_path / "sharded" / f"{TINY_TRAIN.name}.json")
    assert sharded["hardware"]["jax_devices"] == ["cpu:0", "cpu:1"]
    assert alone[0][0]["hardware"]["jax_devices"] == ["cpu:0"]
    assert_same_numbers(sharded, [document for document, _ in alone])


@pytest.mark.slow  # minutes of compile: `make test-slow`
def test_two_processes_through_jax_distributed_give_the_numbers_of_one_device(tmp_path, alone):
    """Two processes on this host (jax.distributed, one CPU device each): process 0 writes two one-seed runs."""
    with socket.socket() as probe:  # a free port for the coordinator
        probe.bind(("localhost", 0))
        port = probe.getsockname()[1]
    cluster = ["--coordinator", f"localhost:{port}", "--num-processes", "2", "--process-id"]
    out = tmp_path / "cluster"
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    processes = [subprocess.Popen(_command(out, 2) + cluster + [str(i)], env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True) for i in (0, 1)]
    outputs = [process.communicate(timeout=900) for process in processes]
    for process, (_, stderr) in zip(processes, outputs):
        assert process.returncode == 0, stderr[-2000:]
    together = results.read(out / f"{TINY_TRAIN.name}.json")
    assert together["hardware"]["jax_devices"] == ["TFRT_CPU_0", "TFRT_CPU_2048"] or len(
        together["hardware"]["jax_devices"]) == 2
    assert_same_numbers(together, [document for document, _ in alone])
    assert (out / f"{TINY_TRAIN.name}.policy.npz").exists() and (out / f"{TINY_TRAIN.name}.agents").is_dir()


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


@pytest.mark.slow  # two processes compile twice, killed and resumed: minutes (`make test-slow`)
def test_two_processes_killed_mid_way_resume_to_the_numbers_of_one_device(tmp_path, alone):
    """SIGKILL both processes of a jax.distributed run once a chunk is checkpointed; the same two commands again
    resume from that checkpoint (each process its own shards) and end with the uninterrupted numbers."""


    out = tmp_path / "cluster"
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    result, ckpt = out / f"{TINY_TRAIN.name}.json", checkpoints.folder(out / f"{TINY_TRAIN.name}.json")

    def start(port):
        cluster = ["--coordinator", f"localhost:{port}", "--num-processes", "2", "--process-id"]
        return [subprocess.Popen(_command(out, 2) + cluster + [str(i)], env=env, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True) for i in (0, 1)]

    processes = start(_free_port())
    deadline = time.time() + 900
    while time.time() < deadline and all(p.poll() is None for p in processes):
        try:
            done = json.loads(result.read_text())["steps"]
        except (FileNotFoundError, json.JSONDecodeError):
            done = []
        if done and (ckpt / "1").is_dir():
            break
        time.sleep(0.05)
    assert all(p.poll() is None for p in processes), "the run ended before it could be killed mid-way"
    for process in processes:
        process.send_signal(signal.SIGKILL)
        process.communicate()
    assert not json.loads(result.read_text())["complete"]

    processes = start(_free_port())
    outputs = [process.communicate(timeout=900) for process in processes]
    for process, (_, stderr) in zip(processes, outputs):
        assert process.returncode == 0, stderr[-2000:]
    assert "resuming" in outputs[0][1]
    assert_same_numbers(results.read(result), [document for document, _ in alone])


RESUME_SHARDED = """
import sys, jax, numpy as np
from pathlib import Path
sys.path.insert(0, {tests!r})
from tests.conftest import TINY_TRAIN
from mjx_badger.learning import checkpoints, programs
from mjx_badger.learning.train import make_train
carry, chunk, _ = programs.compiled(make_train(TINY_TRAIN), [0, 1])
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
    code = RESUME_SHARDED.format(tests=str(Path(__file__).resolve().parents[2]), path=str(tmp_path / "run.json"))
    done = subprocess.run([sys.executable, "-c", code], env=TWO_CPU_DEVICES, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split()[-3:] == ["1", "2", "True"]  # restored after chunk 1, on both devices, same next chunk


def assert_same_policy(path, other) -> None:
    """The saved policies beside two results files hold the same arrays, float ones to the bit."""
    with np.load(path.with_suffix(".policy.npz")) as mine, np.load(other.with_suffix(".policy.npz")) as theirs:
        assert sorted(mine.files) == sorted(theirs.files)
        for name in mine.files:
            if mine[name].dtype.kind == "f":
                np.testing.assert_array_equal(mine[name], theirs[name], err_msg=name)


LEARNING_RATE = "algo_params.learning_rate"


def test_a_swept_run_equals_the_separate_runs_number_for_number(tmp_path, alone):
    """Two learning rates in one program (the rate an array in the carry): the member at the tiny run's own rate
    is that separate run, number for number, and each member's numbers follow its value, not its place (the
    grid again in the other order: its chunk, the costly program, comes from the cache)."""
    rate = TINY_TRAIN.agent_config.learning_rate
    documents = sweep.run(TINY_TRAIN, ((LEARNING_RATE, (rate, 3 * rate)),), [0], tmp_path / "sweep", progress=False,
                          tensorboard=False)
    reversed_order = sweep.run(TINY_TRAIN, ((LEARNING_RATE, (3 * rate, rate)),), [0], tmp_path / "reversed",
                               progress=False, tensorboard=False)
    written = sorted((tmp_path / "sweep").glob("*.json"))
    assert [path.name for path in written] == [f"{TINY_TRAIN.name}_learning_rate={rate:g}.json",
                                               f"{TINY_TRAIN.name}_learning_rate={3 * rate:g}.json"]
    swept = [results.read(path) for path in written]
    for document, own in zip(swept, documents):
        assert document["sweep"] == {"fields": [LEARNING_RATE], "values": own["sweep"]["values"], "members": 2,
                                     "vmapped": 1}
    assert_same_numbers(swept[0], [alone[0][0]])
    assert_same_policy(written[0], alone[0][1])
    for path, document in zip(written, swept):  # the same value in the other place: the same numbers and policy
        value = document["sweep"]["values"]
        other = next(other for other in (tmp_path / "reversed").glob("*.json")
                     if results.read(other)["sweep"]["values"] == value)
        assert_same_numbers(results.read(other), [document])
        assert_same_policy(path, other)
    assert [d["sweep"]["values"] for d in reversed_order] == [d["sweep"]["values"] for d in documents][::-1]
    # The swept value took effect: the members learned differently.
    assert documents[0]["metrics"]["train/critic_loss"][-1] != documents[1]["metrics"]["train/critic_loss"][-1]


def test_seeds_that_do_not_split_over_the_devices_are_refused_before_anything_compiles(tmp_path):
    done = _train(tmp_path, 3, TWO_CPU_DEVICES)
    assert done.returncode == 2
    assert "3 seeds do not split evenly over 2 devices" in done.stderr and "Traceback" not in done.stderr
    with pytest.raises(ValueError, match="multiple of 2"):
        programs.check_seeds_divide(5, 2)
    programs.check_seeds_divide(1, 2)  # one seed runs on the first device
