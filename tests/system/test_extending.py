"""A newcomer's extensions, registered from this module alone: a filter, an algorithm variant (CrossQ's kind), a
task, a robot and a parameter experiment."""

import dataclasses

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest

from mjx_badger.agents.config import ALGORITHMS, Algorithm, crossq, sac
from mjx_badger.control import actions, filters
from mjx_badger.experiments import registry as experiments
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
from mjx_badger.outputs import plots
from mjx_badger.protocol import protocols
from mjx_badger.records import analysis, results
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics, mjcf
from mjx_badger.tasks import locomotion as tasks
from tests.conftest import seed_keys


def moving_average(dt: float, weight: float = 0.5) -> filters.Filter:
    """The toy filter: y = weight x + (1 - weight) y_prev, from rest at the first target."""
    return filters.Filter(init=lambda x0: jnp.asarray(x0), step=lambda y, x: (weight * x + (1 - weight) * y,) * 2)


# The toy robot: an HB40 with 4 cm longer calves and a heavier trunk, dropped from a little higher.
LONG_LEGS = dataclasses.replace(robot.HB40, name="hb40-long", calf_length=0.24, trunk_mass=7.0, home_height=0.35)


@pytest.fixture
def toys():
    """Register the toys the way docs/extending.md says, and take them out again afterwards."""
    actions.register(actions.filter_approach("jt-toy", "JT-TOY", "tab:olive", moving_average))
    ALGORITHMS["toy-crossq"] = Algorithm(lambda: crossq().replace(name="toy-crossq", hidden=(16, 16)), "Toy", "k")
    tasks.TASKS["slow-walk"] = lambda form, rules: tasks.forward(0.2, form=form)
    robot.register(LONG_LEGS)
    yield
    del actions.APPROACHES["jt-toy"], ALGORITHMS["toy-crossq"], tasks.TASKS["slow-walk"], robot.ROBOTS["hb40-long"]


def test_registered_toys_train_a_smoke_run_and_show_in_figures(toys):
    config = TrainConfig(approach="jt-toy", algo="toy-crossq", task="slow-walk", total_steps=150, chunk_steps=50,
                         warmup_steps=100, eval_steps=20, approach_params=(("weight", 0.25),), robot="hb40-long")
    config.validate()
    trainer = make_train(config)
    assert trainer.env.action_space.name == "jt-toy" and trainer.env.spec is LONG_LEGS
    carry = jax.jit(jax.vmap(trainer.init))(seed_keys([0, 1]))
    chunk = jax.jit(jax.vmap(trainer.chunk, in_axes=(0, None)))
    for index in range(config.num_chunks):
        carry, metrics = chunk(carry, index * config.chunk_steps)
    assert np.all(np.asarray(carry.agent_state.updates) == 50)
    assert np.isfinite(np.asarray(metrics["train/forward_velocity"])).all()
    assert analysis.display_name("jt-toy") == "JT-TOY" and analysis.display_name("toy-crossq") == "Toy"
    assert not actions.is_cpg("jt-toy")


def test_an_approach_parameter_reaches_its_filter_and_unknown_ones_are_named(toys):
    """weight 1 passes the target straight through; weight 0.25 moves a quarter of the way from rest."""
    outputs = {}
    for weight in (1.0, 0.25):
        space = actions.make_action_space("jt-toy", 0.02, weight=weight)
        _, ctrl = space.step(space.init(), jnp.ones(space.size))
        outputs[weight] = np.asarray(ctrl - space.rest_ctrl())
    np.testing.assert_allclose(outputs[0.25], 0.25 * outputs[1.0], rtol=1e-5)
    with pytest.raises(ValueError, match="takes weight, not cutoff"):
        TrainConfig(approach="jt-toy", approach_params=(("cutoff", 1.0),)).validate()
    with pytest.raises(ValueError, match="takes cutoff_hz, not weight"):
        TrainConfig(approach="jt-lpf", approach_params=(("weight", 1.0),)).validate()


