"""HostReplay: the on-robot replay buffer in host memory, shared by the control and learner threads."""

import threading
from pathlib import Path

import numpy as np

from mjx_badger.agents.losses import Transition
from mjx_badger.core import safe_io


class HostReplay:
    """Replay buffer in host memory: the control thread adds while the learner samples."""

    def __init__(self, capacity: int, obs_size: int, action_size: int):
        self.obs = np.zeros((capacity, obs_size), np.float32)
        self.action = np.zeros((capacity, action_size), np.float32)
        self.reward = np.zeros(capacity, np.float32)
        self.next_obs = np.zeros((capacity, obs_size), np.float32)
        self.discount = np.zeros(capacity, np.float32)
        self.size = 0
        self._lock = threading.Lock()

    def add(self, obs, action, reward, next_obs, discount) -> None:
        with self._lock:
            i = self.size % len(self.reward)
            self.obs[i], self.action[i], self.reward[i] = obs, action, reward
            self.next_obs[i], self.discount[i] = next_obs, discount
            self.size += 1

    def sample(self, rng: np.random.Generator, batch_size: int) -> Transition:
        with self._lock:
            index = rng.integers(0, min(self.size, len(self.reward)), batch_size)
            return Transition(self.obs[index], self.action[index], self.reward[index], self.next_obs[index],
                              self.discount[index])

    def rows(self, start: int):
        """(obs, reward, discount, end): the steps stored from number `start` on, in the order they came."""
        with self._lock:
            end = self.size
            index = np.arange(start, end) % len(self.reward)
            return self.obs[index], self.reward[index], self.discount[index], end

    def save(self, path: Path) -> None:
        with self._lock:
            safe_io.save_npz(path, obs=self.obs, action=self.action, reward=self.reward, next_obs=self.next_obs,
                     discount=self.discount, size=self.size)

    def load(self, path: Path) -> None:
        with np.load(path) as stored:
            for name in ("obs", "action", "reward", "next_obs", "discount"):
                getattr(self, name)[:] = stored[name]
            self.size = int(stored["size"])
