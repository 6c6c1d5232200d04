"""Between episodes: what the robot does in the operator's states other than learning (operator.py).

standing and paused hold the nominal pose (the robot's own controller), collapsed damps the motors, idle leaves
the robot as it is, and testing walks a saved policy under the operator's command: on the robot's computer
when the robot is behind a link whose server holds a policy, else here with the same driver (test_drive.py).
"""

from mjx_badger.realtime.interface import LinkLost
from mjx_badger.realtime.test_drive import Driver

WAIT_S = 0.1
"""How often a waiting run looks at the operator again (and publishes its numbers)."""


class Between:
    """What the robot was last told between episodes, so each state's action happens once on entering it."""

    def __init__(self, started: bool, test_policy=None):
        self.started = started
        self.test_policy = test_policy
        self.last = "learning" if started else "idle"
        self.driver: Driver | None = None

    def handle(self, session, state: str) -> None:
        """Act on entering `state` (not learning), then wait a little for the operator."""
        bot = session.bot
        try:
            if state != self.last:
                self._leave_testing(bot)
                self._enter(session, state)
                self.last = state
            if state == "testing":
                self._drive(session)
        except LinkLost as error:
            session.view.note(f"the robot did not answer in {state}: {error}")
            self.last = "lost"  # try again on the next call
        session.view.show()
        # In test mode over a link every wait is a keep-alive period: the robot's watchdog allows two.
        session.operator.wait_while((state,), 0.5 / session.config.hz if state == "testing" else WAIT_S)

    def _enter(self, session, state: str) -> None:
        bot = session.bot
        if state == "collapsed":
            bot.damp()
        elif state in ("standing", "paused", "testing"):
            if not self.started:
                bot.start()
                self.started = True
            elif self.last in ("collapsed", "lost", "waiting_reset"):
                bot.reset()  # the robot lies damped: stand it up again
            else:
                bot.hold()

    def _drive(self, session) -> None:
        bot, command = session.bot, session.operator.command
        if hasattr(bot, "drive") and self.test_policy is None:
            bot.drive(command)  # the robot's own policy walks; this request is its keep-alive too
            return
        if self.driver is None:
            self.driver = Driver(bot, self.test_policy)
            self.driver.start()
        self.driver.command = command
        if self.driver.stopped:
            session.operator.become("collapsed")
            self.last = "collapsed"

    def stop_driving(self, bot) -> None:
        """No test drive goes on (the run is ending)."""
        self._leave_testing(bot)

    def _leave_testing(self, bot) -> None:
        if self.driver is not None:
            self.driver.stop()
            self.driver = None

    def entering_learning(self, session) -> None:
        """Before an episode: the robot stands (after idle, collapse or a lost link) and nothing else drives it."""
        if self.last != "learning":
            self._leave_testing(session.bot)
            if self.last not in ("standing", "paused", "testing"):
                self._enter(session, "standing")
            else:
                session.bot.hold()
            self.last = "learning"
