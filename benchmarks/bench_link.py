"""The robot link on this machine: control timing over the link beside the in-process loop, round trips, the time from
killing the training process to the robot damped, a 2 s stall and a training-process restart, each resumed.

    python -m benchmarks.bench_link [--kills 20] [--steps 3000] [--only timed kill_to_damp stall restart]

Every robot is the simulated HB40 (office conditions) in its own robot-server process; every learner is CrossQ at 40 Hz
(JT-OEF, forward 0.25 m/s) updating beside the loop. Writes benchmarks/results/link.json.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.common import RESULTS, ROOT
from mjx_badger.realtime.linked_robot import LinkedRobot

RUN = ["--approach", "jt-oef", "--algo", "crossq", "--conditions", "office", "--eval-seconds", "0"]
STREAMER = """
import sys, time
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.robot.description import nominal_pose
bot = LinkedRobot(sys.argv[1], timeout_s=0.1)
bot.start()
print("streaming", flush=True)
while True:  # what a training process sends at 40 Hz: a reading and a command each period
    try:
        bot.read(); bot.command(nominal_pose(), 60.0, 3.0)
    except Exception:  # damped by a late period of its own (a busy machine): stand up and go on, as the loop does
        bot.reset()
    time.sleep(0.025)
"""


def command(*args) -> list[str]:
    return [sys.executable, "-m", "mjx_badger", *args]


def server(port: int, folder: Path) -> subprocess.Popen:
    """A robot server on 127.0.0.1:port logging its damps to folder/events.jsonl; waits until it answers."""
    process = subprocess.Popen(command("robot-server", "--conditions", "office", "--address", f"tcp://127.0.0.1:{port}",
                                       "--events", str(folder / "events.jsonl"), "--reset-seconds", "0.5"),
                               cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    probe = LinkedRobot(f"tcp://127.0.0.1:{port}")
    while probe.hello(1.0) is None:
        assert process.poll() is None, "the robot server did not start"
    return process


def damps(folder: Path) -> list[dict]:
    path = folder / "events.jsonl"
    return [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []


def train(folder: Path, steps: int, link: str | None, extra=()) -> subprocess.Popen:
    where = ["--link", link] if link else []
    return subprocess.Popen(command("realtime", *RUN, "--steps", str(steps), "--out", str(folder), *where, *extra),
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def timing(document: dict) -> dict:
    t = document["timing"]
    keep = ("period_p50_ms", "period_p99_ms", "period_error_p99_ms", "period_error_max_ms", "missed_deadlines",
            "ticks", "work_p50_ms", "work_p99_ms")
    return dict({k: t[k] for k in keep}, updates_per_learning_step=document["updates_per_learning_step"],
                link=document.get("link"), link_gaps=document.get("link_gaps"), falls=document["falls"])


def timed_runs(folder: Path, steps: int) -> dict:
    """The same run in-process and over the link: the loop's own timing record of each."""
    out = {}
    for name, port in (("in_process", None), ("over_link", 5611)):
        (folder / name).mkdir(exist_ok=True)
        robot = server(port, folder / name) if port else None
        run = train(folder / name, steps, f"tcp://127.0.0.1:{port}" if port else None)
        run.communicate()
        if robot:
            robot.send_signal(signal.SIGINT)
            robot.wait()
        document = json.loads(next((folder / name).glob("*_crossq_forward.json")).read_text())
        out[name] = timing(document)
        print(name, json.dumps(out[name]), flush=True)
    return out


def kill_to_damp(folder: Path, kills: int) -> dict:
    """SIGKILL a process streaming at 40 Hz over the link; the robot's damp time after each kill."""
    robot = server(5612, folder)
    address, delays, skipped = "tcp://127.0.0.1:5612", [], 0
    operator = LinkedRobot(address, timeout_s=5.0)
    for _ in range(kills):
        streamer = subprocess.Popen([sys.executable, "-c", STREAMER, address], cwd=ROOT, stdout=subprocess.PIPE,
                                    text=True)
        assert streamer.stdout.readline().strip() == "streaming"
        time.sleep(1.0)
        killed = time.time()
        os.kill(streamer.pid, signal.SIGKILL)
        streamer.wait()
        event = None
        while event is None and time.time() < killed + 3.0:  # none: the robot was standing up when it was killed
            time.sleep(0.005)
            event = next((e for e in damps(folder) if e["unix_time"] >= killed), None)
        if event is None:
            skipped += 1
            continue
        assert event["reason"].startswith("no valid command"), event
        delays.append(1000 * (event["unix_time"] - killed))
        operator.reset()  # stood up again for the next kill
    robot.send_signal(signal.SIGINT)
    robot.wait()
    d = np.asarray(delays)
    return {"kills": kills, "not_walking_when_killed": skipped, "kill_to_damp_p50_ms": float(np.median(d)), "kill_to_damp_max_ms": float(d.max()),
            "kill_to_damp_min_ms": float(d.min()), "watchdog_ms": 50.0, "all_ms": [round(x, 1) for x in delays]}


