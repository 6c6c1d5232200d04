"""The persistent compile cache: a folder JAX writes its executables to, created where it is asked for."""

import os

import jax

from mjx_badger.core.cache import enable_compilation_cache


def test_the_cache_goes_to_the_folder_given_or_to_mjx_badger_cache(tmp_path, monkeypatch):
    shared = os.environ["MJX_BADGER_CACHE"]  # the test run's own (conftest.py), put back below
    try:
        assert enable_compilation_cache(tmp_path / "a" / "b") == tmp_path / "a" / "b"
        assert (tmp_path / "a" / "b").is_dir() and jax.config.jax_compilation_cache_dir == str(tmp_path / "a" / "b")
        monkeypatch.setenv("MJX_BADGER_CACHE", str(tmp_path / "from-env"))
        assert enable_compilation_cache() == tmp_path / "from-env"
        assert jax.config.jax_persistent_cache_min_compile_time_secs == 1.0
    finally:
        enable_compilation_cache(shared)
    assert jax.config.jax_compilation_cache_dir == shared
