"""A run's results documents: a diverging seed is recorded and announced once."""

import numpy as np

from mjx_badger.learning import documents


def test_the_runner_records_and_announces_a_seed_that_diverges(tmp_path, capsys):
    document = {"seeds": [3, 4], "diverged_at_step": [None, None]}
    documents.note_divergence(document, np.array([-1, 2000]), tmp_path / "run.json")
    documents.note_divergence(document, np.array([-1, 2000]), tmp_path / "run.json")
    assert document["diverged_at_step"] == [None, 2000]
    assert capsys.readouterr().err.count("run.json: seed 4 went non-finite by step 2000") == 1
