"""Scale out: seeds split over devices and sweeps in one program, both with the numbers of separate runs."""

import os
import socket
import subprocess
import sys
import time

import jax
import numpy as np
import pytest

from conftest import TINY_TRAIN
from mjx_badger import results, runner, sweep
from mjx_badger.train import make_train

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


def assert_same_policy(path, other) -> None:
    """The saved policies beside two results files hold the same arrays, float ones to the bit."""
    with np.load(path.with_suffix(".policy.npz")) as mine, np.load(other.with_suffix(".policy.npz")) as theirs:
        assert sorted(mine.files) == sorted(theirs.files)
        for name in mine.files:
            if mine[name].dtype.kind == "f":
                np.testing.assert_array_equal(mine[name], theirs[name], err_msg=name)


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
    import json
    import signal

    from mjx_badger import checkpoints

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


def test_seeds_that_do_not_split_over_the_devices_are_refused_before_anything_compiles(tmp_path):
    done = _train(tmp_path, 3, TWO_CPU_DEVICES)
    assert done.returncode == 2
    assert "3 seeds do not split evenly over 2 devices" in done.stderr and "Traceback" not in done.stderr
    with pytest.raises(ValueError, match="multiple of 2"):
        runner.check_seeds_divide(5, 2)
    runner.check_seeds_divide(1, 2)  # one seed runs on the first device


def test_the_full_profile_estimate_is_measured_once_per_algorithm_and_evaluation_size(monkeypatch):
    from mjx_badger import cli, reproduce
    from mjx_badger.experiments import EXPERIMENTS

    timed = []

    def fake_measure(config, seeds, evaluation=False):
        timed.append((config.algo, config.task, len(seeds), evaluation))
        rate = 100.0 if config.algo == "crossq" else 10.0
        return {"seed_steps_per_s": rate / 2 if config.task.startswith("omni") else rate, "compile_s": 60.0}

    monkeypatch.setattr(runner, "measure_speed", fake_measure)
    todo = [(EXPERIMENTS[name], run, None) for name in ("algo-comparison", "forward-max", "omni-random")
            for run in EXPERIMENTS[name].runs]
    line = reproduce.measured_estimate(todo, cli.Reproduce(profile="full"), seeds=10)
    # One chunk per algorithm and evaluation size (forward-max shares forward's one command), with evaluation.
    assert sorted(timed) == sorted([(algo, "forward", 10, True) for algo in ("sac", "sac-utd20", "droq", "crossq")]
                                   + [("crossq", "omni-random", 10, True)])
    assert "crossq forward 100 seed-steps/s" in line and "crossq omni-random 50 seed-steps/s" in line
    expected_s = sum(experiment.steps(run, "full") * 10 / fake_measure(experiment.train_config(run, "full"), [])
                     ["seed_steps_per_s"] + 60.0 for experiment, run, _ in todo)
    assert f"about {expected_s / 3600:.1f} h for these {len(todo)} runs" in line
    assert reproduce.measured_estimate(todo[:1], cli.Reproduce(profile="full"), seeds=10).endswith(" h for this run")


def test_the_timed_chunk_evaluates_as_long_per_learning_step_as_the_run():
    config = TINY_TRAIN
    cut = runner.short_run(config, 20, evaluation=True)
    assert cut.eval_steps / cut.chunk_steps == pytest.approx(config.eval_steps / config.chunk_steps, rel=0.05)
    assert runner.short_run(config, 20).eval_steps == 1  # the learner's own rate (benchmarks)


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_a_short_chunk_is_timed_on_this_machine():
    measured = runner.measure_speed(TINY_TRAIN, [0, 1], steps=20)
    assert measured["compile_s"] > 0  # the short program is its own: compiled here
    # Its rate is what a chunk of that program takes here, timed apart (within a loaded machine's spread).
    carry, chunk, compile_s = runner.compiled(make_train(runner.short_run(TINY_TRAIN, 20)), [0, 1])
    assert compile_s == 0.0  # the process kept it
    carry, _ = jax.block_until_ready(chunk(carry, 0))
    started = time.perf_counter()
    jax.block_until_ready(chunk(carry, 20))
    timed = 2 * 20 / (time.perf_counter() - started)
    assert timed / 3 < measured["seed_steps_per_s"] < 3 * timed


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


def test_a_grid_whose_members_differ_in_shape_is_refused_naming_the_field():
    with pytest.raises(ValueError, match=r"members differ in shape: algo_params.ensemble_size changes .*agent_state"):
        sweep.Sweep(TINY_TRAIN, (("algo_params.ensemble_size", (2, 3)),), [0])
    with pytest.raises(ValueError, match="cannot sweep algo_params.updates_per_step: the program needs it as a Python "
                                         "number"):
        sweep.Sweep(TINY_TRAIN, (("algo_params.updates_per_step", (1, 2)),), [0])
    for bad, message in ((("robot", (1, 2)), "cannot sweep 'robot'"),
                         (("algo_params.learning_rate", ("fast",)), "must be numbers"),
                         (("task_params.speed", (1.0,)), "task 'forward' takes")):
        with pytest.raises(ValueError, match=message):
            sweep.members(TINY_TRAIN, (bad,))
    assert sweep.parse_axis("task_params.target_velocity=0.3, 0.5") == ("task_params.target_velocity", (0.3, 0.5))
    with pytest.raises(ValueError, match="must be numbers"):
        sweep.parse_axis("task_params.target_velocity=0.3,fast")


def test_the_sweep_command_refuses_a_bad_grid_before_compiling(tmp_path):
    grid = tmp_path / "grid.json"
    grid.write_text('{"algo_params.ensemble_size": [2, 3]}')
    command = [sys.executable, "-m", "mjx_badger", "sweep", "--grid", str(grid), "--out", str(tmp_path / "out"),
               "--quiet"]
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 2 and "members differ in shape: algo_params.ensemble_size" in done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "out").exists()  # nothing written, not even the folder


@pytest.mark.slow  # minutes of compile: `make test-slow`
def test_members_vmapped_together_each_get_their_own_values():
    """With all members in one vmapped group, each member's environment runs at its own swept target velocity."""
    targets = (0.25, 0.5, 0.75)
    program = sweep.Sweep(TINY_TRAIN, (("task_params.target_velocity", targets),), [0, 1], vmapped=3)
    carry, chunk, _ = program.compiled()
    (values, state), metrics = chunk(carry, 0)
    np.testing.assert_array_equal(np.asarray(values)[:, 0], np.float32(targets))
    commanded = np.asarray(state.env_state.obs)[:, :, 48]  # [member][seed]: the observed target velocity
    np.testing.assert_allclose(commanded, np.repeat(np.float32(targets)[:, None], 2, axis=1))
    assert np.asarray(metrics["train/falls"]).shape == (3, 2)
