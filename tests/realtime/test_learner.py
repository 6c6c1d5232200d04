"""The concurrent learner: an idle learner sleeps until a step is stored; an agent with running moments is fed
every stored step once, in order, and reset at its steps."""

import threading
import time

import jax
import numpy as np

from mjx_badger.realtime.host_replay import HostReplay
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


class _Agent:
    """What the learner needs of an agent with running moments and a reset, recording each call."""

    def __init__(self, resets):
        self.config = type("Config", (), {"resets": resets})()
        self.calls = []

    def observe(self, state, obs, reward, done):
        return state + [("observe", float(obs[0]), float(reward), float(done))]

    def reset(self, state, key):
        return state + [("reset",)]


def test_the_learner_feeds_each_stored_step_once_in_order_and_resets_when_its_step_has_passed():
    buffer = HostReplay(10, 2, 1)
    for i in range(3):
        buffer.add(np.full(2, i), np.zeros(1), 10.0 + i, np.zeros(2), 0.0 if i == 1 else 1.0)
    steps = [3]
    learner = Learner(update=None, state=[], buffer=HostReplay(10, 2, 1), batch_size=1, key=jax.random.PRNGKey(0),
                      allowed=lambda updates: False, agent=_Agent(resets=(2, 5, 9)), step=lambda: steps[0])
    learner.buffer, learner.observe = buffer, learner.agent.observe  # plain Python: nothing to compile
    assert learner.pending_resets == [5, 9]  # a reset step already behind a resumed session is not redone
    state = learner.caught_up([])
    assert state == [("observe", 0.0, 10.0, 0.0), ("observe", 1.0, 11.0, 1.0), ("observe", 2.0, 12.0, 0.0)]
    buffer.add(np.full(2, 3), np.zeros(1), 13.0, np.zeros(2), 1.0)
    steps[0] = 5
    state = learner.caught_up(state)
    assert state[3:] == [("reset",), ("observe", 3.0, 13.0, 0.0)] and learner.pending_resets == [9]
    assert learner.caught_up(state) == state  # nothing new stored, no step passed
