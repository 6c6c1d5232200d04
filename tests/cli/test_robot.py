"""`realtime`: what a robot cannot run is refused before anything compiles."""

import pytest

from mjx_badger.cli import robot
from tests.commands import refused


def test_realtime_refuses_what_a_robot_cannot_run(capsys):
    assert "cpg-rt-avg" in refused(capsys, ["realtime", "--approach", "cpg-rt"])
    assert "unknown robot adapter 'hb50'; choose from simulated" in refused(capsys, ["realtime", "--robot-adapter", "hb50"])
    assert "planned contacts" in refused(capsys, ["realtime", "--approach", "jt-oef", "--planned-contacts"])
    assert "warmup_steps (200) must be smaller" in refused(capsys, ["realtime", "--steps", "100", "--warmup-steps", "200"])
    assert "control rate" in refused(capsys, ["realtime", "--control-hz", "500"])


def test_a_negative_reset_time_or_an_unknown_robot_is_refused_by_the_commands_check(tmp_path):
    with pytest.raises(ValueError, match="--reset-seconds must not be negative"):
        robot.Realtime(reset_seconds=-1.0, out=tmp_path).check()
    with pytest.raises(ValueError, match="unknown robot adapter 'hb40-ros'; choose from simulated"):
        robot.Realtime(robot_adapter="hb40-ros", out=tmp_path).check()
