"""A saved policy exported for the robot's computer: the ONNX actor acts as the JAX agent does, the settings
hold what the robot needs, and what cannot run there is refused in one line."""

import json
from pathlib import Path

import jax
import numpy as np
import onnx
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.control import actions
from mjx_badger.learning.config import TrainConfig
from mjx_badger.outputs import onnx_export
from mjx_badger.records import policy, results
from mjx_badger.sim.observation import observation_layout

DATA = Path(__file__).resolve().parents[2] / "figures" / "data"
WALKER = DATA / "quick" / "thesis-text" / "real-outdoor" / "jt-oef_crossq_forward.json"  # its policy holds seed 2
MAX_DIFFERENCE = 1e-5
"""The largest |ONNX - JAX| allowed over 1,000 observations (measured: 1e-6 or less, the float32 rounding)."""


def tiny_run(folder: Path, algo: str, protocol: str, seeds=(3, 4)) -> Path:
    """A results file and the saved policy of an untrained JT-NF agent of 32 x 32 (no training: the actor's
    arithmetic is what is checked), its batch statistics moved off their 0 / 1 so that renormalisation counts."""
    config = TrainConfig(approach="jt-nf", algo=algo, protocol=protocol, algo_params=(("hidden", (32, 32)),))
    space = actions.make_action_space("jt-nf", 0.025, config.protocol_spec)
    layout = observation_layout(space, config.protocol_spec)
    size = sum(s for _, s, _ in layout)
    agent = make_agent(config.agent_config, size, space.size)
    states = jax.vmap(agent.init)(jax.random.split(jax.random.PRNGKey(0), len(seeds)))
    rng = np.random.default_rng(0)
    stats = jax.tree.map(lambda x: rng.uniform(0.5, 1.5, x.shape).astype(x.dtype) if x.dtype == np.float32 else x,
                         states.actor_stats)
    document = {"schema": results.SCHEMA, "config": results.config_dict(config), "seeds": list(seeds),
                "policy": f"{config.name}.policy.npz", "complete": True}
    path = folder / f"{config.name}.json"
    results.write(path, document)
    meta = {"seeds": list(seeds), "config": json.loads(json.dumps(document["config"])), "observation_size": size,
            "control_hz": config.env_config.rate("jt-nf"), "action_size": space.size,
            "observation_layout": [list(block) for block in layout]}
    policy.save(policy.path_for(path), *jax.device_get((states.actor_params, stats)), meta)
    return path


@pytest.mark.parametrize("algo, protocol", [("sac", "thesis-text"), ("sac-utd20", "thesis-text"),
                                            ("droq", "thesis-code"), ("crossq", "thesis-text"),
                                            ("crossq", "thesis-code")])
def test_the_onnx_actor_of_every_algorithm_acts_as_the_jax_agent(tmp_path, algo, protocol):
    """Dense and relu layers (SAC, SAC-UTD20, DroQ: dropout and layer norm are the critic's) and the released
    CrossQ's batch renormalisation in the actor (thesis-code), on 1,000 observations per seed."""
    path = tiny_run(tmp_path, algo, protocol)
    for seed in (3, 4):
        out = onnx_export.export(path, seed, tmp_path / f"seed{seed}.onnx")
        difference = onnx_export.check(path, seed, out, n=1000)
        print(f"{algo} {protocol} seed {seed}: max |ONNX - JAX| {difference:.2e}")
        assert difference <= MAX_DIFFERENCE
    model = onnx.load(out)
    assert (model.opset_import[0].version, model.ir_version) == (onnx_export.OPSET, onnx_export.IR_VERSION)
    ops = {node.op_type for node in model.graph.node}
    assert ops == ({"MatMul", "Add", "Relu", "Tanh", "Sub", "Div", "Mul"} if algo == "crossq" and
                   protocol == "thesis-code" else {"MatMul", "Add", "Relu", "Tanh"})
    shape = [d.dim_param or d.dim_value for d in model.graph.input[0].type.tensor_type.shape.dim]
    assert shape == ["batch", 54] and model.graph.input[0].type.tensor_type.elem_type == onnx.TensorProto.FLOAT


