"""Property: any argument list a user can type gets exit 0 or exit 2 with one line, never a traceback, and exit 2
writes nothing. Hypothesis generates argument lists per command from its options and values that are valid,
at the edges (0, -1, int32's limit, NaN, infinities) or nonsense; each is parsed and checked (`cli.parse`, every
check a command makes before it runs) and never run, except `train --dry-run`, `sweep --dry-run` and `list`,
which only print. MJX_BADGER_PROPERTY_EXAMPLES sets the cases per command (default 30)."""

import collections
import contextlib
import io
import json
import os
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.cli import main as cli
from mjx_badger.control.actions import APPROACHES
from mjx_badger.core import faults
from mjx_badger.estimation import fit
from mjx_badger.estimation.learned import FIELDS
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, PROFILES
from mjx_badger.protocol.conditions import CONDITIONS
from mjx_badger.protocol.protocols import PROTOCOLS
from mjx_badger.realtime.adapters import ADAPTERS
from mjx_badger.robot.description import ROBOTS
from mjx_badger.tasks.locomotion import TASKS

EXAMPLES = int(os.environ.get("MJX_BADGER_PROPERTY_EXAMPLES", "30"))
REFERENCE = Path(__file__).resolve().parents[2] / "figures" / "data"
WITH_POLICY = REFERENCE / "quick" / "thesis-code" / "forward" / "jt-oef_crossq_forward.json"
POLICY_MISSING = REFERENCE / "quick" / "thesis-code" / "forward" / "cpg-vf_crossq_forward.json"
OMNI_POLICY = REFERENCE / "estimators" / "policy" / "cpg-vf_crossq_omni-pdec.json"
FITTED = REFERENCE / "estimators" / "thesis.estimator.npz"
OUTCOMES_FILE = os.environ.get("MJX_BADGER_PROPERTY_OUTCOMES")
"""With a path, each command's outcome counts are added to this JSON file (docs/robustness.md's table)."""

INTEGERS = ["0", "1", "2", "3", "100", "300", "-1", "2147483647", "2147483648", "99999999999999999999", "1.5", "two"]
FLOATS = ["0", "0.5", "1", "20", "-1", "nan", "inf", "-inf", "1e308", "1e999", "-0.0", "fast"]
PAIRS = ["cutoff_hz=2.0", "min_cutoff=nan", "learning_rate=0.001", "learning_rate=inf", "batch_size=0", "hidden=[0]",
         "hidden=[32,32]", "action_delay=False", "action_delay=maybe", "rewards=foo", "episode_seconds=1e999",
         "target_velocity=0.3", "speed=-inf", "nope=1", "=", "x", "jt_pd_gains=[60,3]", "jt_pd_gains=[]"]
PATHS = ["out", "results", "file", "file/sub", "/proc/version/x", "", "deep/new/folder"]
OPTIONS = {
    "--approach": list(APPROACHES) + ["jt-xyz", ""],
    "--algo": list(ALGORITHMS) + ["ppo"],
    "--task": list(TASKS) + ["backflip"],
    "--protocol": list(PROTOCOLS) + ["thesis-paper"],
    "--robot": list(ROBOTS) + ["hb40-v2"],
    "--robot-adapter": list(ADAPTERS) + ["hb50"],
    "--profile": list(PROFILES) + ["huge"],
    "--experiments": list(EXPERIMENTS) + list(GROUPS) + ["everything"],
    "--conditions": list(CONDITIONS) + ["moon"],
    "--condition": ["estimate_in_loop=False", "ground.incline_deg=nan", "ground.incline_deg=90", "ground.friction=0.9",
                    "ground.friction=(0.9,0.1)", "ground.contacts=('thigh','foot')", "ground.terrain=lava",
                    "sensing=ekf", "sensing=exact", "sensing=None", "reset_seconds=-1", "nope=1", "ground.impratio=0.5",
                    "ground.impratio=10"],
    "--results": [str(OMNI_POLICY), str(WITH_POLICY), "missing.json", "file"],
    "--dataset": ["dataset.npz", "dataset.npz", "missing.npz", "file"],
    "--inputs": ["thesis", "rich", "everything"],
    "--policies": [str(WITH_POLICY), "missing.json"],
    "--learned": [str(FITTED), "missing.npz", "file"],
    "--budgets": list(PROFILES) + ["none"],
    "--only": ["action delay", "DroQ", "reward forms", "nothing"],
    "--set": PAIRS, "--approach-param": PAIRS, "--algo-param": PAIRS, "--task-param": PAIRS,
    "--vary": ["algo_params.learning_rate=0.001,0.003", "task_params.target_velocity=0.3,nan", "steps.x=1",
               "algo_params.learning_rate=", "approach_params.cutoff_hz=1e999"],
    "--grid": ["grid.json", "file", "missing.json"],
    "--coordinator": ["localhost", "host:0", "host:99999", ":80", "a:b"],  # never valid: a valid one would join
    "--command": ["0.5,0,0", "0.5,0", "nan,0,0", "1,2,inf", "a,b,c"],
    "--engine": ["native", "mjx", "gpu"],
    "--init-from": [str(WITH_POLICY), "missing.json", "file"],
    "--link": ["tcp://127.0.0.1:5555", "tcp://10.0.0.1:5555", "http://x", "tcp://", ""],
    "--address": ["tcp://127.0.0.1:5555", "tcp://0.0.0.0:5555", "ipc:///tmp/x", "udp://x", ""],
    "--adapter": list(ADAPTERS) + ["hb50"],
    "--console-host": ["127.0.0.1", "0.0.0.0", "::1", "nothost", ""],
    "--keys": ["missing", "file", "out"],
    "--test-policy": ["missing.onnx", "file", ""],
    "--policy": ["missing.onnx", "file", ""],
    "--events": PATHS,
}
INTEGER_OPTIONS = ["--steps", "--total-steps", "--chunk-steps", "--warmup-steps", "--eval-steps", "--seeds",
                   "--first-seed", "--num-processes", "--process-id", "--vmapped", "--seed", "--init-seed", "--envs",
                   "--epochs", "--batch-size", "--console-port"]