def test_the_low_pass_cutoff_is_a_parameter():
    """A higher cutoff lets more of a step through in one control period."""
    first = {}
    for cutoff in (1.0, 8.0):
        space = actions.make_action_space("jt-lpf", 0.02, cutoff_hz=cutoff)
        _, ctrl = space.step(space.init(), jnp.ones(space.size))
        first[cutoff] = float(jnp.abs(ctrl - space.rest_ctrl()).max())
    assert 0 < first[1.0] < first[8.0]


def test_a_registered_crossq_variant_gets_the_protocols_crossq_settings(toys, monkeypatch):
    """Policy delay, renorm warm-up, actor renorm, target entropy and the next-episode bootstrap follow the
    algorithm's kind (AgentConfig.is_crossq), not its name; a SAC variant gets none of them."""
    monkeypatch.setitem(ALGORITHMS, "toy-sac", Algorithm(lambda: sac().replace(name="toy-sac"), "Toy SAC", "k"))
    for protocol in (protocols.THESIS_CODE, protocols.THESIS_TEXT):
        variant = protocol.agent_config("toy-crossq")
        assert variant == protocol.agent_config("crossq").replace(name="toy-crossq", hidden=(16, 16))
        assert (variant.policy_delay, variant.renorm_warmup_steps, variant.actor_batch_renorm) == (
            protocol.crossq_policy_delay, protocol.crossq_renorm_warmup, protocol.crossq_actor_renorm)
        assert protocol.bootstraps_from_next_episode("toy-crossq") == protocol.bootstraps_from_next_episode("crossq")
        assert protocol.agent_config("toy-sac") == protocol.agent_config("sac").replace(name="toy-sac")
        assert not protocol.bootstraps_from_next_episode("toy-sac")
    code = protocols.THESIS_CODE.agent_config("toy-crossq")
    assert code.target_entropy == -6.0 and code.policy_delay == 1 and code.renorm_warmup_steps == 1000
    assert protocols.THESIS_CODE.bootstraps_from_next_episode("toy-crossq")
    assert protocols.THESIS_CODE.agent_config("toy-sac").target_entropy is None


def test_a_task_that_cannot_take_reward_weights_is_refused_when_the_run_is_built(toys, monkeypatch):
    """slow-walk's factory has no weights=: a <term>_weight is refused by the spec's check, not by a TypeError
    when the env is built; a factory with weights=None gets one parameter per reward term."""
    assert tasks.task_params("slow-walk") == ()
    with pytest.raises(ValueError, match=r"task 'slow-walk' cannot take reward weights \(energy_weight\)"):
        TrainConfig(task="slow-walk", task_params=(("energy_weight", 0.0),))
    monkeypatch.setitem(tasks.TASKS, "slow-walk-weighted",
                        lambda form, rules, weights=None: tasks.forward(0.2, weights, form=form))
    config = TrainConfig(task="slow-walk-weighted", task_params=(("energy_weight", 0.0),))
    assert config.make_task().weights["energy"] == 0.0 and "velocity_weight" in tasks.task_params("slow-walk-weighted")


# The toy experiment: three One Euro cutoffs of JT-OEF, one registry entry drawn like the thesis's.
CUTOFFS = experiments.Experiment(
    name="oef-cutoffs", thesis_figure="none (ours)", thesis_numbers={}, figures=("forward",),
    runs=tuple(experiments.Run("jt-oef", "crossq", "forward", approach_params=(("min_cutoff", c),))
               for c in (0.5, 1.0, 2.0)))


def _document(velocity, chunks=5):
    """A hand-made complete results document of 2 seeds whose training velocity ramps to `velocity`."""
    ramp = [velocity * (i + 1) / chunks for i in range(chunks)]
    return {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1], "complete": True,
            "steps": [1000 * (i + 1) for i in range(chunks)], "sim_minutes": [0.4 * (i + 1) for i in range(chunks)],
            "metrics": {"train/forward_velocity": [[v, v] for v in ramp], "train/falls": [[1.0, 2.0]] * chunks}}


