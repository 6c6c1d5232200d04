"""The learner thread: updates the agent from the replay buffer while the robot walks, within its cap."""

import threading

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.realtime.host_replay import HostReplay


class Learner(threading.Thread):
    """Updates the agent from the replay buffer while the robot walks; `state` is the latest agent."""

    def __init__(self, update, state, buffer: HostReplay, batch_size: int, key, allowed, updates: int = 0,
                 agent=None, step=None):
        super().__init__(name="learner", daemon=True)
        self.update, self.state, self.buffer = update, state, buffer
        self.batch_size, self.key, self.allowed = batch_size, key, allowed
        self.updates = updates
        self.metrics = {}
        # An agent with running normalisers or resets (agents.agent.Agent): before each update it is fed every
        # step stored since, in order, and reset at its steps still ahead (`step()`: the robot's steps so far).
        self.agent, self.step = agent, step or (lambda: 0)
        self.observe = jax.jit(agent.observe) if agent is not None else None
        self.seen = buffer.size if buffer is not None else 0  # a resumed session's moments hold what came before
        self.pending_resets = [s for s in (agent.config.resets if agent is not None else ()) if s > self.step()]
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
            self.state = self.caught_up(self.state)
            batch = self.buffer.sample(self._rng, self.batch_size)
            state, metrics = self.update(self.state, batch, jax.random.fold_in(self.key, self.updates),
                                         jnp.int32(self.updates))
            self.state = jax.block_until_ready(state)
            self.metrics = metrics
            self.updates += 1


    def caught_up(self, state):
        """The agent reset if a reset step has passed, then fed the steps stored since it last was."""
        if self.agent is None:
            return state
        if self.pending_resets and self.step() >= self.pending_resets[0]:
            self.pending_resets.pop(0)
            state = self.agent.reset(state, jax.random.fold_in(self.key, 2**31 - 1 - len(self.pending_resets)))
        obs, reward, discount, self.seen = self.buffer.rows(self.seen)
        for row in range(len(reward)):  # a fall (discount 0) ends the discounted return (a time limit does not here)
            state = self.observe(state, obs[row], reward[row], 1.0 - discount[row])
        return state

    def prepare(self):
        """Compile the agent's observe before the robot moves (its result is dropped)."""
        if self.observe is not None:
            size = self.buffer.obs.shape[1]
            jax.block_until_ready(self.observe(self.state, np.zeros(size, np.float32), 0.0, 0.0))


def replay_ratio_cap(config, progress):
    """The learner's `allowed(updates)`: nothing during warm-up, then at most `config.utd` updates
    per learning step (any number if `config.unthrottled`)."""

    def allowed(updates: int) -> bool:
        learning_steps = progress.step - config.warmup_steps
        return learning_steps > 0 and (config.unthrottled or updates < config.utd * learning_steps)

    return allowed
