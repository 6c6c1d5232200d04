"""The HB40 of the thesis code: its figures, its kinematics, it stands, and MJX agrees with native MuJoCo."""

import dataclasses

import mujoco
import numpy as np

from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf


def test_model_figures_are_the_thesis_codes():
    model = mjcf.load_model()
    assert model.opt.timestep == robot.HB40.physics_dt == 0.005
    assert model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL and model.opt.impratio == 100
    # 5.423 trunk + 4 x (0.645 + 0.827 + 0.118) = 11.783 kg
    np.testing.assert_allclose(model.body("trunk").subtreemass[0], 11.783, atol=1e-3)
    # plane.xml's inertias, not a uniform box's (0.019, 0.037, 0.047)
    np.testing.assert_allclose(model.body("trunk").inertia, [0.6228, 0.4899, 0.1946], atol=1e-6)
    np.testing.assert_allclose(sorted(model.body("FL_calf").inertia), sorted([0.0213, 0.0212, 0.0002]), atol=1e-6)
    # Floor against trunk, and per leg thigh motor, calf and foot: 13 pairs.
    assert model.npair == 13 and model.nu == 12
    assert model.body("trunk").pos[2] == robot.HB40.home_height == 0.316
    np.testing.assert_allclose(model.jnt_range[1 + 2], [0.0, 2.53])  # FL knee opens positively
    np.testing.assert_allclose(model.jnt_range[1 + 5], [-2.53, 0.0])  # FR knee negatively


def test_nominal_pose_puts_each_foot_where_the_thesis_code_model_does():
    """Their nominal pose: each foot ~0.252 m below and ~0.102 m outboard of its hip (docs/thesis-code.md §1)."""
    model = mjcf.load_model()
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    mujoco.mj_forward(model, data)
    for i, leg in enumerate(robot.HB40.legs):
        foot = data.geom(f"{leg}_foot").xpos - data.body(f"{leg}_hip").xpos
        assert abs(-foot[2] - 0.252) < 0.002, f"{leg} foot {-foot[2]:.4f} m below its hip"
        assert abs(robot.HB40.left_sign[i] * foot[1] - 0.102) < 0.002, f"{leg} foot {foot[1]:.4f} m to the side"
    # The thesis's [0.1, 0.6, -1.2] in their convention: left legs (0.1/-0.1, -0.6, 1.2), right legs mirrored.
    np.testing.assert_allclose(robot.nominal_pose().reshape(4, 3),
                               [[0.1, -0.6, 1.2], [-0.1, 0.6, -1.2], [-0.1, -0.6, 1.2], [0.1, 0.6, -1.2]], atol=1e-7)


def test_the_spec_is_the_one_place_of_the_robots_figures():
    """A changed figure in the spec reaches the model and the kinematics built from it."""
    longer = dataclasses.replace(robot.HB40, calf_length=0.25)
    model = mjcf.load_model(longer)
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model, longer)
    mujoco.mj_forward(model, data)
    drop = data.body("FL_hip").xpos[2] - data.geom("FL_foot").xpos[2]
    assert drop > 0.27, "the calf length did not reach the model"


