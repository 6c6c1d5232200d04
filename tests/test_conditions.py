"""On-robot conditions: each field, when set, is applied; a ground MJX cannot collide is refused before compiling."""

import dataclasses
import math

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest
from mujoco import mjx

from mjx_badger import conditions, mjcf, robot, tasks, terrain
from mjx_badger.env import EnvConfig, HB40Env
from mjx_badger.train import TrainConfig

OFFICE_TRUE_VELOCITY = conditions.OFFICE.replace(estimate_in_loop=False)


def _probe_task():
    """The forward task whose reward is the velocity it is given, to see which velocity reaches the reward."""
    return tasks.forward()._replace(reward=lambda motion, command: (motion.linear_velocity[0], {}))


def _walk(env, steps=25, key=0):
    step = jax.jit(env.step)
    state = jax.jit(env.reset)(jax.random.PRNGKey(key))
    for i in range(steps):
        state = step(state, 0.4 * jnp.sin(0.4 * i + jnp.arange(env.action_size)))
    return jax.device_get(state)


@pytest.fixture(scope="module")
def office():
    return HB40Env("jt-oef", _probe_task(), EnvConfig(conditions=conditions.OFFICE))


def test_the_estimate_not_the_truth_reaches_the_reward_and_the_observation(office):
    state = _walk(office)
    estimate, truth = state.info["estimate"], state.metrics["forward_velocity"]
    assert abs(estimate[0] - truth) > 1e-3  # they differ, so the test can tell them apart
    assert state.reward == pytest.approx(float(estimate[0]), abs=1e-6)
    layout = [name for name, size, _ in office.observation_layout for _ in range(size)]
    velocity = [i for i, name in enumerate(layout) if name == "trunk_linear_velocity"]
    np.testing.assert_allclose(state.obs[velocity], estimate, atol=1e-6)  # thesis-code scales velocity by 1
    # Swapped back to the truth, the reward is the true forward velocity.
    swapped = _walk(HB40Env("jt-oef", _probe_task(), EnvConfig(conditions=OFFICE_TRUE_VELOCITY)))
    assert swapped.reward == pytest.approx(float(swapped.metrics["forward_velocity"]), abs=1e-6)


def test_the_robots_own_stop_ends_the_episode_as_a_fall(office):
    """Pitched 40 degrees: past the released robot env's 30 (thesis-code), so the first step stops it."""
    state = jax.jit(office.reset)(jax.random.PRNGKey(0))
    half = math.radians(40) / 2
    qpos = state.pipeline_state.qpos.at[3:7].set(jnp.array([math.cos(half), 0.0, math.sin(half), 0.0]))
    state = state.replace(pipeline_state=state.pipeline_state.replace(qpos=qpos))
    after = jax.device_get(jax.jit(office.step)(state, jnp.zeros(office.action_size)))
    assert after.info["terminated"] and after.info["falls"] == 1
    # A CPG robot stops too: on the robot the monitor, not the simulation code's never-terminating CPG, decides.
    cpg = HB40Env("cpg-d", "forward", EnvConfig(conditions=conditions.OFFICE))
    assert cpg.conditions.safety_stop and not cpg.protocol.cpg_terminates


def test_the_feet_stand_on_the_cobblestones_and_the_incline_tilts_the_ground():
    ground = conditions.OUTDOOR.ground
    model = mjcf.load_model(ground=ground)
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    data.ctrl[:] = robot.nominal_pose()
    for _ in range(400):  # 2 s: drop and settle
        mujoco.mj_step(model, data)
    floor = model.geom("floor").id
    touching = {model.geom(int(c.geom2 if c.geom1 == floor else c.geom1)).name for c in data.contact[:data.ncon]}
    assert touching and touching <= set(robot.HB40.foot_geoms)  # only feet touch the stones
    assert model.geom_type[floor] == mujoco.mjtGeom.mjGEOM_HFIELD
    # The floor's normal leans 3 degrees back from vertical: it rises along +x.
    normal = data.geom_xmat[floor].reshape(3, 3)[:, 2]
    assert normal[0] < 0 and math.degrees(math.acos(normal[2])) == pytest.approx(3.0, abs=1e-4)
    heights = terrain.cobblestones(ground)
    assert heights.min() == 0.0 and 0.7 < heights.max() <= 1.0  # joints at 0, crowns 75-100 % of the relief
    # On a level plane the same robot settles lower at x = 2 m than on the slope there (2 tan 3 deg = 0.105 m).
    sloped = mjcf.load_model(ground=conditions.Ground(incline_deg=3.0))
    data = mujoco.MjData(sloped)
    data.qpos[:] = robot.standing_qpos(sloped)
    data.qpos[0], data.qpos[2] = 2.0, robot.HB40.home_height + 2 * math.tan(math.radians(3))
    data.ctrl[:] = robot.nominal_pose()
    for _ in range(400):
        mujoco.mj_step(sloped, data)
    assert data.qpos[2] - 2 * math.tan(math.radians(3)) == pytest.approx(0.262, abs=0.02)  # the level settle height


def test_friction_is_drawn_per_episode_within_its_range_and_reaches_the_physics():
    env = HB40Env("jt-oef", "forward", EnvConfig(conditions=conditions.OUTDOOR))
    low, high = conditions.OUTDOOR.ground.friction
    frictions = [float(jax.jit(env.reset)(jax.random.PRNGKey(k)).info["friction"]) for k in range(6)]
    assert len(set(frictions)) == 6 and all(low <= f <= high for f in frictions)
    info = {"friction": jnp.float32(frictions[0])}
    np.testing.assert_allclose(env._ground_model(info).pair_friction[:, :2], frictions[0], rtol=1e-6)
    assert not HB40Env("jt-oef", "forward")._varies_friction  # sim: the model's own friction, nothing drawn


