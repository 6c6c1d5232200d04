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

MATMUL_PRECISION = "highest"
"""float32 matrix products in full float32 on every device: Ampere and later GPUs otherwise use TF32 (10-bit
mantissas), which changes a run's numbers from one GPU to another (mujoco_playground#86). A CPU computes float32
products in full either way. JAX_DEFAULT_MATMUL_PRECISION overrides it (docs/cluster.md: what it costs)."""


def _pin_matmul_precision() -> None:
    """Before JAX's first computation: through its environment variable, or its config where JAX is loaded."""
    import sys

    chosen = os.environ.setdefault("JAX_DEFAULT_MATMUL_PRECISION", MATMUL_PRECISION)
    if sys.modules.get("jax") is not None:  # loaded already (None: a test has blocked it)
        sys.modules["jax"].config.update("jax_default_matmul_precision", chosen)


_pin_matmul_precision()

GYM_ENV_ID = "mjx_badger/HB40-v0"


def _register_gymnasium() -> None:
    """`gymnasium.make(GYM_ENV_ID, ...)` builds gym_env.HB40GymEnv; the module loads only then."""
    import gymnasium

    if GYM_ENV_ID not in gymnasium.registry:
        gymnasium.register(id=GYM_ENV_ID, entry_point="mjx_badger.sim.gym_env:HB40GymEnv")


_register_gymnasium()