def test_a_committed_policy_exports_with_everything_the_robot_needs(tmp_path):
    out = onnx_export.export(WALKER, None, tmp_path / "robot" / "walker.onnx")
    difference = onnx_export.check(WALKER, None, out)
    print(f"committed thesis-text JT-OEF: max |ONNX - JAX| {difference:.2e} on 1,000 observations")
    assert difference <= MAX_DIFFERENCE
    settings = json.loads((tmp_path / "robot" / "walker.onboard.json").read_text())
    assert settings["schema"] == "mjx_badger.onboard/1" and settings["onnx"]["file"] == "walker.onnx"
    assert settings["source"] == {**settings["source"], "results": WALKER.name, "seed": 2}
    assert (settings["approach"], settings["kind"], settings["control_hz"], settings["control_dt"]) == (
        "jt-oef", "jt", 40.0, 0.025)
    assert settings["pd_gains"] == [60.0, 3.0] and len(settings["nominal_pose"]) == 12
    assert settings["observation"]["size"] == 54
    assert settings["observation"]["angular_acceleration"] == "gyro-difference"
    assert settings["filter"] == {"name": "one_euro", "params": {"min_cutoff": 2.5, "beta": 0.1, "d_cutoff": 100.0,
                                                                 "start_at_first_input": False}}
    assert settings["action"]["scale"][:3] == pytest.approx([0.2, 0.4, 0.4])
    assert settings["task"]["command"] == [0.25, 0.0, 0.0]
    assert settings["estimator"] == {"name": "kinematic-kalman", "acceleration_std": 0.5, "odometry_std": 0.1,
                                     "trained_with": "kinematic-kalman"}


def test_observations_are_drawn_where_the_actor_works(tmp_path):
    """Each block about its quantity's value on a walking robot; an input-renormalising actor from its statistics."""
    _, _, actor = onnx_export.saved(WALKER, None)
    obs = onnx_export.observations(actor, 4000)
    assert obs.dtype == np.float32 and obs.shape == (4000, 54)
    np.testing.assert_allclose(obs[:, 51:54].mean(0), [0.0, 0.0, -1.0], atol=0.01)  # projected gravity
    np.testing.assert_allclose(obs[:, 12:24].std(0), 0.3, rtol=0.1)  # 3 rad/s at scale 0.1
    _, _, renorm = onnx_export.saved(tiny_run(tmp_path, "crossq", "thesis-code"), 3)
    mean, var = renorm.arrays["BatchRenorm_0/mean"], renorm.arrays["BatchRenorm_0/var"]
    obs = onnx_export.observations(renorm, 4000)
    np.testing.assert_allclose(obs.std(0), np.sqrt(var), rtol=0.1)
    np.testing.assert_allclose(obs.mean(0), mean, atol=0.1)


def _no_policy(tmp_path):
    document = json.loads(WALKER.read_text())
    del document["policy"]
    (tmp_path / "run.json").write_text(json.dumps(document))
    return tmp_path / "run.json", None


QUICK = DATA / "quick" / "thesis-text"
REFUSED = {
    "no results file": (lambda tmp: (tmp / "none.json", None), "no results file"),
    "no policy named": (_no_policy, "has no saved policy"),
    "policy not committed": (lambda tmp: (QUICK / "forward" / "jt-oef_crossq_forward.json", None), "is missing"),
    "unknown seed": (lambda tmp: (WALKER, 0), r"holds seeds \[2\], not 0"),
    "negative seed": (lambda tmp: (WALKER, -1), "--seed"),
    "two PD controllers": (lambda tmp: (QUICK / "real-office" / "cpg-rt_crossq_forward.json", None),
                           "cpg-rt under thesis-text combines by 'torque-average', two PD controllers per joint.*"
                           "the onboard runner takes jt-nf, jt-lpf, jt-oef, cpg-d, cpg-vf, cpg-rt-avg, cpg-rt-sum"),
    "released code's CPG": (lambda tmp: (DATA / "full" / "thesis-code" / "forward" / "cpg-d_crossq_forward.json",
                                         None), "cpg-d under thesis-code: the released code's CPG .* is not ported"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_what_the_robot_cannot_run_is_refused_in_one_line_and_nothing_written(tmp_path, case):
    make, message = REFUSED[case]
    results_file, seed = make(tmp_path)
    out = tmp_path / "out" / "policy.onnx"
    with pytest.raises(ValueError, match=message) as refused:
        onnx_export.export(results_file, seed, out)
    assert "\n" not in str(refused.value)
    assert not out.parent.exists()


def test_check_and_export_name_a_wrong_output_or_a_missing_onnx_file(tmp_path):
    with pytest.raises(ValueError, match="ends in .onnx"):
        onnx_export.export(WALKER, None, tmp_path / "policy.json")
    with pytest.raises(ValueError, match="no ONNX file"):
        onnx_export.check(WALKER, None, tmp_path / "policy.onnx")
    with pytest.raises(ValueError, match="n must"):
        onnx_export.check(WALKER, None, tmp_path / "policy.onnx", n=0)