FLOAT_OPTIONS = ["--gait-seconds", "--target-velocity", "--control-hz", "--episode-seconds", "--updates-per-step",
                 "--eval-seconds", "--reset-seconds", "--seconds", "--action-noise", "--link-timeout-s",
                 "--checkpoint-every-s", "--watchdog-periods"]
PATH_OPTIONS = ["--out", "--results-dir", "--figures-dir", "--json", "--markdown", "--plot", "--to"]
FLAGS = ["--quiet", "--restart", "--no-tensorboard", "--dry-run", "--force", "--planned-contacts", "--unthrottled",
         "--no-sensor-noise", "--console", "--operator-resets"]
RUN = ["--approach", "--algo", "--task", "--protocol", "--robot", "--set", "--approach-param", "--algo-param",
       "--task-param", "--conditions", "--condition"]
CLUSTER = ["--coordinator", "--num-processes", "--process-id"]  # --distributed would join a cluster: left out
COMMANDS = {
    "train": RUN + CLUSTER + ["--steps", "--total-steps", "--chunk-steps", "--warmup-steps", "--eval-steps",
                              "--gait-seconds", "--seeds", "--first-seed", "--out", "--quiet", "--restart",
                              "--no-tensorboard", "--dry-run"],
    "sweep": RUN + ["--steps", "--chunk-steps", "--warmup-steps", "--seeds", "--out", "--vary", "--grid", "--vmapped",
                    "--dry-run"],
    "reproduce": CLUSTER + ["--profile", "--protocol", "--experiments", "--results-dir", "--figures-dir", "--force",
                            "--no-tensorboard"],
    "figures": ["--profile", "--protocol", "--results-dir", "--figures-dir"],
    "claims": ["--profile", "--protocol", "--results-dir", "--json", "--markdown", "--plot", "--budgets"],
    "publish": ["--profile", "--protocol", "--results-dir", "--to"],
    "attribute": ["--results-dir", "--only"],
    "realtime": RUN + ["--target-velocity", "--steps", "--warmup-steps", "--control-hz", "--episode-seconds",
                       "--planned-contacts", "--updates-per-step", "--unthrottled", "--eval-seconds", "--seed",
                       "--init-from", "--init-seed", "--robot-adapter", "--reset-seconds", "--no-sensor-noise", "--out",
                       "--restart", "--quiet", "--link", "--keys", "--link-timeout-s", "--console", "--console-host",
                       "--console-port", "--operator-resets", "--test-policy", "--checkpoint-every-s"],
    "robot-server": RUN + ["--adapter", "--address", "--keys", "--watchdog-periods", "--policy", "--events",
                           "--reset-seconds", "--no-sensor-noise"],
    "link-keys": [],
    "export": ["--seed", "--out"],
    "evaluate": ["--seed", "--command", "--seconds", "--conditions", "--engine", "--json"],
    "render": ["--seed", "--command", "--seconds", "--conditions", "--out"],
    "estimator collect": ["--results", "--steps", "--envs", "--task", "--action-noise", "--seed", "--out"],
    "estimator fit": ["--dataset", "--inputs", "--epochs", "--batch-size", "--out"],
    "estimator figures": ["--policies", "--learned", "--seconds", "--seed", "--out"],
    "list": [],
}
POSITIONAL = {"evaluate": [str(WITH_POLICY)] * 3 + [str(POLICY_MISSING), "missing.json", "file"]}
POSITIONAL["render"] = POSITIONAL["export"] = POSITIONAL["evaluate"]
POSITIONAL["link-keys"] = ["keys", "new/keys", "file", ""]
MOST = {"evaluate": 3, "render": 3}
"""Options drawn at most (default 6): each of these few is refused often, so more would leave no valid case."""
LEADING = {"sweep": ["--vary"], "publish": ["--to"], "estimator fit": ["--dataset"]}
SEQUENCES = {"--experiments", "--budgets", "--only", "--policies", "--learned"}
"""Options that take several values (or none)."""


