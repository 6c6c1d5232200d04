"""The on-robot loop: estimator, safety monitor, the loop end to end, stop and resume."""

import dataclasses
import os
import signal
import threading
import time

import numpy as np
import pytest

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.realtime import figure as realtime_figure
from mjx_badger.realtime import scheduling
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.loop import run
from mjx_badger.realtime.operator import Operator
from mjx_badger.realtime.robot_server import RobotServer
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from tests.realtime.test_scheduling import granted_in_a_thread


class Recording(SimulatedHB40):
    """The simulated HB40 with a hand that tips it over at `tip_at` reads, and a log of the gains at reset."""

    def __init__(self, tip_at=None, **kwargs):
        super().__init__(**kwargs)
        self.tip_at, self.reads, self.gains_at_reset = tip_at, 0, []

    def read(self):
        self.reads += 1
        if self.reads == self.tip_at:
            self.tip(roll=1.2)
        return super().read()

    def reset(self):
        self.gains_at_reset.append(self.gains)
        super().reset()


# Small and slow enough for a test: 20 Hz, a 32x32 CrossQ, 20 warm-up steps, 1 s evaluation.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=40, warmup_steps=20, control_hz=20.0,
                      eval_seconds=1.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))


def test_loop_runs_end_to_end_and_a_tip_puts_the_robot_in_damping_mode(tmp_path, monkeypatch):
    fifo = granted_in_a_thread(scheduling.raise_to_realtime, scheduling.back_to_normal)
    lockable = granted_in_a_thread(scheduling.lock_memory, scheduling.unlock_memory)
    # The loop counts major faults at the session's start and end: the report must hold the difference.
    faults = iter((7, 12))
    monkeypatch.setattr(scheduling, "major_page_faults", lambda: next(faults))
    bot = Recording(tip_at=10, reset_seconds=0.1)
    document = run(TINY, bot, tmp_path, resume=False, view=False)
    assert document["complete"] and document["steps"] == TINY.steps
    assert document["falls"] >= 1
    assert bot.gains_at_reset[0] == robot.HB40.damping_gains
    # The learner ran concurrently: one update per learning step, capped by the replay ratio.
    assert 0 < document["updates"] <= TINY.steps - TINY.warmup_steps
    timing = document["timing"]
    assert timing["ticks"] >= TINY.steps
    # The results say what the machine granted: SCHED_FIFO exactly where this process can have it.
    assert timing["scheduling"] == ("SCHED_FIFO" if fifo else "ordinary, compute threads niced")
    assert timing["memory_locked"] is lockable
    # The typical tick fits its period; the worst one is the machine's (a loaded CPU stretches it), and the
    # deadline misses are measured in benchmarks/bench_realtime.py, not asserted here.
    assert 0 < timing["work_p50_ms"] < 1000 / TINY.hz and timing["work_p50_ms"] <= timing["work_max_ms"]
    assert timing["major_page_faults"] == 5
    assert not scheduling.is_realtime()  # the caller's thread is ordinary again afterwards
    assert document["evaluation"]["seconds"] > 0
    trace = np.load(tmp_path / f"{TINY.name}.trace.npy")
    assert trace.shape[0] == TINY.steps and trace[:, 7].sum() == document["falls"]
    assert np.isfinite(trace[:, 2]).all() and np.isfinite(trace[:, 4]).all()
    figure = realtime_figure.draw(document, trace, tmp_path / "run.png")
    assert figure.stat().st_size > 10_000
    # An evaluation that fell before its first second has no best second (it once crashed the drawing).
    fell = dict(document, evaluation={"seconds": 0.5, "fell": "roll -0.81 rad", "estimated_velocity": -0.1,
                                      "true_velocity": 0.14, "true_peak_1s": None})
    assert realtime_figure.draw(fell, trace, tmp_path / "fell.png").stat().st_size > 10_000


