"""The pure vmapped training loop: one trace, determinism, a smoke run, results files."""

import json
import os
import struct
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from PIL import Image

from conftest import COMPILES, TINY_TRAIN, seed_keys, traced
from mjx_badger import evaluation, plots, policy, results, runner, tensorboard
from mjx_badger.cli import main
from mjx_badger.experiments import EXPERIMENTS, result_name
from mjx_badger.train import TrainConfig


def _run_all_chunks(train_fns, seeds):
    init, chunk = train_fns
    carry = init(seed_keys(seeds))
    history = []
    for index in range(TINY_TRAIN.num_chunks):
        carry, metrics = chunk(carry, index * TINY_TRAIN.chunk_steps)
        history.append(jax.device_get(metrics))
    return carry, history


def test_smoke_training_run(train_fns):
    carry, history = _run_all_chunks(train_fns, [0, 1])
    assert int(carry.buffer.size[0]) == TINY_TRAIN.total_steps
    updates = sum(m["train/updates"] for m in history)
    # One update per step after warm-up, counted inside the compiled program.
    np.testing.assert_array_equal(updates, [TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps] * 2)
    assert int(carry.agent_state.updates[0]) == TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps
    last = history[-1]
    for name in ("train/critic_loss", "train/actor_loss", "train/alpha", "train/forward_velocity",
                 "eval/desired_velocity", "eval/forward/desired_velocity", "eval/desired_mae", "eval/return",
                 "reward/velocity", "reward/energy"):
        assert np.isfinite(last[name]).all(), name
    assert np.isnan(history[0]["train/critic_loss"]).all()  # the first chunk is all warm-up
    # Seeds differ from each other.
    assert not np.allclose(last["train/forward_velocity"][0], last["train/forward_velocity"][1])


def test_a_run_reuses_the_process_compiled_chunk_and_same_seed_gives_same_numbers(train_fns, tmp_path):
    """The chunk takes its start step as an argument (one program serves every chunk), and a later run of
    the same configuration and seed count in this process traces and compiles nothing of it again."""
    _, first = _run_all_chunks(train_fns, [5, 7])
    since = len(COMPILES)
    document = runner.run(TINY_TRAIN, [5, 7], tmp_path / "again.json", progress=False, tensorboard=False)
    assert traced(since, "chunk") == 0 and document["wall_clock"]["compile_s"] == 0.0
    assert traced(since, "gait") == 1  # its gait program, now built once for this configuration
    since = len(COMPILES)
    runner.run(TINY_TRAIN, [5, 7], tmp_path / "third.json", progress=False, tensorboard=False)
    assert traced(since, "") == 0, COMPILES[since:]
    second = [{name: np.array(values[i], float) for name, values in document["metrics"].items()} for i in range(3)]
    for a, b in zip(first, second):
        for name in a:
            np.testing.assert_array_equal(np.asarray(a[name], float).round(5), b[name], err_msg=name)


@pytest.mark.slow  # a learning program of its own: minutes of compile
def test_whole_train_program_matches_chunked_runs(trainer, train_fns):
    """`train(key)` (all chunks in one scan) runs the same program as the host's chunk loop.

    The warm-up chunk is bit-identical; once learning starts the two differently compiled
    programs differ in float rounding, which the chaotic rollouts amplify, so later chunks
    are only checked for sanity.
    """
    _, chunked = _run_all_chunks(train_fns, [3, 4])
    _, stacked = jax.jit(jax.vmap(trainer.train))(seed_keys([3, 4]))
    for name in chunked[0]:
        np.testing.assert_array_equal(stacked[name][0, 0], chunked[0][name][0], err_msg=name)
    assert stacked["train/updates"][0].sum() == TINY_TRAIN.total_steps - TINY_TRAIN.warmup_steps
    assert np.isfinite(stacked["train/critic_loss"][0, 1:]).all()


def _scalars(folder):
    """{tag: [(step, value)]} of the event files in `folder` (TFRecord: length, crc, Event proto, crc)."""
    from tensorboardX.proto.event_pb2 import Event

    found = {}
    for path in sorted(folder.glob("events.out.tfevents.*")):
        data, at = path.read_bytes(), 0
        while at < len(data):
            (length,) = struct.unpack("<Q", data[at:at + 8])
            event = Event.FromString(data[at + 12:at + 12 + length])
            at += 16 + length
            for value in event.summary.value:
                found.setdefault(value.tag, []).append((event.step, value.simple_value))
    return found


