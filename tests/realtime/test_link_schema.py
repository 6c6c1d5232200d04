"""The link's messages: JSON of one version, every field checked, NaN and pickles refused."""

import pickle

import numpy as np
import pytest

from mjx_badger.realtime import link_schema
from mjx_badger.realtime.link_schema import Refused


def test_a_message_round_trips_with_its_arrays_as_lists():
    message = {"v": 1, "id": 7, "type": "command", "targets": np.arange(12) / 10, "kp": np.float32(60), "kd": 3}
    decoded = link_schema.decode(link_schema.encode(message))
    assert decoded["targets"] == [i / 10 for i in range(12)] and decoded["kp"] == 60.0
    np.testing.assert_array_equal(link_schema.vector(decoded, "targets", 12), np.arange(12) / 10)


@pytest.mark.parametrize("raw, why", [
    (b"\x80\x04", "not JSON"),
    (pickle.dumps({"v": 1}), "not JSON"),
    (b"[1, 2]", "a JSON object"),
    (b'{"v": 2, "id": 1, "type": "read"}', "version 2"),
    (b'{"v": 1, "type": "read"}', "integer id"),
    (b'{"v": 1, "id": true, "type": "read"}', "integer id"),
    (b'{"v": 1, "id": 1, "targets": [NaN]}', "not JSON"),
    (b"x" * (link_schema.MAX_BYTES + 1), "at most"),
    (b'{"v": 1, "id": 1, "x": ' + b"[" * 2000 + b"]" * 2000 + b"}", "not JSON"),  # once a RecursionError
])
def test_what_breaks_the_schema_is_refused_by_name(raw, why):
    with pytest.raises(Refused, match=why):
        link_schema.decode(raw)


def test_fields_are_checked_for_shape_type_finiteness_and_range():
    low, high = np.full(12, -1.0), np.full(12, 1.0)
    with pytest.raises(Refused, match="list of 12"):
        link_schema.vector({"targets": [0.0] * 11}, "targets", 12)
    with pytest.raises(Refused, match="list of 12"):
        link_schema.vector({"targets": [0.0] * 11 + [True]}, "targets", 12)
    with pytest.raises(Refused, match="finite"):
        link_schema.vector({"targets": [0.0] * 11 + [1e400]}, "targets", 12)
    with pytest.raises(Refused, match=r"targets\[3\] = 2.000 is outside its range \[-1.000, 1.000\]"):
        link_schema.vector({"targets": [0.0] * 3 + [2.0] + [0.0] * 8}, "targets", 12, low, high)
    with pytest.raises(Refused, match=r"kp must be a number in \[0.0, 200.0\]"):
        link_schema.number({"kp": 201}, "kp", 0.0, 200.0)
    # An integer JSON reads and no float holds (once an OverflowError that stopped the robot server).
    with pytest.raises(Refused, match="list of 12"):
        link_schema.vector({"targets": [0.0] * 11 + [10**400]}, "targets", 12)
    with pytest.raises(Refused, match="kp must be a number"):
        link_schema.number(link_schema.decode(b'{"v": 1, "id": 1, "kp": 1' + b"0" * 400 + b"}"), "kp", 0.0, 200.0)
    with pytest.raises(TypeError, match="not part of the link's schema"):
        link_schema.encode({"x": object()})
