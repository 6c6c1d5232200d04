"""Where a clone keeps what the package reads from beside itself."""

from mjx_badger.core import paths


def test_the_repository_is_the_clone_and_holds_the_committed_results():
    assert (paths.REPOSITORY / "pyproject.toml").is_file() and (paths.REPOSITORY / "mjx_badger").is_dir()
    assert paths.REFERENCE == paths.REPOSITORY / "figures" / "data"
    assert (paths.REFERENCE / "quick" / "thesis-code" / "forward").is_dir()