def test_runner_writes_a_results_file_and_a_figure(tmp_path, train_fns):
    experiment = EXPERIMENTS["forward"]
    path = tmp_path / "results" / "forward" / result_name(experiment.runs[2])
    runner.run(TINY_TRAIN, [0, 1], path, progress=False)  # the program of train_fns: nothing compiles
    document = results.read(path)
    assert document["complete"] and document["seeds"] == [0, 1]
    assert document["steps"] == [100, 200, 300] and document["diverged_at_step"] == [None, None]
    # thesis-code: JT at 50 Hz
    np.testing.assert_allclose(document["sim_minutes"], [100 / 50 / 60, 200 / 50 / 60, 300 / 50 / 60], atol=1e-4)
    assert document["config"]["agent"]["learning_rate"] == 0.005
    assert document["config"]["env"]["control_hz"] == 50.0
    assert document["config"]["protocol"] == "thesis-code"
    assert document["config"]["env"]["protocol"]["termination"] == "thesis-code"
    assert np.array(document["metrics"]["train/forward_velocity"]).shape == (3, 2)
    # TensorBoard: one run per seed, one scalar per metric and chunk (none while a metric has no value yet).
    events = {seed: _scalars(tensorboard.folder(path) / f"seed_{seed}") for seed in (0, 1)}
    for seed, column in ((0, 0), (1, 1)):
        rows = np.array(document["metrics"]["train/forward_velocity"], dtype=float)[:, column]
        assert [step for step, _ in events[seed]["train/forward_velocity"]] == [100, 200, 300]
        np.testing.assert_allclose([value for _, value in events[seed]["train/forward_velocity"]], rows, atol=1e-5)
    learner = np.array(document["metrics"]["train/critic_loss"], dtype=float)[:, 0]
    assert len(events[0]["train/critic_loss"]) == np.isfinite(learner).sum() < 3  # warm-up chunk left out
    assert document["wall_clock"]["tensorboard_s"] <= document["wall_clock"]["run_s"]  # timed apart from training
    assert _evaluation_schema(document["metrics"]) == ({"forward"}, set(evaluation.RUN_METRICS))
    assert (path.parent / document["agents"]).is_dir()
    saved = policy.load(path.parent / document["policy"], seed=1)
    assert saved.meta["config"] == document["config"] and saved.meta["seeds"] == [0, 1]
    assert np.abs(saved(np.zeros(saved.observation_size))).max() <= 1.0
    report = tmp_path / "evaluation.json"
    assert main(["evaluate", str(path), "--seed", "1", "--seconds", "2", "--json", str(report)]) == 0
    native_run = json.loads(report.read_text())
    assert native_run["engine"] == "native" and native_run["seed"] == 1 and native_run["command"] == [0.5, 0.0, 0.0]
    assert np.isfinite(native_run["velocity_along_command"]) and native_run["seconds"] == 2.0
    assert 0 <= native_run["falls"] <= 2 * 50 and isinstance(native_run["falls"], int)  # at most one per step
    # The same policy tested under the office's conditions: the robot's senses and its estimate (a sim run has none).
    assert "estimated_velocity_along_command" not in native_run and native_run["conditions"] == "sim"
    assert main(["evaluate", str(path), "--seconds", "1", "--conditions", "office", "--json", str(report)]) == 0
    office = json.loads(report.read_text())
    assert office["conditions"] == "office" and np.isfinite(office["estimated_velocity_along_command"])
    from mjx_badger import mjcf, render

    try:
        render.check_gl(mjcf.load_model())
        rendering = True
    except RuntimeError:  # no offscreen OpenGL on this machine: no videos, and `render` says why (below)
        rendering = False
    videos = render.draw(tmp_path / "results", tmp_path / "figures", "smoke", ["forward"], "thesis-code", seconds=0.5)
    gif = tmp_path / "gait.gif"
    if rendering:
        assert [p.name for p in videos] == ["forward_smoke.gif"] and videos[0].parent.name == "thesis-code"
        assert main(["render", str(path), "--seconds", "1", "--out", str(gif)]) == 0
        with Image.open(gif) as video:
            assert video.n_frames == 25 and video.size == (480, 360)  # 1 s at 25 frames/s
            assert np.asarray(video.convert("RGB")).std() > 10  # a scene, not a blank image
    else:
        assert videos == []
    # Without a working offscreen backend: the install line and exit 2, before anything runs.
    done = subprocess.run([sys.executable, "-m", "mjx_badger", "render", str(path), "--out", str(gif)],
                          env=dict(os.environ, MUJOCO_GL="osmesa"), capture_output=True, text=True)
    if done.returncode == 0:  # where OSMesa is installed it simply works
        with Image.open(gif) as video:
            assert video.n_frames > 1
    else:
        assert done.returncode == 2 and "apt install libegl1" in done.stderr, done.stderr[-2000:]
        assert "Traceback" not in done.stderr
    assert document["metrics"]["train/critic_loss"][0] == [None, None]  # NaN is written as null
    assert document["versions"]["mujoco"] and document["git_commit"]
    assert document["wall_clock"]["compile_s"] == 0.0 and document["hardware"]["peak_memory_mib"] > 0
    json.loads(path.read_text())  # strict JSON

    gait = document["gait"]
    assert np.array(gait["contacts"]).shape == (2, 400, 4)  # 2 seeds x 2 s at 200 Hz x 4 feet
    assert set(np.unique(gait["contacts"])) <= {0, 1}
    assert np.isfinite(np.array(gait["forward_velocity"], dtype=float)).all()

    written = plots.draw(tmp_path / "results", tmp_path / "figures", "smoke", ["forward"])
    assert [p.name for p in written] == ["forward_smoke.png", "forward_gait_smoke.png", "forward_smoke.md",
                                         "forward_vs_released-code_smoke.md", "overview_smoke.png"]
    assert all(p.parent.name == "thesis-code" for p in written)
    assert written[2].read_text().startswith("Protocol: thesis-code")
    # thesis-code's forward run beside the released code's CPU spread, our two seeds counted against it.
    assert "| JT-OEF | 14k, 10k, never / " in written[3].read_text() and " of 2) |" in written[3].read_text()
    assert all(p.stat().st_size > 10_000 for p in written if p.suffix == ".png")
    assert "JT-OEF" in written[2].read_text()

    # The same file stands in for a maximal-velocity run, only to exercise that figure and table.
    max_path = tmp_path / "results" / "forward-max" / "jt-oef_crossq_forward-max.json"
    max_path.parent.mkdir()
    max_path.write_text(path.read_text())
    written = plots.draw(tmp_path / "results", tmp_path / "figures", "smoke", ["forward-max"])
    assert [p.name for p in written] == ["forward-max_smoke.png", "forward-max_gait_smoke.png",
                                         "forward-max_smoke.md", "overview_smoke.png"]
    assert "| JT-OEF | 2 x 300 | 1.3 |" in written[2].read_text()


