"""Action pipelines: from the policy's action in [-1, 1]^A to PD joint targets.

An action space is `init() -> state` and `step(state, action) -> (state, joint_targets)`;
the approaches of thesis Table 5.2 are registered by name in `APPROACHES`.
"""

from typing import Callable, NamedTuple

import jax.numpy as jnp

from mjx_badger import filters, robot


class ActionSpace(NamedTuple):
    """A named action pipeline with its action size."""

    name: str
    size: int
    init: Callable
    step: Callable


def joint_targets(name: str, filter_name: str, dt: float) -> ActionSpace:
    """JT (§4.2): nominal pose + action scaled to +-[0.2, 0.4, 0.4], then filtered."""
    filt = filters.make_filter(filter_name, dt)
    nominal = jnp.asarray(robot.NOMINAL_POSE)
    scale = jnp.asarray(robot.JT_ACTION_SCALE)

    def step(state, action):
        # Filtering the joint targets (radians), so the One Euro beta acts on rad/s.
        return filt.step(state, nominal + scale * jnp.clip(action, -1.0, 1.0))

    return ActionSpace(name=name, size=robot.NUM_JOINTS, init=lambda: filt.init(nominal), step=step)


APPROACHES = {
    "jt-nf": lambda dt: joint_targets("jt-nf", "none", dt),
    "jt-lpf": lambda dt: joint_targets("jt-lpf", "lowpass", dt),
    "jt-oef": lambda dt: joint_targets("jt-oef", "one_euro", dt),
}


def make_action_space(approach: str, dt: float) -> ActionSpace:
    """The action pipeline of `approach` at control period `dt`."""
    return APPROACHES[approach](dt)
