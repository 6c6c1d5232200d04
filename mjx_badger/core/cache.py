"""The persistent XLA compilation cache: a rerun of a configuration loads its programs instead of compiling."""

import os
from pathlib import Path


def enable_compilation_cache(path: str | os.PathLike | None = None) -> Path:
    """Keep XLA executables on disk so a rerun of the same configuration skips compilation."""
    import jax

    cache = Path(path or os.environ.get("MJX_BADGER_CACHE", Path.home() / ".cache" / "mjx_badger" / "jax"))
    cache.mkdir(parents=True, exist_ok=True)
    jax.config.update("jax_compilation_cache_dir", str(cache))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 1.0)
    return cache
