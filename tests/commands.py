"""Running a command as a test does: `refused` checks the one-line refusal every bad input gets."""

import pytest

from mjx_badger.cli.main import main


def refused(capsys, argv, *says) -> str:
    """`argv` exits 2 with one line on stderr, 'error: ...', holding every one of `says`; returns the line."""
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1, f"not one line: {err!r}"
    for words in says:
        assert words in err, err
    return err
