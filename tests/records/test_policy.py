"""Saved policies: the NumPy actor acts as the JAX agent does, and loading it needs no JAX."""

import dataclasses
import subprocess
import sys

import jax
import numpy as np
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.protocol import protocols
from mjx_badger.records import policy

OBS, ACT = 17, 5


@pytest.mark.parametrize("algo, protocol", [("crossq", protocols.THESIS_CODE), ("sac", protocols.THESIS_TEXT)])
def test_the_numpy_policy_acts_as_the_agent_does(tmp_path, algo, protocol):
    config = protocol.agent_config(algo).replace(hidden=(32, 32))
    assert config.actor_batch_renorm == (algo == "crossq" and protocol is protocols.THESIS_CODE)
    agent = make_agent(config, OBS, ACT)
    keys = jax.random.split(jax.random.PRNGKey(0), 2)
    states = jax.vmap(agent.init)(keys)  # two seeds
    rng = np.random.default_rng(0)
    # Running statistics away from their initial 0 / 1, so the renorm layers matter.
    stats = jax.tree.map(lambda x: rng.uniform(0.5, 1.5, x.shape).astype(x.dtype) if x.dtype == np.float32 else x,
                         states.actor_stats)
    states = states.replace(actor_stats=stats)
    meta = {"seeds": [3, 4], "config": {"agent": {"hidden": list(config.hidden),
                                                  "actor_batch_renorm": config.actor_batch_renorm}},
            "observation_size": OBS, "action_size": ACT, "observation_layout": [["all", OBS, 1.0]], "control_hz": 40.0}
    path = policy.save(tmp_path / "run.policy.npz", *jax.device_get((states.actor_params, states.actor_stats)), meta)
    obs = rng.normal(size=(8, OBS)).astype(np.float32)
    for index, seed in enumerate((3, 4)):
        expected = agent.act(jax.tree.map(lambda x: x[index], states), obs, None, deterministic=True)
        np.testing.assert_allclose(policy.load(path, seed)(obs), np.asarray(expected), atol=1e-5)
    with pytest.raises(ValueError, match="holds seeds \\[3, 4\\], not 0"):
        policy.load(path, 0)


def test_a_saved_policy_loads_and_acts_without_jax(tmp_path):
    meta = {"seeds": [0], "config": {"agent": {"hidden": [4], "actor_batch_renorm": False}}, "observation_size": 3,
            "action_size": 2, "observation_layout": [["all", 3, 1.0]], "control_hz": 40.0}
    params = {"Dense_0": {"kernel": np.ones((1, 3, 4)), "bias": np.zeros((1, 4))},
              "Dense_1": {"kernel": np.full((1, 4, 2), 0.1), "bias": np.zeros((1, 2))}}
    path = policy.save(tmp_path / "p.policy.npz", params, {}, meta)
    script = ("import sys; sys.modules['jax'] = None; sys.modules['flax'] = None\n"
              "from mjx_badger.records import policy\n"
              f"print(policy.load({str(path)!r})([1.0, 2.0, -1.0]).tolist())")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    np.testing.assert_allclose(eval(done.stdout), np.tanh([0.8, 0.8]), atol=1e-6)  # relu(2) x 4 x 0.1


def test_a_newer_agents_network_is_named_as_outside_the_numpy_format():
    assert policy.unsupported(dataclasses.asdict(ALGORITHMS["crossq"]())) == ""
    assert "'xqc' network is not in the NumPy policy format" in policy.unsupported(
        dataclasses.asdict(ALGORITHMS["xqc"]()))
    assert policy.unsupported({"name": "mine", "observation_norm": True}).startswith("mine standardises")
