"""Where the robot is: an adapter in this process or a robot server's address, checked before anything moves."""

import pytest

from mjx_badger.estimation import sensors
from mjx_badger.realtime import link_keys
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.launch import Robot
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.simulated import SimulatedHB40


@pytest.mark.parametrize("where, why", [
    (Robot(address="http://x"), r"--link takes tcp://HOST:PORT \(or ipc://PATH\), not 'http://x'"),
    (Robot(address="tcp://10.1.2.3:5555"), "tcp://10.1.2.3:5555 leaves this machine: the learner needs --keys"),
    (Robot(adapter="hb40-ros"), "unknown robot adapter 'hb40-ros'; choose from simulated"),
    (Robot(address="tcp://10.1.2.3:5555", keys="/nonexistent"), "holds no link keys"),
])
def test_check_refuses_what_cannot_be_reached_safely(where, why):
    with pytest.raises(ValueError, match=why):
        where.check()


def test_check_takes_a_local_address_or_a_remote_one_with_keys(tmp_path):
    Robot(address="tcp://127.0.0.1:5555").check()
    Robot(address="ipc:///tmp/robot").check()
    Robot(address="tcp://10.1.2.3:5555", keys=link_keys.make(tmp_path / "keys")).check()
    Robot().check()


def test_make_gives_a_linked_robot_for_an_address_and_the_adapters_robot_otherwise(tmp_path):
    keys = link_keys.make(tmp_path / "keys")
    linked = Robot(address="tcp://10.1.2.3:5555", keys=keys, timeout_s=0.02).make(RealtimeConfig())
    assert isinstance(linked, LinkedRobot) and linked.address == "tcp://10.1.2.3:5555"
    assert linked.timeout_s == 0.02 and linked.keys == keys and linked.round_trips == []  # nothing sent yet
    local = Robot(reset_seconds=0.5, sensor_noise=False).make(RealtimeConfig(seed=3))
    assert isinstance(local, SimulatedHB40) and not isinstance(local, LinkedRobot)
    assert local.reset_seconds == 0.5 and local.noise == sensors.EXACT