def test_a_parameter_experiment_names_files_and_draws_each_value(monkeypatch, tmp_path):
    monkeypatch.setitem(experiments.EXPERIMENTS, CUTOFFS.name, CUTOFFS)
    labels = [CUTOFFS.label(run) for run in CUTOFFS.runs]
    assert labels == ["jt-oef min_cutoff=0.5", "jt-oef min_cutoff=1.0", "jt-oef min_cutoff=2.0"]
    names = [CUTOFFS.result_name(run) for run in CUTOFFS.runs]
    assert names[0] == "jt-oef_crossq_forward__min_cutoff=0.5.json" and len(set(names)) == 3
    configs = [CUTOFFS.train_config(run, "smoke") for run in CUTOFFS.runs]
    assert [c.approach_params for c in configs] == [(("min_cutoff", c),) for c in (0.5, 1.0, 2.0)]
    folder = tmp_path / "smoke" / "thesis-code"
    for run, velocity in zip(CUTOFFS.runs, (0.3, 0.5, 0.6)):
        results.write(folder / CUTOFFS.name / CUTOFFS.result_name(run), _document(velocity))
    written = plots.draw(folder, tmp_path / "figures", "smoke", names=[CUTOFFS.name])
    assert [p.name for p in written] == ["oef-cutoffs_smoke.png", "oef-cutoffs_smoke.md"]
    table = written[1].read_text()
    assert all(f"| JT-OEF min_cutoff={c} | 2 x 5,000 |" in table for c in (0.5, 1.0, 2.0))


def test_parameters_the_runs_share_name_nothing_and_any_group_can_vary():
    """A learning-rate comparison at the real-world target: the shared target velocity is in neither label nor
    file name; the learning rate is in both and in each run's agent."""
    compared = experiments.Experiment(
        name="learning-rates", thesis_figure="-", thesis_numbers={},
        runs=tuple(experiments.Run("jt-oef", "crossq", "forward", experiments.REAL_TARGET,
                                   algo_params=(("learning_rate", rate),)) for rate in (0.001, 0.005)))
    assert [compared.label(run) for run in compared.runs] == ["jt-oef learning_rate=0.001",
                                                              "jt-oef learning_rate=0.005"]
    assert compared.result_name(compared.runs[1]) == "jt-oef_crossq_forward__learning_rate=0.005.json"
    configs = [compared.train_config(run, "quick") for run in compared.runs]
    assert [c.agent_config.learning_rate for c in configs] == [0.001, 0.005]
    assert configs[0].task_params == configs[1].task_params == experiments.REAL_TARGET


def test_a_kind_outside_jt_and_cpg_is_refused():
    with pytest.raises(ValueError, match="kind 'wheel' is not one of"):
        actions.register(actions.Approach("wheels", "wheel", "W", "k", lambda dt, p, spec: None))


def test_a_registered_robot_is_built_from_its_spec(toys):
    """The toy robot's model and kinematics both come from its spec: FK equals native MuJoCo's feet."""
    model = mjcf.load_model(LONG_LEGS)
    assert model.body("trunk").mass[0] == 7.0
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model, LONG_LEGS)
    mujoco.mj_forward(model, data)
    native = np.array([data.geom(f"{leg}_foot").xpos - data.body(f"{leg}_hip").xpos for leg in LONG_LEGS.legs])
    np.testing.assert_allclose(np.asarray(kinematics.forward(robot.nominal_pose(LONG_LEGS), LONG_LEGS)), native,
                               atol=1e-6)
    assert native[:, 2].min() < kinematics.nominal_feet()[:, 2].min() - 0.02  # the longer calves stand taller
    with pytest.raises(ValueError, match="unknown robot 'hb50'; choose from hb40, hb40-v1"):
        TrainConfig(robot="hb50")


def test_the_foot_offset_cpg_stands_any_robot_on_its_own_nominal_feet(toys):
    """thesis-text's CPG inverts the spec's own kinematics; the released code's IK is the HB40's alone."""
    space = actions.make_action_space("cpg-d", 0.025, protocols.THESIS_TEXT, LONG_LEGS)
    _, ctrl = space.step(space.init(), jnp.zeros(space.size))
    stance = np.asarray(kinematics.forward(ctrl, LONG_LEGS))[[1, 2]]  # FR and RL stand while FL and RR swing
    np.testing.assert_allclose(stance, kinematics.nominal_feet(LONG_LEGS)[[1, 2]], atol=1e-5)
    with pytest.raises(ValueError, match="runs on the hb40 only, not on hb40-long"):
        TrainConfig(approach="cpg-d", protocol="thesis-code", robot="hb40-long")
