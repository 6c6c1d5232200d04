"""The operator: the states and buttons of the thesis's web remote, and the live numbers a console shows.

The loop asks the operator what to do at every control period (`state`); a console (console.py) or a test
presses buttons (`press`), which are checked against the state they are pressed in. The live numbers are
one snapshot dict the loop publishes a few times a second, kept with a short history for the plots.
"""

import collections
import logging
import math
import threading
import time

log = logging.getLogger("mjx_badger.operator")

STATES = ("idle", "standing", "learning", "paused", "waiting_reset", "collapsed", "testing", "finished")
"""idle: nothing moves yet; standing: the robot holds its pose; learning: episodes run and the learner updates;
paused: the robot holds its pose, the run waits; waiting_reset: a fall, until the operator stands it up again;
collapsed: motors damped by the operator; testing: a trained policy walks under the operator's velocity
command, nothing is learnt; finished: the run is over."""

BUTTONS = {
    # button: the states it may be pressed in -> the state it leads to
    "stand_up": (("idle", "collapsed", "paused", "testing"), "standing"),
    "learn": (("standing", "paused"), "learning"),
    "pause": (("learning", "testing"), "paused"),
    "collapse": (("idle", "standing", "learning", "paused", "waiting_reset", "testing"), "collapsed"),
    "reset_done": (("waiting_reset",), "learning"),
    "test": (("standing", "paused"), "testing"),
}
"""The remote's buttons; `drive` (a velocity command in test mode) changes no state."""

MAX_COMMAND = (1.5, 1.0, 2.0)
"""The largest |vx| (m/s), |vy| (m/s) and |yaw rate| (rad/s) test mode accepts."""


class Operator:
    """The run's state, the buttons that change it, the test mode's command and the live snapshot."""

    def __init__(self, state: str = "learning", operator_resets: bool = False, history: int = 600):
        if state not in STATES:
            raise ValueError(f"unknown state {state!r}; valid: {', '.join(STATES)}")
        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._state = state
        self.operator_resets = operator_resets
        """After a fall, wait for the reset_done button (else the robot's own reset is awaited, as without a console)."""
        self.command = (0.0, 0.0, 0.0)
        self.live: dict = {"state": state}
        self.history: collections.deque = collections.deque(maxlen=history)
        self.refused = 0
        self.test_refusal: str | None = "no test policy: give one with --test-policy FILE.onnx (made by `export`)"
        """Why test mode is not possible, or None where a saved policy can walk the robot."""

    @property
    def state(self) -> str:
        return self._state

    def press(self, button: str, command=None) -> str | None:
        """Press a button (or `drive` with command (vx, vy, yaw)); None if done, else why it was refused."""
        with self._lock:
            error = self._press(button, command)
            if error is None:
                self._changed.notify_all()
        if error is not None:
            self.refused += 1
            log.warning("refused %s in state %s: %s", button, self._state, error)
        return error

    def _press(self, button: str, command) -> str | None:
        if button == "drive":
            if self._state != "testing":
                return "drive works in test mode only"
            checked = _command(command)
            if isinstance(checked, str):
                return checked
            self.command = checked
            return None
        if button not in BUTTONS:
            return f"unknown button {button!r}; valid: {', '.join([*BUTTONS, 'drive'])}"
        allowed, after = BUTTONS[button]
        if self._state not in allowed:
            return f"{button} is not possible while {self._state} (possible in: {', '.join(allowed)})"
        if button == "test":
            if self.test_refusal:
                return self.test_refusal
            self.command = (0.0, 0.0, 0.0)
        self._state = after
        return None

    def become(self, state: str) -> None:
        """The loop's own transitions: a fall (waiting_reset), the reset done, the end of the run."""
        with self._lock:
            self._state = state
            self._changed.notify_all()

    def wait_while(self, states, timeout: float) -> str:
        """Block while the state is one of `states`, at most `timeout` seconds; the state then."""
        with self._lock:
            self._changed.wait_for(lambda: self._state not in states, timeout)
            return self._state

    def publish(self, snapshot: dict) -> None:
        """The loop's latest numbers (plain JSON-able values), stamped and kept for the plots."""
        snapshot = dict(snapshot, state=self._state, command=list(self.command), unix_time=time.time())
        self.live = snapshot
        self.history.append(snapshot)

    def snapshot(self) -> dict:
        return dict(self.live, state=self._state, command=list(self.command))


def _command(command) -> tuple | str:
    """The test mode's velocity command as three floats, or why it is not one."""
    try:
        values = tuple(float(c) for c in command)
    except (TypeError, ValueError):
        return "a command is three numbers: vx, vy, yaw rate"
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        return "a command is three finite numbers: vx, vy, yaw rate"
    if any(abs(v) > limit for v, limit in zip(values, MAX_COMMAND)):
        return f"a command stays within |vx| <= {MAX_COMMAND[0]}, |vy| <= {MAX_COMMAND[1]}, |yaw| <= {MAX_COMMAND[2]}"
    return values
