"""The learner thread: updates the agent from the replay buffer while the robot walks, within its cap."""

import threading

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.realtime.host_replay import HostReplay


class Learner(threading.Thread):
    """Updates the agent from the replay buffer while the robot walks; `state` is the latest agent."""

    def __init__(self, update, state, buffer: HostReplay, batch_size: int, key, allowed, updates: int = 0):
        super().__init__(name="learner", daemon=True)
        self.update, self.state, self.buffer = update, state, buffer
        self.batch_size, self.key, self.allowed = batch_size, key, allowed
        self.updates = updates
        self.metrics = {}
        self.halt = threading.Event()
        self.new_step = threading.Event()
        self._rng = np.random.default_rng(int(jax.random.randint(key, (), 0, 2**31 - 1)))

    def stop(self):
        self.halt.set()
        self.new_step.set()
        self.join()

    def run(self):
        while not self.halt.is_set():
            if not self.allowed(self.updates):
                # Sleep until the control thread stores a step: polling would take the GIL
                # thousands of times a second from the thread that must wake on time.
                self.new_step.wait(0.1)
                self.new_step.clear()
                continue
            batch = self.buffer.sample(self._rng, self.batch_size)
            state, metrics = self.update(self.state, batch, jax.random.fold_in(self.key, self.updates),
                                         jnp.int32(self.updates))
            self.state = jax.block_until_ready(state)
            self.metrics = metrics
            self.updates += 1


def replay_ratio_cap(config, progress):
    """The learner's `allowed(updates)`: nothing during warm-up, then at most `config.utd` updates
    per learning step (any number if `config.unthrottled`)."""

    def allowed(updates: int) -> bool:
        learning_steps = progress.step - config.warmup_steps
        return learning_steps > 0 and (config.unthrottled or updates < config.utd * learning_steps)

    return allowed
