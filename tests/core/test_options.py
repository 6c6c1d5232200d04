"""NAME=VALUE options: the value is read as a Python literal, a bare word stays a string, a list becomes a tuple."""

import pytest

from mjx_badger.core import options


@pytest.mark.parametrize("text, pair", [("cutoff_hz=2.0", ("cutoff_hz", 2.0)), ("action_delay=False", ("action_delay", False)),
                                        ("lowpass=butterworth", ("lowpass", "butterworth")),
                                        ("hidden=[64, 64]", ("hidden", (64, 64))), ("name=", ("name", ""))])
def test_a_pair_is_read_as_a_literal_or_a_word(text, pair):
    assert options.name_value(text) == pair


@pytest.mark.parametrize("text", ["cutoff_hz", "=2.0", ""])
def test_a_pair_without_a_name_or_an_equals_sign_is_refused(text):
    with pytest.raises(ValueError, match="expected NAME=VALUE"):
        options.name_value(text)