def stall(folder: Path, steps: int) -> dict:
    """The robot server stopped (SIGSTOP) for 2 s mid-run, then continued: the run resumes, the gap counted apart."""
    robot = server(5613, folder)
    run = train(folder, steps, "tcp://127.0.0.1:5613")
    _wait_for_step(run, 1400)  # learning for a while
    robot.send_signal(signal.SIGSTOP)
    time.sleep(2.0)
    robot.send_signal(signal.SIGCONT)
    run.communicate()
    robot.send_signal(signal.SIGINT)
    robot.wait()
    document = json.loads(next(folder.glob("*_crossq_forward.json")).read_text())
    trace = np.load(next(folder.glob("*.trace.npy")))
    return {"stall_s": 2.0, "complete": document["complete"], "steps": document["steps"],
            "link_gaps": document["link_gaps"], "gap_s": 60 * document["gap_minutes"], "robot_damps": len(damps(folder)),
            "largest_train_s_between_steps": float(np.diff(trace[:, 1]).max())}


def restart(folder: Path, steps: int) -> dict:
    """The training process SIGKILLed mid-run and started again: the robot damps itself, the run resumes from its
    last checkpoint with its replay buffer."""
    robot = server(5614, folder)
    args = ("--checkpoint-every-s", "5")
    run = train(folder, steps, "tcp://127.0.0.1:5614", args)
    _wait_for_step(run, 1400)
    killed = time.time()
    run.kill()
    run.wait()
    while not damps(folder) or damps(folder)[-1]["unix_time"] < killed:
        time.sleep(0.005)
    damped_after_ms = 1000 * (damps(folder)[-1]["unix_time"] - killed)
    again = train(folder, steps, "tcp://127.0.0.1:5614", args)
    output, _ = again.communicate()
    resumed = next((line for line in output.splitlines() if line.startswith("resuming")), None)
    robot.send_signal(signal.SIGINT)
    robot.wait()
    document = json.loads(next(folder.glob("*_crossq_forward.json")).read_text())
    replay = np.load(next(folder.glob("*.checkpoint")) / "replay.npz")
    return {"killed_after_step": 1400, "robot_damped_after_ms": damped_after_ms, "resumed": resumed,
            "complete": document["complete"], "steps": document["steps"], "replay_size": int(replay["size"])}


def _wait_for_step(run: subprocess.Popen, step: int) -> None:
    """Read the run's progress lines until it reports `step` (its line every 10 s when not on a terminal)."""
    for line in run.stdout:
        if line.startswith("step ") and int(line.split()[1].split("/")[0].rstrip(":")) >= step:
            return
    raise RuntimeError("the run ended before the step")


PARTS = ("timed", "kill_to_damp", "stall", "restart")


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--steps", type=int, default=3000, help="steps of each timed run (40 Hz; 1000 warm-up)")
    parser.add_argument("--only", nargs="+", choices=PARTS, default=list(PARTS),
                        help="measure these parts again, keeping the others of the results file")
    args = parser.parse_args()
    path = RESULTS / "link.json"
    result = json.loads(path.read_text()) if path.exists() and set(args.only) != set(PARTS) else {}
    result.update(what=" ".join(__doc__.split("\n\n")[0].split()), command="python -m benchmarks.bench_link",
                  machine=f"{os.cpu_count()} CPU cores, no GPU")
    measure = {"timed": lambda folder: timed_runs(folder, args.steps),
               "kill_to_damp": lambda folder: kill_to_damp(folder, args.kills),
               "stall": lambda folder: stall(folder, 2000), "restart": lambda folder: restart(folder, 2000)}
    with tempfile.TemporaryDirectory() as scratch:
        for part in args.only:
            (Path(scratch) / part).mkdir()
            started = time.time()
            result[part] = dict(measure[part](Path(scratch) / part), date=time.strftime("%Y-%m-%d %H:%M"),
                                wall_s=round(time.time() - started, 1))
            print(part, json.dumps(result[part]), flush=True)
            path.write_text(json.dumps(result, indent=1) + "\n")  # each part kept as soon as it is measured
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
