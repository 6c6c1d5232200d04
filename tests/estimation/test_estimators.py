"""The shared velocity estimators (thesis §2.6): what each must do on signals whose answer is known."""

import dataclasses
import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.estimation import estimators, sensors
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics
from mjx_badger.sim.env import EnvConfig, HB40Env
from tests.commands import refused

DT = 0.025
POSE = np.asarray(robot.nominal_pose(), np.float32)


def _reading(acceleration=(0.0, 0.0, 9.81), joint_velocity=None, contacts=(1, 1, 1, 1)) -> estimators.Reading:
    """A level trunk: encoders at the nominal pose, the given specific force, no rotation rate."""
    return estimators.Reading(jnp.asarray(POSE), jnp.zeros(12) if joint_velocity is None else jnp.asarray(joint_velocity),
                              jnp.asarray(acceleration, jnp.float32), jnp.zeros(3), jnp.eye(3),
                              jnp.asarray(contacts, jnp.float32), jnp.zeros(12))


def _run(estimator, readings, dt=DT):
    step = jax.jit(estimator.step)
    state, out = estimator.init(), []
    for reading in readings:
        state, velocity = step(state, reading, dt)
        out.append(np.asarray(velocity))
    return np.array(out)


@pytest.mark.parametrize("name", list(estimators.ESTIMATORS))
def test_standing_still_reads_zero(name):
    velocity = _run(estimators.make(name), [_reading()] * 80)
    np.testing.assert_allclose(velocity, 0.0, atol=1e-5)


def test_constant_acceleration_integrates_to_a_ramp():
    """0.5 m/s^2 forward from rest: the trapezoidal rule is exact, v(t) = 0.5 t (the first step starts from rest)."""
    readings = [_reading((0.5, 0.0, 9.81))] * 40
    velocity = _run(estimators.make("integration"), readings)
    times = DT * np.arange(1, 41)
    np.testing.assert_allclose(velocity[:, 0], 0.5 * (times - DT / 2), atol=1e-4)


def test_a_constant_bias_drifts_the_integration_at_its_own_rate_and_a_reset_recalibrates():
    """A 0.05 m/s^2 accelerometer bias on a robot at rest: after 20 s the estimate is off by about 1 m/s."""
    bias = 0.05
    velocity = _run(estimators.make("integration"), [_reading((bias, 0.0, 9.81))] * int(20 / DT))
    assert velocity[-1, 0] == pytest.approx(bias * (20 - DT / 2), rel=1e-3)
    assert abs(velocity[-1, 1]) < 1e-5
    # The kinematic filter, corrected by the still legs, does not drift.
    held = _run(estimators.make("kinematic-kalman"), [_reading((bias, 0.0, 9.81))] * int(20 / DT))
    assert abs(held[-1, 0]) < 0.01
    fresh = estimators.make("integration").init()
    assert not np.any(np.asarray(fresh.velocity))


def test_averaging_all_four_legs_of_a_trot_underestimates_by_the_swing_legs_share():
    """Trunk at v over two stance feet; the two swing feet move forward at 2v in the world (the trot's swing),
    so each implies v - 2v = -v for the trunk: all four averaged read (2v - 2v) / 4 = 0; the stance legs alone, v."""
    spec, v = robot.HB40, 0.4
    stance = np.array([1, 0, 0, 1], np.float32)  # FL and RR on the ground, FR and RL in the air
    odometry = np.zeros((4, 3), np.float32)
    odometry[:, 0] = np.where(stance > 0, v, -v)  # the trunk velocity each foot implies
    # Joint velocities whose feet move so: solve the legs' Jacobians for the wanted foot velocities.
    feet_velocity = -odometry  # no rotation: v_trunk = -dp/dt
    jacobian = jax.jacfwd(lambda q: kinematics.forward(q, spec=spec))(jnp.asarray(POSE))
    joint_velocity = np.linalg.lstsq(np.asarray(jacobian).reshape(12, 12), feet_velocity.reshape(12), rcond=None)[0]
    np.testing.assert_allclose(estimators.leg_odometry(jnp.asarray(POSE), jnp.asarray(joint_velocity, jnp.float32),
                                                       jnp.zeros(3), spec), odometry, atol=1e-4)
    all_feet = _run(estimators.make("kinematic-kalman"), [_reading(joint_velocity=joint_velocity)] * 80)
    stance_only = _run(estimators.make("kinematic-kalman-contact"),
                       [_reading(joint_velocity=joint_velocity, contacts=stance)] * 80)
    # The thesis's filter ignores any contacts it is given: all four feet, always.
    ignored = _run(estimators.make("kinematic-kalman"), [_reading(joint_velocity=joint_velocity, contacts=stance)] * 80)
    np.testing.assert_allclose(ignored, all_feet, atol=1e-6)
    # No acceleration: the filter settles on its odometry, 0 for all four feet and v for the contact-aware variant.
    assert abs(all_feet[-1, 0]) < 1e-3
    assert stance_only[-1, 0] == pytest.approx(v, abs=1e-3)
    # The study's family between them: trust 0.5 weighs stance feet 1 and swing feet 1/2, (2v - v) / 3.
    half = _run(estimators.make("kinematic-kalman", estimators.KalmanConfig(contact_trust=0.5)),
                [_reading(joint_velocity=joint_velocity, contacts=stance)] * 80)
    assert half[-1, 0] == pytest.approx(v / 3, abs=1e-3)


def test_the_estimators_vmap_over_robots():
    estimator = estimators.make("kinematic-kalman")
    readings = jax.tree.map(lambda *x: jnp.stack(x), *[_reading((a, 0.0, 9.81)) for a in (0.0, 0.3, -0.2)])
    states = jax.vmap(lambda _: estimator.init())(jnp.arange(3))
    batched = jax.vmap(estimator.step, in_axes=(0, 0, None))(states, readings, DT)[1]
    for i, a in enumerate((0.0, 0.3, -0.2)):
        single = estimator.step(estimator.init(), _reading((a, 0.0, 9.81)), DT)[1]
        np.testing.assert_allclose(batched[i], single, atol=1e-6)


def test_an_unknown_estimator_is_refused_naming_the_choices():
    with pytest.raises(ValueError, match="unknown estimator 'ekf'; choose from kinematic-kalman, kinematic-kalman-contact, integration, learned"):
        estimators.make("ekf")


def test_an_unknown_estimator_or_input_set_is_refused(capsys):
    with pytest.raises(ValueError, match="unknown estimator 'ekf'; choose from kinematic-kalman, "
                                         "kinematic-kalman-contact, integration, learned"):
        HB40Env("jt-oef", "forward", EnvConfig(sensing=sensors.Sensing(estimator="ekf")))
    err = refused(capsys, ["estimator", "fit", "--inputs", "everything"])
    assert "everything" in err and "thesis" in err and "rich" in err
    with pytest.raises(ValueError, match="the learned estimator needs its file"):
        estimators.make("learned")
    json.dumps(dataclasses.asdict(sensors.Sensing()))  # a results file can record it