def test_omni_run_records_eight_evaluations_and_the_curriculum_and_draws_every_omni_figure(tmp_path):
    config = TrainConfig(approach="cpg-d", algo="crossq", task="omni-pdec", total_steps=200, chunk_steps=100,
                         warmup_steps=100, eval_steps=10)
    path = tmp_path / "results" / "omni-pdec" / "cpg-d_crossq_omni-pdec.json"
    document = runner.run(config, [0, 1], path, progress=False)
    assert document["wall_clock"]["compile_s"] > 0  # a configuration of its own: compiled here
    metrics = document["metrics"]
    for direction in ("forward", "backward", "left", "right"):
        for level in ("full", "half"):
            for name in ("desired_velocity", "lateral_velocity", "yaw_rate", "desired_mae", "lateral_mae", "yaw_mae"):
                values = np.array(metrics[f"eval/{direction}_{level}/{name}"], dtype=float)
                assert values.shape == (2, 2) and np.isfinite(values).all()
    assert np.array(metrics["curriculum/learned_bins"]).shape == (2, 2)
    runs, names = _evaluation_schema(metrics)
    assert len(runs) == 8 and names == set(evaluation.RUN_METRICS)  # the forward task's metric names, eight runs
    assert np.array(metrics["train/desired_velocity"]).shape == (2, 2)
    assert document["gait"]["command"] == [0.5, 0.0, 0.0]

    # The same file stands in for a random-command run, only to exercise the comparison figure.
    random_path = tmp_path / "results" / "omni-random" / "cpg-d_crossq_omni-random.json"
    random_path.parent.mkdir()
    random_path.write_text(path.read_text())
    written = {p.name: p for p in plots.draw(tmp_path / "results", tmp_path / "figures", "smoke")}
    for name in ("omni-pdec_smoke.png", "omni-pdec_smoke.md", "omni-pdec_directions_smoke.png",
                 "omni-pdec_gait_smoke.png", "omni-random_smoke.png", "omni-random_directions_smoke.png",
                 "omni-pdec_vs_omni-random_smoke.png", "overview_smoke.png"):
        assert name in written, name
    assert "| CPG-D | 2 x 200 |" in written["omni-pdec_smoke.md"].read_text()


