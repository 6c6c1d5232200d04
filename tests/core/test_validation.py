"""Bounds on what a command takes: each check refuses in one line naming the field and its valid range."""

import math

import pytest

from mjx_badger.core import validation


def test_an_integer_is_refused_outside_its_range_or_of_another_kind():
    assert validation.integer("--seeds", 3, 1, 10) == 3
    for bad in (0, 11, 2.0, True, "3"):
        with pytest.raises(ValueError, match=r"--seeds must be an integer in 1\.\.10"):
            validation.integer("--seeds", bad, 1, 10)
    with pytest.raises(ValueError, match=r"int32 step counters"):
        validation.integer("total_steps", 2**31, 1, validation.INT32_MAX, "int32 step counters")


def test_a_number_must_be_finite_and_inside_its_closed_or_half_open_interval():
    assert validation.number("x", 0.5, 0.0, 1.0) == 0.5
    assert validation.number("x", 1.0, 0.0, 1.0, low_open=True) == 1.0
    with pytest.raises(ValueError, match=r"x must be a finite number in \(0, 1\], not 0\.0"):
        validation.number("x", 0.0, 0.0, 1.0, low_open=True)
    for bad in (math.nan, math.inf, "1", False):
        with pytest.raises(ValueError, match="finite number"):
            validation.number("x", bad)


def test_a_changed_field_takes_only_the_kind_of_its_default():
    validation.like("protocol field", "action_delay", False, True)
    validation.like("protocol field", "episode_seconds", 20, 10.0)  # a float field takes any finite number
    validation.like("algorithm parameter", "hidden", (128, 128), (256, 256))
    for value, default, says in ((1, True, "True or False"), (0, 256, r"integer in 1\.\."), ((), (1,), "non-empty"),
                                 (3, "butterworth", "a word like 'butterworth'")):
        with pytest.raises(ValueError, match=says):
            validation.like("f", "name", value, default)
    # A field None under one protocol and a number under the other takes either kind.
    validation.like_any("protocol field", "jt_control_hz", 50.0, [None, 50.0])
    with pytest.raises(ValueError, match="finite number"):
        validation.like_any("protocol field", "jt_control_hz", "fast", [None, 50.0])


def test_paths_are_checked_without_creating_anything(tmp_path):
    validation.writable_dir(tmp_path / "new" / "deeper", "output folder")  # creatable
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match="is a file, not a folder"):
        validation.writable_dir(tmp_path / "file", "output folder")
    with pytest.raises(ValueError, match=r"is not writable: .* is a file"):
        validation.writable_dir(tmp_path / "file" / "below", "output folder")
    with pytest.raises(ValueError, match="is a folder, not a file"):
        validation.writable_file(tmp_path, "--json")
    assert validation.nearest_existing(tmp_path / "a" / "b") == tmp_path