def test_mjx_and_native_mujoco_agree_on_the_cobblestones():
    """Half a second of the robot dropped onto the stones under a joint-target wave, both engines."""
    model = mjcf.load_model(ground=conditions.OUTDOOR.ground)
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    data.qpos[:2] = [0.31, -0.17]  # off the grid's symmetry lines
    mujoco.mj_forward(model, data)
    mx, dx = mjx.put_model(model), mjx.put_data(model, data)
    step = jax.jit(mjx.step)
    for i in range(100):
        ctrl = robot.nominal_pose() + 0.1 * np.sin(0.1 * i + np.arange(12))
        data.ctrl[:] = ctrl
        mujoco.mj_step(model, data)
        dx = step(mx, dx.replace(ctrl=jnp.asarray(ctrl, jnp.float32)))
    np.testing.assert_allclose(np.asarray(dx.qpos[:3]), data.qpos[:3], atol=0.005)  # trunk within 5 mm
    np.testing.assert_allclose(np.asarray(dx.qpos[7:]), data.qpos[7:], atol=0.03)  # joints within 0.03 rad


def test_a_part_mjx_cannot_collide_with_the_stones_is_refused_before_compiling(capsys):
    with pytest.raises(ValueError, match="geom 'FL_thigh' is a cylinder: MJX collides a height field only with "
                                         "sphere, capsule, box, mesh"):
        TrainConfig(conditions="outdoor", condition_changes=(("ground.contacts", ("thigh", "foot")),))
    from mjx_badger import cli
    with pytest.raises(SystemExit) as exit_:
        cli.main(["train", "--conditions", "outdoor", "--condition", "ground.contacts=('calf','thigh','foot')"])
    assert exit_.value.code == 2
    assert "is a cylinder" in capsys.readouterr().err


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


def test_the_on_robot_loops_simulated_robot_walks_on_the_same_ground():
    from mjx_badger.realtime.simulated import SimulatedHB40

    bot = SimulatedHB40(noise=None, conditions=conditions.OUTDOOR, seed=0)
    assert bot.model.geom_type[bot.model.geom("floor").id] == mujoco.mjtGeom.mjGEOM_HFIELD
    frictions = []
    for _ in range(4):  # the operator stands it up on another spot
        bot._stand()
        frictions.append(float(bot.model.pair_friction[0, 0]))
    low, high = conditions.OUTDOOR.ground.friction
    assert len(set(frictions)) == 4 and all(low <= f <= high for f in frictions)
    assert SimulatedHB40(noise=None).model.geom_type[0] == mujoco.mjtGeom.mjGEOM_PLANE


def test_native_evaluation_reports_the_estimate_beside_the_true_speed():
    from mjx_badger import native

    env = native.evaluation_env(TrainConfig(approach="cpg-d", conditions="office"), 1.0)
    report = native.run_native(env, lambda obs: np.zeros(env.action_size), [0.25, 0.0, 0.0], 1.0)
    assert "estimated_velocity_along_command" in report and np.isfinite(report["estimated_velocity_along_command"])
    assert "estimated_velocity_along_command" not in native.run_native(
        native.evaluation_env(TrainConfig(approach="cpg-d"), 1.0), lambda obs: np.zeros(env.action_size),
        [0.25, 0.0, 0.0], 1.0)


def test_a_floor_too_slippery_for_the_solver_is_refused_before_compiling():
    with pytest.raises(ValueError, match="ground friction 0.7 is below 1, where MJX's contact solver blows up"):
        TrainConfig(conditions="office", condition_changes=(("ground.friction", 0.7),))
    TrainConfig(conditions="office", condition_changes=(("ground.friction", 1.2),))  # above the floor: fine
    # With a ground whose solver runs at impratio 1 the check has nothing to guard.
    TrainConfig(conditions="office", condition_changes=(("ground.friction", 0.7), ("ground.impratio", 1.0)))


def test_the_stones_run_the_contact_solver_at_their_own_impratio_everywhere():
    """Outdoor's impratio reaches the MJX env, native MuJoCo and the on-robot loop's robot; the office keeps the
    model's."""
    from mjx_badger import native
    from mjx_badger.realtime.simulated import SimulatedHB40

    stones = conditions.OUTDOOR.ground.impratio
    assert stones == 10.0 and robot.HB40.impratio == 100.0
    outdoor = TrainConfig(approach="jt-oef", conditions="outdoor")
    assert float(HB40Env("jt-oef", "forward", EnvConfig(conditions=conditions.OUTDOOR)).mjx_model.opt.impratio) == stones
    assert native.evaluation_env(outdoor, 1.0).mj_model.opt.impratio == stones
    assert SimulatedHB40(noise=None, conditions=conditions.OUTDOOR).model.opt.impratio == stones
    assert mjcf.load_model(ground=conditions.OFFICE.ground).opt.impratio == robot.HB40.impratio
    with pytest.raises(ValueError, match="ground impratio 0.5: choose within 1..1000"):
        TrainConfig(conditions="outdoor", condition_changes=(("ground.impratio", 0.5),))
