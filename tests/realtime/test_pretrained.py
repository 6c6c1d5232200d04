"""The loop started from an agent trained in MJX."""

import dataclasses
import json

import jax
import numpy as np
import pytest

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.learning import checkpoints, runner
from mjx_badger.learning.config import TrainConfig
from mjx_badger.realtime import control, pretrained
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.loop import run
from mjx_badger.realtime.simulated import SimulatedHB40

# Small and slow enough for a test: 20 Hz, a 32x32 CrossQ, 20 warm-up steps, 1 s evaluation.
TINY = RealtimeConfig(approach="jt-oef", algo="crossq", steps=40, warmup_steps=20, control_hz=20.0,
                      eval_seconds=1.0, agent=ALGORITHMS["crossq"]().replace(hidden=(32, 32), batch_size=16))


def test_the_loop_starts_from_an_agent_trained_in_mjx(tmp_path):
    """--init-from: the MJX run's saved agent of the chosen seed is the loop's first agent, and it learns on."""
    trained = TrainConfig(approach="jt-oef", algo="crossq", protocol="thesis-text", total_steps=200, chunk_steps=100,
                          warmup_steps=100, eval_steps=10, agent=TINY.agent_config)
    path = tmp_path / "mjx" / "jt-oef_crossq_forward.json"
    runner.run(trained, [3, 4], path, progress=False)
    config = dataclasses.replace(TINY, init_from=str(path), init_seed=4, eval_seconds=0.0)
    _, _, agent, *_ = control.build(config)
    start = pretrained.load(config, agent)
    saved = checkpoints.load_agents(path, jax.vmap(agent.init)(jax.random.split(jax.random.PRNGKey(9), 2)))
    for a, b in zip(jax.tree.leaves(start), jax.tree.leaves(saved)):
        np.testing.assert_array_equal(a, b[1])
    assert int(start.updates) == 100  # the MJX run's updates: 200 steps, 100 of them warm-up
    document = run(config, SimulatedHB40(reset_seconds=0.1), tmp_path / "robot", resume=False, view=False)
    assert document["complete"] and document["updates"] > 0
    # A run that observed as the released code does cannot start the robot's loop.
    document = json.loads(path.read_text())
    document["config"]["protocol"] = "thesis-code"
    (tmp_path / "code.json").write_text(json.dumps(document))
    with pytest.raises(ValueError, match="its protocol is 'thesis-code', this run's 'thesis-text'"):
        dataclasses.replace(TINY, init_from=str(tmp_path / "code.json"))
    with pytest.raises(ValueError, match="holds seeds \\[3, 4\\], not 0"):
        dataclasses.replace(TINY, init_from=str(path), init_seed=0)