def values(option: str):
    if option in OPTIONS:
        choices = st.sampled_from(OPTIONS[option])
    elif option in INTEGER_OPTIONS:
        choices = st.sampled_from(INTEGERS)
    elif option in FLOAT_OPTIONS:
        choices = st.sampled_from(FLOATS)
    elif option in PATH_OPTIONS:
        choices = st.sampled_from(PATHS)
    else:
        return st.just([])
    if option in SEQUENCES:
        return st.lists(choices, max_size=3)
    return choices.map(lambda value: [value])


@st.composite
def arguments(draw, command: str) -> list[str]:
    """An argument list for `command`: its options with drawn values, now and then an unknown option or a stray word."""
    argv = command.split()  # "estimator fit": a command and its subcommand
    if command in POSITIONAL:
        argv.append(draw(st.sampled_from(POSITIONAL[command])))
    for option in LEADING.get(command, ()):  # what the command is hardly ever run without, most of the time
        if draw(st.integers(0, 3)):
            argv += [option] + draw(values(option))
    for option in draw(st.lists(st.sampled_from(COMMANDS[command] or ["--help-me"]), max_size=MOST.get(command, 6))):
        argv += [option] + draw(values(option))
    if draw(st.integers(0, 9)) == 0:
        argv.insert(draw(st.integers(1, len(argv))), draw(st.sampled_from(["--bogus", "stray", "-x", "--steps=1"])))
    return argv


def tiny_dataset() -> tuple[dict, dict]:
    """(arrays, meta) of an estimator dataset of 4 steps of 2 envs, for `estimator fit`'s checks."""
    arrays = {name: np.zeros((4, 2, size), np.float32) for name, size in FIELDS}
    arrays.update(velocity=np.zeros((4, 2, 3), np.float32), done=np.zeros((4, 2), bool))
    return arrays, {"robot": "hb40", "fields": [list(f) for f in FIELDS], "policy": "none",
                    "steps": 4, "envs": 2, "task": "none", "control_hz": 40.0}


def snapshot(folder: Path) -> dict:
    return {str(p.relative_to(folder)): (p.is_dir(), p.stat().st_size, p.stat().st_mtime_ns) for p in folder.rglob("*")}


def one_case(argv: list[str]) -> int:
    """Exit code of `argv` parsed and checked in a fresh folder (with a file, a results folder and a grid in it)."""
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        (folder / "file").write_text("")
        (folder / "results" / "quick" / "thesis-code").mkdir(parents=True)
        (folder / "grid.json").write_text(json.dumps({"algo_params.learning_rate": [0.001, 0.003]}))
        fit.save_dataset(folder / "dataset.npz", *tiny_dataset())
        before, cwd, errors = snapshot(folder), os.getcwd(), io.StringIO()
        os.chdir(folder)
        try:
            with contextlib.redirect_stderr(errors), contextlib.redirect_stdout(io.StringIO()):
                try:
                    command = cli.parse(argv)
                    code = 0
                except SystemExit as done:
                    code = done.code
                if code == 0 and getattr(command, "dry_run", False):
                    code = faults.run(command)  # only prints
        finally:
            os.chdir(cwd)
        err = errors.getvalue()
        assert code in (0, 2), f"{argv}: exit {code}\n{err}"
        assert "Traceback" not in err, f"{argv}:\n{err}"
        if code == 2:
            assert err.startswith("error: ") and err.count("\n") == 1, f"{argv}: not one line: {err!r}"
            assert snapshot(folder) == before, f"{argv}: refused, yet wrote {set(snapshot(folder)) - set(before)}"
        return code


@pytest.mark.parametrize("command", list(COMMANDS))
def test_any_arguments_exit_0_or_2_in_one_line_and_a_refusal_writes_nothing(command):
    outcomes = collections.Counter()

    # `list` takes no options: its cases are all unknown ones, which tyro is slow to refuse (a third of a second).
    @settings(max_examples=min(EXAMPLES, 10) if command == "list" else EXAMPLES, deadline=None, derandomize=True,
              database=None,
              suppress_health_check=list(HealthCheck))
    @given(argv=arguments(command))
    def check(argv):
        outcomes[one_case(argv)] += 1

    check()
    assert outcomes[2] > 0 or command == "list"  # the generator reaches the checks ...
    if command not in ("render", "list"):  # (render needs OpenGL, which this machine may not have)
        assert outcomes[0] > 0  # ... and gets past them too
    if OUTCOMES_FILE:
        path = Path(OUTCOMES_FILE)
        recorded = json.loads(path.read_text()) if path.exists() else {}
        recorded[command] = {"cases": sum(outcomes.values()), "exit_0": outcomes[0], "exit_2": outcomes[2]}
        path.write_text(json.dumps(recorded, indent=1) + "\n")
