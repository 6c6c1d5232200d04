"""The operator's buttons, pressed in every state; test mode's command; the live numbers and their history."""

import itertools
import threading
import time

import pytest

from mjx_badger.realtime.operator import BUTTONS, MAX_COMMAND, STATES, Operator


@pytest.mark.parametrize("button, state", itertools.product(BUTTONS, STATES))
def test_a_button_works_in_the_states_it_is_made_for_and_is_refused_in_the_others(button, state):
    operator = Operator(state)
    operator.test_refusal = None  # a test policy is there
    allowed, after = BUTTONS[button]
    error = operator.press(button)
    if state in allowed:
        assert error is None and operator.state == after and operator.refused == 0
    else:
        assert error == f"{button} is not possible while {state} (possible in: {', '.join(allowed)})"
        assert operator.state == state and operator.refused == 1


def test_every_state_can_be_left_and_every_button_leads_somewhere_known():
    assert {after for _, after in BUTTONS.values()} <= set(STATES)
    assert all(set(allowed) <= set(STATES) for allowed, _ in BUTTONS.values())
    with pytest.raises(ValueError, match="unknown state 'walking'; valid: idle, standing"):
        Operator("walking")
    operator = Operator("standing")
    assert operator.press("jump") == "unknown button 'jump'; valid: stand_up, learn, pause, collapse, reset_done, test, drive"
    assert operator.state == "standing" and operator.refused == 1


def test_test_mode_is_refused_while_there_is_no_test_policy():
    operator = Operator("standing")
    assert operator.test_refusal and operator.press("test") == operator.test_refusal
    assert operator.state == "standing"
    operator.test_refusal = None
    assert operator.press("test") is None and operator.state == "testing"


@pytest.mark.parametrize("command, why", [
    ((MAX_COMMAND[0] + 0.01, 0.0, 0.0), "stays within"),
    ((0.0, -MAX_COMMAND[1] - 0.01, 0.0), "stays within"),
    ((0.0, 0.0, MAX_COMMAND[2] + 0.01), "stays within"),
    ((float("nan"), 0.0, 0.0), "three finite numbers"),
    ((0.0, float("inf"), 0.0), "three finite numbers"),
    ((0.5, 0.0), "three finite numbers"),
    ((0.5, 0.0, 0.0, 0.0), "three finite numbers"),
    (("fast", 0.0, 0.0), "three numbers"),
    (None, "three numbers"),
])
def test_drive_takes_three_finite_numbers_within_max_command_only(command, why):
    operator = Operator("testing")
    assert operator.press("drive", (0.5, -0.2, 1.0)) is None and operator.command == (0.5, -0.2, 1.0)
    assert why in operator.press("drive", command)
    assert operator.command == (0.5, -0.2, 1.0) and operator.state == "testing" and operator.refused == 1


def test_drive_works_in_test_mode_only_and_test_mode_starts_at_rest():
    for state in set(STATES) - {"testing"}:
        assert Operator(state).press("drive", (0.1, 0.0, 0.0)) == "drive works in test mode only"
    operator = Operator("testing")
    operator.test_refusal = None
    assert operator.press("drive", MAX_COMMAND) is None and operator.command == MAX_COMMAND  # the limit itself
    assert operator.press("pause") is None and operator.press("test") is None
    assert operator.command == (0.0, 0.0, 0.0)


def test_publish_stamps_the_snapshot_and_keeps_a_short_history():
    operator = Operator("learning", history=2)
    for step in range(3):
        operator.publish({"step": step})
    assert [s["step"] for s in operator.history] == [1, 2]
    live = operator.live
    assert live["state"] == "learning" and live["command"] == [0.0, 0.0, 0.0] and live["unix_time"] <= time.time()
    assert operator.press("pause") is None
    assert operator.snapshot()["state"] == "paused" and operator.snapshot()["step"] == 2  # the state now
    assert operator.live["state"] == "learning"  # as published


def test_wait_while_wakes_on_a_press_or_a_transition_and_times_out_otherwise():
    operator = Operator("idle")
    start = time.perf_counter()
    assert operator.wait_while(("idle",), 0.05) == "idle" and time.perf_counter() - start >= 0.04
    presser = threading.Timer(0.1, operator.press, ("stand_up",))
    presser.start()
    start = time.perf_counter()
    assert operator.wait_while(("idle",), 10.0) == "standing"
    assert time.perf_counter() - start < 5.0
    threading.Timer(0.1, operator.become, ("finished",)).start()
    assert operator.wait_while(("standing",), 10.0) == "finished"
    assert operator.wait_while(("idle",), 10.0) == "finished"  # not in the states: at once
