"""Videos of a policy: native MuJoCo rendered offscreen (EGL or OSMesa) by `mujoco.Renderer`, as a GIF.

The camera follows the trunk from its left, a little ahead and above, over a checkered floor
(a render-only twin of the run's model: same bodies, a floor texture and a sky added, so the
physics the policy runs on is the run's own). MP4 needs an ffmpeg
binary, which this suite does not install; a GIF needs only Pillow (matplotlib's).
"""

import io
import re
from pathlib import Path
from typing import Callable

import mujoco
import numpy as np

from mjx_badger.core import safe_io
from mjx_badger.robot import mjcf, terrain
from mjx_badger.sim import native

SCENERY = """<asset>
    <texture name="grid" type="2d" builtin="checker" rgb1="0.78 0.8 0.82" rgb2="0.62 0.65 0.68" width="256" height="256"/>
    <material name="grid" texture="grid" texuniform="true" texrepeat="4 4" reflectance="0"/>
    <texture type="skybox" builtin="gradient" rgb1="0.55 0.7 0.88" rgb2="0.95 0.96 1" width="256" height="256"/>
  </asset>
  <worldbody>"""
"""A checkered floor (so speed can be read off the video) and a sky, for videos only."""


GL_HELP = ("offscreen rendering needs an OpenGL backend without a display: install EGL (apt install libegl1) "
           "or OSMesa (apt install libosmesa6) and set MUJOCO_GL=egl or MUJOCO_GL=osmesa")


def check_gl(model: mujoco.MjModel) -> None:
    """Raise RuntimeError with the install line if no offscreen OpenGL context can be made here."""
    try:
        mujoco.Renderer(model, 8, 8).close()
    except Exception as error:  # mujoco.FatalError, or a backend library that is missing
        raise RuntimeError(f"{GL_HELP} ({error})") from None


def scenery_model(env) -> mujoco.MjModel:
    """The env's model with SCENERY: the same bodies and joints, so the env's MjData renders in it."""
    xml = mjcf.mjcf(env.spec, env.action_space.split_pd, env.ground).replace("<worldbody>", SCENERY, 1)
    line = next((l for l in xml.splitlines() if '<geom name="floor"' in l), None)
    assert line is not None, "the floor geom's declaration changed; update render.scenery_model"
    if env.ground.terrain == "flat":  # the stones keep their own colour
        xml = xml.replace(line, re.sub(r'\s*rgba="[^"]*"', "", line).replace("/>", ' material="grid"/>'), 1)
    return terrain.set_heights(mujoco.MjModel.from_xml_string(xml), env.ground)


def follower(env, size: tuple = (480, 360)) -> Callable:
    """`frame(data)`: an RGB image (height, width, 3) of the env's MjData, the camera following the trunk."""
    width, height = size
    renderer = mujoco.Renderer(scenery_model(env), height, width)
    camera = mujoco.MjvCamera()
    camera.distance, camera.elevation, camera.azimuth = 1.3, -15.0, 110.0
    trunk = env.mj_model.body("trunk").id

    def frame(data) -> np.ndarray:
        camera.lookat[:] = data.xpos[trunk]
        renderer.update_scene(data, camera)
        return renderer.render().copy()

    return frame


def record(env, act: Callable, command, seconds: float, out: Path, fps: float = 25.0,
           size: tuple = (480, 360)) -> dict:
    """Run `act` on native MuJoCo for `seconds` and write the frames to `out` (.gif); returns the evaluation."""
    out = Path(out)
    if out.suffix.lower() != ".gif":
        raise ValueError(f"{out.name}: videos are written as .gif (an .mp4 needs ffmpeg, which is not installed)")
    frame = follower(env, size)
    every = max(1, int(round(env.control_hz / fps)))
    frames, count = [], [0]

    def draw(model, data):
        count[0] += 1
        if count[0] % every == 0:
            frames.append(frame(data))

    report = native.run_native(env, act, command, seconds, on_step=draw)
    from PIL import Image

    # One 64-colour palette for every frame: about half the size of per-frame palettes, and no flicker.
    palette = Image.fromarray(np.asarray(frames[len(frames) // 2])).quantize(colors=64)
    images = [Image.fromarray(np.asarray(picture)).quantize(palette=palette, dither=Image.Dither.NONE)
              for picture in frames]
    gif = io.BytesIO()
    images[0].save(gif, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(round(1000 * every / env.control_hz)), optimize=True, loop=0)
    safe_io.write_bytes(out, gif.getvalue())
    return dict(report, frames=len(frames), video=str(out))