def test_single_seed_runs_the_unbatched_program_with_the_same_numbers(tmp_path, train_fns):
    """runner.seeds_chunk skips vmap for one seed (faster on CPU); the warm-up chunk agrees to float rounding
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


def _evaluation_schema(metrics: dict) -> tuple:
    """(run names, metric names) of a document's evaluation, checking every run has every metric over all runs."""
    per_run = [name.split("/")[1:] for name in metrics if name.startswith("eval/") and name.count("/") == 2]
    runs, names = {run for run, _ in per_run}, {name for _, name in per_run}
    assert {name.split("/")[1] for name in metrics if name.startswith("eval/") and name.count("/") == 1} == names
    assert len(per_run) == len(runs) * len(names)
    return runs, names


def test_results_of_the_older_evaluation_schema_are_read_into_todays():
    one = {"schema": results.SCHEMA, "metrics": {"eval/forward_velocity": [[0.1, 0.3]], "eval/return": [[1.0, 2.0]]}}
    two = {"schema": results.SCHEMA, "metrics": {"eval/forward_full/desired_velocity": [[0.4, None]],
                                                 "eval/backward_full/desired_velocity": [[0.2, 0.5]]}}
    upgraded = [results.upgrade(json.loads(json.dumps(d)))["metrics"] for d in (one, two)]
    assert upgraded[0]["eval/desired_velocity"] == [[0.1, 0.3]] and "eval/forward_velocity" not in upgraded[0]
    np.testing.assert_allclose(np.array(upgraded[1]["eval/desired_velocity"][0][:1]), [0.3])
    assert upgraded[1]["eval/desired_velocity"][0][1] is None  # a missing run leaves the mean undefined


def test_schema_1_would_be_falls_are_read_without_its_blowups():
    """Schema 1 counted a blow-up as a would-be fall: 5 would-be with 4 blow-ups is 1 rule firing."""
    old = {"schema": "mjx_badger.results/1",
           "metrics": {"train/would_falls": [[0, 2], [5, 3]], "train/blowups": [[0, 1], [4, 1]]}}
    upgraded = results.upgrade(json.loads(json.dumps(old)))
    assert upgraded["metrics"]["train/would_falls"] == [[0, 1], [1, 2]] and upgraded["schema"] == results.SCHEMA
    today = {"schema": results.SCHEMA, "metrics": {"train/would_falls": [[5]], "train/blowups": [[4]]}}
    assert results.upgrade(today)["metrics"]["train/would_falls"] == [[5]]


def test_a_diverging_seed_is_frozen_and_marked_while_the_others_go_on(train_fns):
    """A NaN put into seed 1's actor freezes seed 1 at its carry from before the chunk; seed 0 trains on."""
    init, chunk = train_fns
    carry = init(seed_keys([0, 1]))
    poison = lambda x: x.at[1].set(jnp.nan) if jnp.issubdtype(x.dtype, jnp.floating) else x
    carry = carry.replace(agent_state=carry.agent_state.replace(
        actor_params=jax.tree.map(poison, carry.agent_state.actor_params)))
    before = jax.device_get(carry)
    history = []
    for index in range(TINY_TRAIN.num_chunks):
        carry, metrics = chunk(carry, index * TINY_TRAIN.chunk_steps)
        history.append(jax.device_get(metrics))
    np.testing.assert_array_equal(carry.diverged_at, [-1, TINY_TRAIN.chunk_steps])
    after = jax.device_get(carry)
    jax.tree.map(lambda old, new: np.testing.assert_array_equal(old[1], new[1]),
                 before.replace(diverged_at=after.diverged_at), after)
    assert int(after.buffer.size[0]) == TINY_TRAIN.total_steps and int(after.buffer.size[1]) == 0
    for metrics in history:
        assert np.isnan(metrics["train/forward_velocity"][1]) and np.isfinite(metrics["train/forward_velocity"][0])
    assert np.isfinite(history[-1]["train/critic_loss"][0])


def test_the_runner_records_and_announces_a_seed_that_diverges(tmp_path, capsys):
    document = {"seeds": [3, 4], "diverged_at_step": [None, None]}
    runner.note_divergence(document, np.array([-1, 2000]), tmp_path / "run.json")
    runner.note_divergence(document, np.array([-1, 2000]), tmp_path / "run.json")
    assert document["diverged_at_step"] == [None, 2000]
    assert capsys.readouterr().err.count("run.json: seed 4 went non-finite by step 2000") == 1
