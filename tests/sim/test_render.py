"""Videos of a policy: a render-only twin of the env's model, and a clear line where no offscreen GL exists."""

import mujoco

from mjx_badger.robot import mjcf
from mjx_badger.sim import render


def test_the_scenery_model_is_the_envs_own_with_a_checkered_floor(env):
    scenery = render.scenery_model(env)
    for size in ("nbody", "njnt", "nq", "nv", "nu", "ngeom"):
        assert getattr(scenery, size) == getattr(env.mj_model, size), size
    floor = scenery.geom("floor")
    assert scenery.material(int(floor.matid[0])).name == "grid"
    assert scenery.opt.timestep == env.mj_model.opt.timestep


def test_a_machine_without_offscreen_gl_is_told_what_to_install():
    try:
        render.check_gl(mjcf.load_model())
    except RuntimeError as error:
        assert str(error).startswith(render.GL_HELP)
    else:
        renderer = mujoco.Renderer(mjcf.load_model(), 8, 8)  # it does render here
        renderer.close()
