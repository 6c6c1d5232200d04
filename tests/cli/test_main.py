"""Bad input gets one clear line and exit code 2 before anything compiles; options come from the run specs."""

import dataclasses
import os
import subprocess
import sys

import pytest

from mjx_badger.cli.main import main
from mjx_badger.learning.config import TrainConfig
from mjx_badger.realtime.config import RealtimeConfig


def test_exit_code_2_from_the_shell_before_any_compile():
    # JAX names every program it traces or compiles when JAX_LOG_COMPILES is set: none may appear.
    done = subprocess.run([sys.executable, "-m", "mjx_badger", "train", "--approach", "nope"],
                          capture_output=True, text=True, env=dict(os.environ, JAX_LOG_COMPILES="1"))
    assert done.returncode == 2
    assert "choose from" in done.stderr and "jt-oef" in done.stderr
    assert "Compiling" not in done.stderr and "Finished tracing" not in done.stderr, done.stderr[-2000:]
    assert done.stderr.count("\n") == 1  # the one line


def test_list_names_everything(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert "jt-oef" in out and "crossq" in out and "forward" in out and "quick" in out
    assert "thesis-code, thesis-text" in out and "termination" in out and "robots: hb40, hb40-v1" in out
    assert "robot adapters: simulated" in out


@pytest.mark.parametrize("command, spec", [("train", TrainConfig), ("realtime", RealtimeConfig)])
def test_every_run_spec_field_is_an_option_with_its_docstring_as_help(capsys, command, spec):
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--help"])
    assert exit_info.value.code == 0
    help_text = " ".join(capsys.readouterr().out.replace("│", " ").split())
    hidden = {"env", "agent"}  # nested configs the protocol resolves; Python callers set them
    for field in dataclasses.fields(spec):
        if field.name not in hidden:
            assert f"--{field.name.replace('_', '-')}" in help_text, field.name
    assert "One-factor swaps of protocol fields" in help_text  # a RunSpec field's docstring, in both
    own = {"train": "Environment steps per seed", "realtime": "Control steps, warm-up included"}[command]
    assert own in help_text  # and one of the command's own fields




COMMANDS = ("train", "sweep", "reproduce", "figures", "claims", "publish", "attribute", "estimate-gain", "realtime",
            "robot-server", "link-keys", "evaluate", "render", "export", "list")


@pytest.mark.parametrize("command", COMMANDS)
def test_every_option_says_what_it_does(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    lines = [line.strip("│ ").strip() for line in capsys.readouterr().out.splitlines()]
    # tyro puts an option's help on the lines after its name; an option with none shows only its default there.
    bare = [line.split()[0] for line, after in zip(lines, lines[1:])
            if line.startswith("--") and line.split()[0] != "--help" and after.startswith("(default:")
            and len(line.split()) <= 2]
    assert not bare, f"{command}: options without help text: {bare}"
