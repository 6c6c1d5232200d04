"""Robot adapters by name: a robot without a ground truth logs NaN for it."""

import numpy as np
import pytest

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.estimation import sensors
from mjx_badger.realtime import adapters, control, interface
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.simulated import SimulatedHB40

# Small and slow enough for a test: 20 Hz, a 32x32 CrossQ, 20 warm-up steps, 1 s evaluation.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=40, warmup_steps=20, control_hz=20.0,
                      eval_seconds=1.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))


def test_the_robot_is_taken_by_its_adapters_name_and_one_without_a_ground_truth_logs_nan():
    bot = adapters.make("simulated", TINY, reset_seconds=0.0, sensor_noise=False)
    assert isinstance(bot, SimulatedHB40) and bot.noise is sensors.EXACT and bot.reset_seconds == 0.0
    np.testing.assert_array_equal(control.true_velocity(bot), np.zeros(3))  # standing, not yet started

    class Blind(interface.Robot):
        """A robot with sensors and motors but no ground truth: `truth` is the protocol's None."""

    assert np.isnan(control.true_velocity(Blind())).all()
    with pytest.raises(ValueError, match="unknown robot adapter 'hb50'; choose from simulated"):
        adapters.make("hb50", TINY)
