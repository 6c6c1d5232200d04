"""RealtimeConfig: bad settings are refused before anything compiles."""

import pytest

from mjx_badger.realtime.config import RealtimeConfig
from tests import conftest


def test_bad_settings_are_refused_before_anything_compiles():
    compiles = len(conftest.COMPILES)
    with pytest.raises(ValueError, match="cpg-rt-avg"):
        RealtimeConfig(approach="cpg-rt").validate()
    with pytest.raises(ValueError, match="planned contacts"):
        RealtimeConfig(approach="jt-oef", planned_contacts=True).validate()
    for algo in ("xqc", "simbav2", "bro", "fastsac"):  # the learner thread feeds the newer agents what they need
        RealtimeConfig(algo=algo).validate()
    assert not conftest.COMPILES[compiles:]  # nothing traced, compiled or loaded from the cache
