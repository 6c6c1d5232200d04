"""A policy on native MuJoCo walks as it does on MJX: same model, action pipeline, observation and fall rule."""

import numpy as np
import pytest

from mjx_badger import native
from mjx_badger.train import TrainConfig

SECONDS = 10.0
VELOCITY_TOLERANCE = 0.03
"""m/s: MJX and native MuJoCo integrate the same contacts a little differently, and a walk amplifies it."""
YAW_TOLERANCE = 0.1
GAIT_TOLERANCE_HZ = 0.3


@pytest.mark.parametrize("approach", ["cpg-d", "jt-nf"])
def test_native_and_mjx_evaluations_agree(approach):
    env = native.evaluation_env(TrainConfig(approach=approach, task="forward"), SECONDS)
    # A fixed random linear policy: it moves the legs enough to walk off (JT) or to steer the trot (CPG).
    weights = np.random.default_rng(0).normal(0, 0.3 / np.sqrt(env.observation_size),
                                              (env.observation_size, env.action_size))
    act = lambda obs: np.tanh(obs @ weights)
    on_mjx = native.run_mjx(env, act, [0.5, 0.0, 0.0], SECONDS)
    on_native = native.run_native(env, act, [0.5, 0.0, 0.0], SECONDS)
    assert on_mjx["falls"] == on_native["falls"] == 0
    for name in ("velocity_along_command", "velocity_across_command"):
        assert abs(on_mjx[name] - on_native[name]) < VELOCITY_TOLERANCE, (name, on_mjx, on_native)
    assert abs(on_mjx["yaw_rate"] - on_native["yaw_rate"]) < YAW_TOLERANCE, (on_mjx, on_native)
    print(approach, on_mjx, on_native)
    assert abs(on_mjx["gait_hz"] - on_native["gait_hz"]) < GAIT_TOLERANCE_HZ
    # It is a walk, not a stand: the trunk moves and the feet step.
    assert abs(on_native["velocity_along_command"]) > 0.02 and on_native["gait_hz"] > 1.0
