"""SIGINT and SIGTERM inside `graceful`: the first is noted for the chunk at hand to finish, the handlers come back."""

import os
import signal

import pytest

from mjx_badger.core import stops


def test_a_signal_inside_the_block_is_noted_and_the_handlers_are_restored_after():
    before = signal.getsignal(signal.SIGTERM)
    with stops.graceful():
        assert stops.requested() is None
        os.kill(os.getpid(), signal.SIGTERM)  # delivered to the main thread before the next bytecode
        assert stops.requested() == signal.SIGTERM
        with stops.graceful():  # a nested block shares the outer one's note
            assert stops.requested() == signal.SIGTERM
    assert stops.requested() is None and signal.getsignal(signal.SIGTERM) is before


def test_a_second_signal_stops_at_once_and_the_exit_code_is_the_shells():
    with stops.graceful():
        os.kill(os.getpid(), signal.SIGINT)
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
    stopped = stops.Interrupted(signal.SIGTERM, "stopped")
    assert stopped.code == 128 + 15 and stops.name(signal.SIGINT) == "SIGINT"


def test_inside_a_block_left_to_the_caller_a_run_keeps_the_callers_handlers():
    caller = lambda signum, frame: None
    previous = signal.signal(signal.SIGTERM, caller)
    try:
        with stops.left_to_caller(), stops.graceful():
            assert signal.getsignal(signal.SIGTERM) is caller
        assert signal.getsignal(signal.SIGTERM) is caller
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_a_stop_crosses_from_a_runs_process_to_its_parent_whole():
    import pickle

    stop = pickle.loads(pickle.dumps(stops.Interrupted(signal.SIGTERM, "stopped by SIGTERM at step 200")))
    assert stop.code == 128 + signal.SIGTERM and str(stop) == "stopped by SIGTERM at step 200"
