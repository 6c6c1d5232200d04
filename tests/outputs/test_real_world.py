"""The on-robot loop's table beside the vmapped real-world runs."""

import json

import pytest

from mjx_badger.outputs import plots, real_world
from mjx_badger.realtime.report import SCHEMA as LOOP_SCHEMA
from mjx_badger.records import real_world as records_real_world
from tests.documents import real_world_document


def test_the_loop_table_puts_the_loop_beside_the_vmapped_runs(tmp_path):
    loop = {"schema": LOOP_SCHEMA, "steps": 20000, "complete": True, "falls": 12, "train_minutes": 8.4,
            "updates_per_learning_step": 0.97, "evaluation": {"true_velocity": 0.31, "estimated_velocity": 0.02, "seconds": 0.55,
                                                                   "fell": "pitch +0.87 rad"},
            "config": {"approach": "cpg-d", "conditions": "outdoor", "condition_changes": [], "protocol": "thesis-text"}}
    folder = tmp_path / "realtime" / "outdoor"
    folder.mkdir(parents=True)
    (folder / "cpg-d_crossq_forward.json").write_text(json.dumps(loop))
    loaded = plots.load_loop(folder)
    assert list(loaded) == ["cpg-d"]
    row = records_real_world.loop_summary(loaded["cpg-d"])
    assert row["minutes"] == pytest.approx(8.4 + 12 * 20 / 60)  # outdoor resets take 20 s each
    table = real_world.loop_table(loaded, {"cpg-d": real_world_document(0.3, 39, conditions="outdoor")})
    assert "| CPG-D | 20,000, thesis-text | 12 | fell after 0.55 s | 0.31 | 0.02 | 12 | 0.97 | 2 x 20,000, thesis-code | 39 [39-39] | 0.30 |" in table
    assert "not run" in real_world.loop_table(loaded, {})
    (folder / "jt-oef_crossq_forward.json").write_text(json.dumps({"schema": "other"}))
    with pytest.raises(ValueError, match="not a mjx_badger.realtime/1 results file"):
        plots.load_loop(folder)
    assert plots.load_loop(tmp_path / "missing") == {}
