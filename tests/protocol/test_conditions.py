"""On-robot conditions: each field, when set, is applied; a ground MJX cannot collide is refused before compiling."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.learning.config import TrainConfig
from mjx_badger.protocol import conditions
from mjx_badger.robot import description as robot
from mjx_badger.sim.env import EnvConfig, HB40Env


def test_friction_is_drawn_per_episode_within_its_range_and_reaches_the_physics():
    env = HB40Env("jt-oef", "forward", EnvConfig(conditions=conditions.OUTDOOR))
    low, high = conditions.OUTDOOR.ground.friction
    frictions = [float(jax.jit(env.reset)(jax.random.PRNGKey(k)).info["friction"]) for k in range(6)]
    assert len(set(frictions)) == 6 and all(low <= f <= high for f in frictions)
    info = {"friction": jnp.float32(frictions[0])}
    np.testing.assert_allclose(env._ground_model(info).pair_friction[:, :2], frictions[0], rtol=1e-6)
    assert not HB40Env("jt-oef", "forward")._varies_friction  # sim: the model's own friction, nothing drawn


def test_unknown_conditions_fields_and_estimators_are_refused_naming_the_choices():
    with pytest.raises(ValueError, match="unknown conditions 'moon'; choose from sim, office, outdoor"):
        TrainConfig(conditions="moon")
    with pytest.raises(ValueError, match="unknown condition fields ground.inclin"):
        TrainConfig(conditions="outdoor", condition_changes=(("ground.inclin", 0.0),))
    with pytest.raises(ValueError, match="unknown estimator 'ekf'"):
        TrainConfig(conditions="office", condition_changes=(("sensing", "ekf"),))


def test_on_the_robot_jt_runs_on_its_own_controller_and_episodes_last_20_s():
    sim, office = TrainConfig(approach="jt-oef"), TrainConfig(approach="jt-oef", conditions="office")
    assert (sim.env_config.control_hz, sim.protocol_spec.jt_pd_gains) == (50.0, (25.0, 1.0))
    assert (office.env_config.control_hz, office.protocol_spec.jt_pd_gains) == (40.0, robot.HB40.pd_gains)
    assert TrainConfig(approach="jt-lpf", algo="sac-utd20", conditions="office").env_config.control_hz == 20.0
    assert office.protocol_spec.episode_seconds == 20.0 and sim.protocol_spec.episode_seconds == 10.0
    assert dataclasses.replace(office, conditions="sim").env_config.conditions is None


def test_a_floor_too_slippery_for_the_solver_is_refused_before_compiling():
    with pytest.raises(ValueError, match="ground friction 0.7 is below 1, where MJX's contact solver blows up"):
        TrainConfig(conditions="office", condition_changes=(("ground.friction", 0.7),))
    TrainConfig(conditions="office", condition_changes=(("ground.friction", 1.2),))  # above the floor: fine
    # With a ground whose solver runs at impratio 1 the check has nothing to guard.
    TrainConfig(conditions="office", condition_changes=(("ground.friction", 0.7), ("ground.impratio", 1.0)))




def test_the_robots_cpg_settings_out_of_reach_are_refused_naming_the_range():
    with pytest.raises(ValueError, match=r"cpg_swing_height_m 0.4 is not in \(0, 0.25\] m"):
        TrainConfig(approach="cpg-d", conditions="office", condition_changes=(("cpg_swing_height_m", 0.4),))
    with pytest.raises(ValueError, match=r"cpg_frequency_hz 6 is not in \[0.5, 4\] Hz"):
        TrainConfig(approach="cpg-d", conditions="office", condition_changes=(("cpg_frequency_hz", 6.0),))
    TrainConfig(approach="cpg-d", conditions="office", condition_changes=(("cpg_swing_height_m", None),))


def test_a_results_file_from_before_a_condition_field_rebuilds_the_run_as_it_ran():
    """A quick office CPG-D run written before the robot's CPG fields and the estimate's contact trust (as every
    run before 2a9286f was) swung 0.15 m at 2 Hz with every foot alike in its filter: rebuilt so."""
    from pathlib import Path

    from mjx_badger.learning.config import from_results
    from mjx_badger.records import results
    path = Path(__file__).resolve().parents[2] / "figures/data/quick/thesis-code/real-office/cpg-d_crossq_forward.json"
    document = results.read(path)
    written = document["config"]["env"]["conditions"]
    for name in conditions.ADDED_LATER:
        written.pop(name, None)
    written["sensing"]["kalman"].pop("contact_trust", None)
    rebuilt = from_results(document).conditions_spec
    assert (rebuilt.cpg_swing_height_m, rebuilt.cpg_frequency_hz, rebuilt.robot_cpg_residual) == (None, None, False)
    assert rebuilt.stop_on_sensed and rebuilt.sensing.kalman.contact_trust == 0.0
    assert conditions.OFFICE.cpg_swing_height_m == 0.2  # today's office, for a new run


def test_the_estimators_contact_trust_is_a_condition_field_in_its_range():
    office = TrainConfig(conditions="office", condition_changes=(("kalman.contact_trust", 0.5),))
    assert office.conditions_spec.sensing.kalman.contact_trust == 0.5
    with pytest.raises(ValueError, match=r"kalman.contact_trust must be a finite number in \[0, 1\], not 1.5"):
        TrainConfig(conditions="office", condition_changes=(("kalman.contact_trust", 1.5),))
    with pytest.raises(ValueError, match="kalman.\\* sets the estimator's noise, and these conditions sense nothing"):
        TrainConfig(condition_changes=(("kalman.contact_trust", 0.5),))
