"""The ground: cobblestones and the incline under the feet, their own solver settings, what MJX cannot collide."""

import math

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest
from mujoco import mjx

from mjx_badger.cli import main as cli
from mjx_badger.learning.config import TrainConfig
from mjx_badger.protocol import conditions
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf, terrain
from mjx_badger.sim import native
from mjx_badger.sim.env import EnvConfig, HB40Env


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
    with pytest.raises(SystemExit) as exit_:
        cli.main(["train", "--conditions", "outdoor", "--condition", "ground.contacts=('calf','thigh','foot')"])
    assert exit_.value.code == 2
    assert "is a cylinder" in capsys.readouterr().err


def test_the_stones_run_the_contact_solver_at_their_own_impratio_everywhere():
    """Outdoor's impratio reaches the MJX env, native MuJoCo and the on-robot loop's robot; the office keeps the
    model's."""

    stones = conditions.OUTDOOR.ground.impratio
    assert stones == 10.0 and robot.HB40.impratio == 100.0
    outdoor = TrainConfig(approach="jt-oef", conditions="outdoor")
    assert float(HB40Env("jt-oef", "forward", EnvConfig(conditions=conditions.OUTDOOR)).mjx_model.opt.impratio) == stones
    assert native.evaluation_env(outdoor, 1.0).mj_model.opt.impratio == stones
    assert SimulatedHB40(noise=None, conditions=conditions.OUTDOOR).model.opt.impratio == stones
    assert mjcf.load_model(ground=conditions.OFFICE.ground).opt.impratio == robot.HB40.impratio
    with pytest.raises(ValueError, match="ground impratio 0.5: choose within 1..1000"):
        TrainConfig(conditions="outdoor", condition_changes=(("ground.impratio", 0.5),))
