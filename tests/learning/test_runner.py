"""The host loop: a run writes its results file, policy and event files chunk by chunk, and draws from them."""

import json
import os
import struct
import subprocess
import sys

import numpy as np
from PIL import Image
from tensorboardX.proto.event_pb2 import Event

from mjx_badger.cli.main import main
from mjx_badger.experiments.registry import EXPERIMENTS, result_name
from mjx_badger.learning import runner, tensorboard
from mjx_badger.outputs import plots
from mjx_badger.outputs import videos as video_files
from mjx_badger.records import policy, results
from mjx_badger.robot import mjcf
from mjx_badger.sim import evaluation
from mjx_badger.sim.render import check_gl
from tests.conftest import TINY_TRAIN
from tests.documents import evaluation_schema


def _scalars(folder):
    """{tag: [(step, value)]} of the event files in `folder` (TFRecord: length, crc, Event proto, crc)."""
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
    assert evaluation_schema(document["metrics"]) == ({"forward"}, set(evaluation.RUN_METRICS))
    assert (path.parent / document["agents"]).is_dir()
    saved = policy.load(path.parent / document["policy"], seed=1)
    assert saved.meta["config"] == document["config"] and saved.meta["seeds"] == [0, 1]
    assert np.abs(saved(np.zeros(saved.observation_size))).max() <= 1.0
    report = tmp_path / "evaluation.json"
    assert main(["evaluate", str(path), "--seed", "1", "--seconds", "2", "--json", str(report)]) == 0
    native_run = json.loads(report.read_text())
    assert native_run["engine"] == "native" and native_run["seed"] == 1 and native_run["command"] == [0.5, 0.0, 0.0]
    assert np.isfinite(native_run["velocity_along_command"]) and native_run["seconds"] == 2.0
    assert np.isfinite(native_run["forward_velocity"]) and native_run["path"] in ("standing", "straight", "drifting",
                                                                               "turning", "circling")
    assert 0 <= native_run["falls"] <= 2 * 50 and isinstance(native_run["falls"], int)  # at most one per step
    # The same policy tested under the office's conditions: the robot's senses and its estimate (a sim run has none).
    assert "estimated_velocity_along_command" not in native_run and native_run["conditions"] == "sim"
    assert main(["evaluate", str(path), "--seconds", "1", "--conditions", "office", "--json", str(report)]) == 0
    office = json.loads(report.read_text())
    assert office["conditions"] == "office" and np.isfinite(office["estimated_velocity_along_command"])

    try:
        check_gl(mjcf.load_model())
        rendering = True
    except RuntimeError:  # no offscreen OpenGL on this machine: no videos, and `render` says why (below)
        rendering = False
    videos = video_files.draw(tmp_path / "results", tmp_path / "figures", "smoke", ["forward"], "thesis-code", seconds=0.5)
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


