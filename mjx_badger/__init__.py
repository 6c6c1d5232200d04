"""mjx_badger: MuJoCo-MJX benchmark suite for quadruped locomotion learning on the HB40."""

import os


def _choose_offscreen_gl() -> None:
    """MUJOCO_GL for videos without a display, set before MuJoCo is first imported (it reads it then).

    The user's EGL or OSMesa if its library exists here, EGL by default; otherwise rendering is
    disabled, because MuJoCo's import itself fails on a backend whose library is missing, and
    `render` then says what to install.
    """
    import ctypes.util

    libraries = {"egl": "EGL", "osmesa": "OSMesa"}
    chosen = os.environ.get("MUJOCO_GL", "egl").lower()
    if chosen in libraries and ctypes.util.find_library(libraries[chosen]) is None:
        chosen = "disable"
    os.environ["MUJOCO_GL"] = chosen


_choose_offscreen_gl()

GYM_ENV_ID = "mjx_badger/HB40-v0"


def _register_gymnasium() -> None:
    """`gymnasium.make(GYM_ENV_ID, ...)` builds gym_env.HB40GymEnv; the module loads only then."""
    import gymnasium

    if GYM_ENV_ID not in gymnasium.registry:
        gymnasium.register(id=GYM_ENV_ID, entry_point="mjx_badger.sim.gym_env:HB40GymEnv")


_register_gymnasium()
