"""`realtime`, `robot-server`, `link-keys` and `export`: what a robot cannot run, or cannot be reached safely with, is
refused in one line before anything compiles or is written."""

import json

import pytest

from mjx_badger.cli import robot
from mjx_badger.cli.main import main
from tests.commands import refused
from tests.outputs.test_onnx_export import WALKER


def test_realtime_refuses_what_a_robot_cannot_run(capsys):
    assert "cpg-rt-avg" in refused(capsys, ["realtime", "--approach", "cpg-rt"])
    assert "unknown robot adapter 'hb50'; choose from simulated" in refused(capsys, ["realtime", "--robot-adapter", "hb50"])
    assert "planned contacts" in refused(capsys, ["realtime", "--approach", "jt-oef", "--planned-contacts"])
    assert "warmup_steps (200) must be smaller" in refused(capsys, ["realtime", "--steps", "100", "--warmup-steps", "200"])
    assert "control rate" in refused(capsys, ["realtime", "--control-hz", "500"])


def test_a_negative_reset_time_or_an_unknown_robot_is_refused_by_the_commands_check(tmp_path):
    with pytest.raises(ValueError, match=r"--reset-seconds must be a finite number in \[0, 3600\], not -1.0"):
        robot.Realtime(reset_seconds=-1.0, out=tmp_path).check()
    with pytest.raises(ValueError, match="unknown robot adapter 'hb40-ros'; choose from simulated"):
        robot.Realtime(robot_adapter="hb40-ros", out=tmp_path).check()


@pytest.mark.parametrize("argv, says", [
    (["robot-server", "--address", "tcp://0.0.0.0:5555"], "the robot server needs --keys FOLDER"),
    (["robot-server", "--address", "http://x"], "--address takes tcp://HOST:PORT (or ipc://PATH), not 'http://x'"),
    (["realtime", "--link", "tcp://10.1.2.3:5555"], "tcp://10.1.2.3:5555 leaves this machine: the learner needs --keys"),
    (["realtime", "--console-host", "nothost"], "--console-host takes an IP address"),
])
def test_a_link_beyond_this_machine_without_keys_or_a_bad_address_is_refused(capsys, tmp_path, argv, says):
    out = tmp_path / "out"
    refused(capsys, argv + (["--out", str(out)] if argv[0] == "realtime" else []), says)
    assert not out.exists()


def test_link_keys_writes_a_key_folder_once_and_never_overwrites_it(capsys, tmp_path):
    folder = tmp_path / "keys"
    assert main(["link-keys", str(folder)]) == 0
    assert f"keys: {folder}" in capsys.readouterr().out
    names = ["authorized/client.key", "client.key", "client.key_secret", "server.key", "server.key_secret"]
    assert sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()) == names
    before = {name: (folder / name).read_bytes() for name in names}
    refused(capsys, ["link-keys", str(folder)], f"{folder} already holds keys")
    assert {name: (folder / name).read_bytes() for name in names} == before


def test_export_of_a_run_without_a_saved_policy_is_refused_and_writes_nothing(capsys, tmp_path):
    document = json.loads(WALKER.read_text())
    del document["policy"]
    (tmp_path / "run.json").write_text(json.dumps(document))
    out = tmp_path / "out" / "policy.onnx"
    refused(capsys, ["export", str(tmp_path / "run.json"), "--out", str(out)], "has no saved policy")
    assert not out.parent.exists()