class Interrupting(SimulatedHB40):
    """The simulated HB40, and an operator who presses Ctrl-C (or a system that sends SIGTERM) at the `at`-th read."""

    def __init__(self, at, signum=signal.SIGINT, **kwargs):
        super().__init__(**kwargs)
        self.at, self.reads, self.signum = at, 0, signum

    def read(self):
        self.reads += 1
        if self.reads == self.at:
            os.kill(os.getpid(), self.signum)
        return super().read()


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_stop_and_resume_keep_the_replay_buffer_and_step_count(tmp_path, signum):
    config = dataclasses.replace(TINY, steps=60, eval_seconds=0.0)
    bot = Interrupting(at=30, signum=signum, reset_seconds=0.1)
    stopped = run(config, bot, tmp_path, view=False)
    assert not stopped["complete"] and 0 < stopped["steps"] < config.steps
    assert bot.damp_calls >= 1
    checkpoint = tmp_path / f"{config.name}.checkpoint"
    saved = np.load(checkpoint / "replay.npz")
    assert int(saved["size"]) == stopped["steps"]
    first_obs = saved["obs"][: stopped["steps"]].copy()

    resumed = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path, view=False)
    assert resumed["complete"] and resumed["steps"] == config.steps
    after = np.load(checkpoint / "replay.npz")
    assert int(after["size"]) == config.steps
    np.testing.assert_array_equal(after["obs"][: stopped["steps"]], first_obs)
    assert resumed["falls"] >= stopped["falls"] and resumed["updates"] >= stopped["updates"]
    # The same command once more neither trains nor rewrites the finished results.
    again = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path, view=False)
    assert again["wall_clock"] == resumed["wall_clock"] and again["steps"] == config.steps
    with pytest.raises(ValueError, match="other settings"):
        run(dataclasses.replace(config, seed=1), SimulatedHB40(), tmp_path, view=False)
    # A checkpoint cut short is named and refused, before anything compiles; the run's lock is given back.
    replay = checkpoint / "replay.npz"
    replay.write_bytes(replay.read_bytes()[:1000])
    with pytest.raises(ValueError, match=f"{checkpoint} is damaged.*--restart"):
        run(config, SimulatedHB40(), tmp_path, view=False)
    assert not (tmp_path / f"{config.name}.json.lock").exists()




class Stalling(RobotServer):
    """A robot server that stops answering for `stall_s` at its `at`-th command, as a cable pulled and put back."""

    def __init__(self, *args, at=30, stall_s=1.0, **kwargs):
        super().__init__(*args, **kwargs)
        self.at, self.stall_s, self.commands = at, stall_s, 0

    def _command(self, message):
        self.commands += 1
        if self.commands == self.at:
            time.sleep(self.stall_s)
        return super()._command(message)


def test_the_same_loop_runs_over_the_link_and_a_stall_is_neither_training_time_nor_a_transition(tmp_path):
    config = dataclasses.replace(TINY, steps=80, eval_seconds=0.0)
    server = Stalling(SimulatedHB40(reset_seconds=0.1), address="tcp://127.0.0.1:0", watchdog_s=0.1)
    serving = threading.Thread(target=server.serve, daemon=True)
    serving.start()
    try:
        document = run(config, LinkedRobot(server.address, timeout_s=0.1), tmp_path, resume=False, view=False)
    finally:
        server.halt.set()
        serving.join()
    assert document["complete"] and document["steps"] == config.steps
    # The stall ended one episode; the robot damped itself on its watchdog and was stood up again.
    assert document["link_gaps"] == 1 and server.damps >= 1
    assert document["gap_minutes"] * 60 >= 0.8 * server.stall_s
    # No transition spans the gap: consecutive steps are one period of training time apart, never the stall.
    trace = np.load(tmp_path / f"{config.name}.trace.npy")
    assert np.diff(trace[:, 1]).max() < server.stall_s / 2
    replay = np.load(tmp_path / f"{config.name}.checkpoint" / "replay.npz")
    assert int(replay["size"]) == config.steps


def test_the_operator_starts_pauses_and_collapses_the_run_and_a_checkpoint_is_written_while_it_walks(tmp_path):
    config = dataclasses.replace(TINY, steps=60, eval_seconds=0.0)
    bot = SimulatedHB40(reset_seconds=0.1)
    operator = Operator("idle")
    seen = {}

    def press_buttons():
        assert operator.wait_while(("idle",), 5.0) == "idle"  # nothing moves until stand up
        seen["idle_steps"] = operator.snapshot().get("step", 0)
        assert operator.press("learn") is not None  # not possible while idle
        assert operator.press("stand_up") is None and operator.press("learn") is None
        _until(lambda: operator.snapshot().get("step", 0) >= 30)
        assert operator.press("pause") is None
        time.sleep(0.5)
        seen["paused_gains"], seen["paused_at"] = bot.gains, operator.snapshot()["step"]
        time.sleep(0.5)
        seen["paused_later"] = operator.snapshot()["step"]
        seen["checkpoint"] = (tmp_path / f"{config.name}.checkpoint").exists()
        assert operator.press("collapse") is None
        time.sleep(0.3)
        seen["collapsed_gains"] = bot.gains
        assert operator.press("stand_up") is None and operator.press("learn") is None

    presser = threading.Thread(target=press_buttons, daemon=True)
    presser.start()
    document = run(config, bot, tmp_path, resume=False, view=False, operator=operator, checkpoint_every_s=0.0)
    presser.join()
    assert document["complete"] and seen["idle_steps"] == 0
    assert seen["paused_gains"] == robot.HB40.pd_gains and seen["paused_later"] == seen["paused_at"]
    assert seen["collapsed_gains"] == robot.HB40.damping_gains
    assert seen["checkpoint"]  # written between episodes, before the run ended
    assert operator.state == "finished"


def _until(condition, timeout_s=120.0):
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)
