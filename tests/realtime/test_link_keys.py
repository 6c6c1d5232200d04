"""The link's keys: CURVE where the link leaves the machine, refused without them, never overwritten."""

import threading

import pytest

from mjx_badger.realtime import link_keys
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.robot_server import RobotServer
from mjx_badger.realtime.simulated import SimulatedHB40


def test_addresses_beyond_this_machine_need_keys(tmp_path):
    assert link_keys.is_local("tcp://127.0.0.1:5555") and link_keys.is_local("tcp://localhost:1")
    assert link_keys.is_local("ipc:///tmp/robot") and not link_keys.is_local("tcp://0.0.0.0:5555")
    assert not link_keys.is_local("tcp://192.168.1.20:5555")
    with pytest.raises(ValueError, match="leaves this machine: the robot server needs --keys"):
        link_keys.check("tcp://0.0.0.0:5555", None, "robot server")
    with pytest.raises(ValueError, match="holds no link keys"):
        link_keys.check("tcp://10.0.0.2:5555", tmp_path, "learner")
    keys = link_keys.make(tmp_path / "keys")
    link_keys.check("tcp://10.0.0.2:5555", keys, "learner")
    with pytest.raises(ValueError, match="already holds keys"):
        link_keys.make(keys)


def test_with_keys_only_the_authorized_client_is_answered(tmp_path):
    keys, strangers = link_keys.make(tmp_path / "keys"), link_keys.make(tmp_path / "other")
    server = RobotServer(SimulatedHB40(), address="tcp://127.0.0.1:0", keys=keys)
    serving = threading.Thread(target=server.serve, daemon=True)
    serving.start()
    try:
        assert LinkedRobot(server.address, keys=keys).hello(2.0)["joints"] == 12
        assert LinkedRobot(server.address, keys=strangers).hello(0.5) is None  # a key the robot does not know
        assert LinkedRobot(server.address).hello(0.5) is None  # plain text to a CURVE server
    finally:
        server.halt.set()
        serving.join()
