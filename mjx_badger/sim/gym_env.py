"""The HB40 as a Gymnasium environment on native MuJoCo, for sbx, Stable-Baselines3, cleanrl and the like.

`gymnasium.make("mjx_badger/HB40-v0", approach="jt-oef", task="forward", protocol="thesis-code")`
(registered when `mjx_badger` is imported, without importing this module). One robot on native MuJoCo, stepped by
`native.NativeEnv`: the MJX env's own model file, reset, action pipeline, observation, reward,
termination and task (curriculum included), so nothing is typed twice. An episode ends as the
MJX env's do: `terminated` on a fall (never for the CPG under thesis-code, whose episodes do not
terminate), `truncated` at the protocol's episode length. A curriculum's state carries over
from one episode to the next of the same env, as it does across the MJX env's auto-resets.
"""

import gymnasium
import jax
import numpy as np
from gymnasium import spaces

from mjx_badger.protocol import protocols
from mjx_badger.robot import description as robot
from mjx_badger.sim import native, render
from mjx_badger.sim.env import EnvConfig, HB40Env


class HB40GymEnv(gymnasium.Env):
    """One HB40 on native MuJoCo under an approach, a task and a protocol."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 25}

    def __init__(self, approach: str = "jt-nf", task: str = "forward", protocol: str = "thesis-code",
                 robot_name: str = "hb40", render_mode: str | None = None):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode={render_mode!r}; choose None or 'rgb_array'")
        config = EnvConfig(protocol=protocols.get(protocol))
        self.mjx_env = HB40Env(approach, task, config, robot.ROBOTS[robot_name])
        self.native = native.NativeEnv(self.mjx_env)
        self.render_mode = render_mode
        self.metadata = dict(self.metadata, render_fps=int(round(self.mjx_env.control_hz)))
        # Observations are physical quantities (accelerations included) with no hard bound.
        self.observation_space = spaces.Box(-np.inf, np.inf, (self.mjx_env.observation_size,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (self.mjx_env.action_size,), np.float32)
        self._task_state, self._renderer = None, None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """A new episode; `options={"command": (vx, vy, yaw)}` fixes its command, else the task draws one."""
        super().reset(seed=seed)
        command = (options or {}).get("command")
        key = jax.random.PRNGKey(int(self.np_random.integers(2**31)))
        state = self.native.reset(key, command, self._task_state)
        self._task_state = state.info["task_state"]
        obs, _, _, _, info = self._host(state)
        return obs, info

    def step(self, action):
        state = self.native.step(np.clip(np.asarray(action, np.float32), -1.0, 1.0))
        self._task_state = state.info["task_state"]
        return self._host(state)

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = render.follower(self.mjx_env)
        return self._renderer(self.native.data)

    def close(self):
        self._renderer = None

    @staticmethod
    def _host(state):
        """(obs, reward, terminated, truncated, info) on the host, in one transfer; new arrays every call
        (Gymnasium checks that returned data is not reused)."""
        obs, reward, terminated, truncated, command, metrics = jax.device_get(
            (state.obs, state.reward, state.info["terminated"], state.info["truncated"], state.info["command"],
             state.metrics))
        info = {"command": np.array(command), "fell": bool(terminated)}
        info.update({name: float(value) for name, value in metrics.items()})
        return np.array(obs, dtype=np.float32), float(reward), bool(terminated), bool(truncated), info
