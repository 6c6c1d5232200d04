"""The concurrent learner: an idle learner sleeps until a step is stored."""

import threading
import time

import jax

from mjx_badger.realtime.learner import Learner


class _RecordedEvent(threading.Event):
    """An Event that records what each wait asked and got: (timeout, woken by set)."""

    def __init__(self):
        super().__init__()
        self.waits = []

    def wait(self, timeout=None):
        woken = super().wait(timeout)
        self.waits.append((timeout, woken))
        return woken


def test_an_idle_learner_sleeps_until_a_step_is_stored():
    """Idle, it waits on the step event with a timeout (never spins); a stored step ends the wait by itself.
    Decided by what the event recorded, not by timing, so a loaded machine cannot fail it."""
    learner = Learner(update=None, state=None, buffer=None, batch_size=1, key=jax.random.PRNGKey(0),
                      allowed=lambda updates: False)
    learner.new_step = _RecordedEvent()
    learner.start()
    deadline = time.perf_counter() + 10.0
    while len(learner.new_step.waits) < 2 and time.perf_counter() < deadline:
        time.sleep(0.01)
    idle = list(learner.new_step.waits)
    assert len(idle) >= 2 and all(timeout == 0.1 and not woken for timeout, woken in idle)  # timed out, asleep
    learner.new_step.set()
    while not any(woken for _, woken in learner.new_step.waits) and time.perf_counter() < deadline:
        time.sleep(0.01)
    learner.stop()
    assert any(woken for _, woken in learner.new_step.waits[len(idle):])  # the stored step woke it
