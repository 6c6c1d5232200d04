"""Tasks: the command a robot is given and the reward it earns for following it."""

from typing import Callable, NamedTuple

import jax.numpy as jnp

from mjx_badger import rewards


class Motion(NamedTuple):
    """Raw trunk quantities a reward is computed from (trunk frame)."""

    linear_velocity: jnp.ndarray  # (3,) m/s
    angular_velocity: jnp.ndarray  # (3,) rad/s
    roll: jnp.ndarray
    pitch: jnp.ndarray
    torque: jnp.ndarray  # (12,) N m


class Task(NamedTuple):
    """A named task: `command(key) -> (3,)` [vx, vy, yaw rate], `reward(motion, command)`, term weights."""

    name: str
    command: Callable
    reward: Callable
    weights: dict


FORWARD_TARGET_VELOCITY = 0.5
FORWARD_WEIGHTS = {"velocity": 1.0, "yaw": -0.1, "roll_pitch": -10.0, "energy": -0.0003}
REWARD_SCALE = 10.0


def forward(target_velocity: float = FORWARD_TARGET_VELOCITY, weights=None) -> Task:
    """Forward locomotion at a target velocity (thesis §4.4.1, Table 4.5)."""
    weights = dict(FORWARD_WEIGHTS if weights is None else weights)

    def command(key):
        return jnp.array([target_velocity, 0.0, 0.0])

    def reward(motion: Motion, cmd):
        terms = {
            "velocity": rewards.velocity_tracking(motion.linear_velocity[0], cmd[0]),
            "yaw": rewards.yaw_rate_squared(motion.angular_velocity[2]),
            "roll_pitch": rewards.roll_pitch_squared(motion.roll, motion.pitch),
            "energy": rewards.torque_squared(motion.torque),
        }
        return rewards.combine(terms, weights, REWARD_SCALE)

    return Task(name="forward", command=command, reward=reward, weights=weights)


TASKS = {"forward": forward}


def make_task(name: str) -> Task:
    """The task called `name` with the thesis's settings."""
    return TASKS[name]()
