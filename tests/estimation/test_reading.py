"""What every estimator reads: the fields a learned estimator stores are the reading's own (gravity derived)."""

import numpy as np

from mjx_badger.estimation.learned import FIELDS, frame
from mjx_badger.estimation.reading import Estimator, Reading


def test_a_learned_estimators_fields_are_the_readings_and_gravity_comes_from_its_rotation():
    assert {name for name, _ in FIELDS} - set(Reading._fields) == {"gravity"}
    reading = Reading(np.zeros(12), np.zeros(12), np.array([0.0, 0.0, 9.81]), np.zeros(3), np.eye(3), np.ones(4),
                      np.zeros(12))
    np.testing.assert_array_equal(frame(reading, ("gravity", "contacts"), np), [0.0, 0.0, -1.0, 1.0, 1.0, 1.0, 1.0])
    assert Estimator._fields == ("init", "step")
