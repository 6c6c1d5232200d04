"""Between episodes: each state's action on the robot happens once, on entering it; test mode drives on."""

from types import SimpleNamespace

from mjx_badger.realtime.interface import LinkLost
from mjx_badger.realtime.operating import Between
from mjx_badger.realtime.operator import Operator
from mjx_badger.robot import description as robot
from tests.realtime.test_robot_server import Recorder, until
from tests.realtime.test_test_drive import Policy


class Bot:
    """A robot that only records what it is told; its reset fails `lost` times (the link down)."""

    def __init__(self, lost=0):
        self.calls, self.lost = [], lost

    def start(self):
        self.calls.append("start")

    def hold(self):
        self.calls.append("hold")

    def damp(self):
        self.calls.append("damp")

    def reset(self):
        self.calls.append("reset")
        if self.lost:
            self.lost -= 1
            raise LinkLost("no reply from tcp://127.0.0.1:5555 to reset within 120000 ms")


class Linked(Bot):
    """A robot behind a link whose server holds a policy: `drive` walks it."""

    def drive(self, command):
        self.calls.append(("drive", command))


def session(bot, state):
    notes = []
    view = SimpleNamespace(show=lambda: None, note=notes.append, notes=notes)
    return SimpleNamespace(bot=bot, operator=Operator(state), view=view, config=SimpleNamespace(hz=40.0))


def test_collapsed_damps_once_and_standing_after_it_stands_the_robot_up_again():
    s, between = session(Bot(), "collapsed"), Between(started=True)
    for _ in range(3):
        between.handle(s, "collapsed")
    assert s.bot.calls == ["damp"]
    assert s.operator.press("stand_up") is None
    between.handle(s, "standing")
    between.handle(s, "standing")
    assert s.bot.calls == ["damp", "reset"]  # it lay damped: a reset, not a hold


def test_paused_and_standing_hold_the_pose_and_the_first_of_them_starts_the_robot():
    s, between = session(Bot(), "standing"), Between(started=False)
    between.handle(s, "idle")
    assert s.bot.calls == []  # idle: nothing moves
    between.handle(s, "standing")
    between.handle(s, "paused")
    between.handle(s, "paused")
    assert s.bot.calls == ["start", "hold"]
    between.entering_learning(s)
    assert s.bot.calls == ["start", "hold", "hold"] and between.last == "learning"


def test_a_lost_link_is_noted_and_the_state_entered_again_on_the_next_call():
    s, between = session(Bot(lost=1), "standing"), Between(started=True)
    between.last = "collapsed"
    between.handle(s, "standing")
    assert between.last == "lost" and "did not answer in standing" in s.view.notes[0]
    between.handle(s, "standing")
    assert s.bot.calls == ["reset", "reset"] and between.last == "standing" and len(s.view.notes) == 1


def test_testing_over_a_link_sends_the_operators_command_as_a_drive_each_call():
    s, between = session(Linked(), "testing"), Between(started=True)
    assert s.operator.press("drive", (0.5, 0.0, 0.25)) is None
    between.handle(s, "testing")
    assert s.operator.press("drive", (0.0, -0.3, 0.0)) is None
    between.handle(s, "testing")
    assert s.bot.calls == ["hold", ("drive", (0.5, 0.0, 0.25)), ("drive", (0.0, -0.3, 0.0))]
    assert between.driver is None  # the robot's own policy walks it, nothing drives from here
    assert s.operator.press("pause") is None
    between.handle(s, "paused")
    assert s.bot.calls[-1] == "hold"


def test_testing_in_process_drives_with_the_test_policy_until_it_trips_then_collapses():
    bot = Recorder()
    s, between = session(bot, "testing"), Between(started=True, test_policy=Policy(trip_at=3))
    between.handle(s, "testing")
    assert between.driver is not None
    until(lambda: between.handle(s, "testing") or s.operator.state == "collapsed")
    assert between.last == "collapsed" and bot.gains == robot.HB40.damping_gains
    between.stop_driving(bot)
    assert between.driver is None and len(bot.calls) == 1 + 3  # entering test mode's hold, three steps
