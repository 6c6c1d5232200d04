"""Publishing results into a reference folder: complete runs only, each with its best seed's policy."""

import numpy as np
import pytest

from mjx_badger.cli import main as cli
from mjx_badger.outputs import publish
from mjx_badger.records import policy, results

META = {"config": {"agent": {"hidden": [4], "actor_batch_renorm": False}}, "observation_size": 3,
        "action_size": 2, "observation_layout": [["all", 3, 1.0]], "control_hz": 40.0}


def _run(folder, name, returns, complete=True):
    """A results file of three seeds whose final evaluation returns are `returns`, with a 3-seed policy."""
    seeds = [0, 1, 2]
    # Seed k's output layer is k + 1 times 0.1, so which seed a policy holds shows in what it does.
    params = {"Dense_0": {"kernel": np.ones((3, 3, 4)), "bias": np.zeros((3, 4))},
              "Dense_1": {"kernel": np.stack([np.full((4, 2), 0.1 * (k + 1)) for k in seeds]),
                          "bias": np.zeros((3, 2))}}
    path = folder / "forward" / f"{name}.json"
    saved = policy.save(path.with_suffix(".policy.npz"), params, {}, dict(META, seeds=seeds))
    document = {"schema": results.SCHEMA, "config": {}, "seeds": seeds, "complete": complete, "steps": [1000],
                "sim_minutes": [0.3], "metrics": {"eval/return": [list(returns)]}, "policy": saved.name,
                "agents": path.with_suffix(".agents").name, "wall_clock": {"started": "2026-12-02T00:00:00+00:00"}}
    results.write(path, document)
    return path


def test_a_complete_run_is_copied_with_its_best_seeds_policy_only(tmp_path):
    source, target = tmp_path / "results", tmp_path / "reference"
    _run(source, "best-is-1", [3.0, 9.0, 5.0])
    _run(source, "unfinished", [1.0, 2.0, 3.0], complete=False)
    done = dict(publish.publish(source, target))
    copied = target / "forward" / "best-is-1.json"
    assert done[copied] == "published with seed 1's policy"
    assert done[target / "forward" / "unfinished.json"] == "skipped: incomplete"
    assert not (target / "forward" / "unfinished.json").exists()
    document = results.read(copied)
    assert document["published_policy_seeds"] == [1] and "agents" not in document
    kept = policy.load(copied.parent / document["policy"])
    assert kept.seed == 1 and kept.meta["seeds"] == [1]
    # relu(2) x 4 x 0.2: seed 1's weights, not seed 0's 0.1.
    np.testing.assert_allclose(kept([1.0, 2.0, -1.0]), np.tanh([1.6, 1.6]), atol=1e-6)
    assert dict(publish.publish(source, target))[copied] == "unchanged"


def test_publish_refuses_a_missing_source_and_its_own_folder(tmp_path, capsys):
    for argv, says in ((["publish", "--results-dir", str(tmp_path / "none")], "no results folder"),
                       (["publish", "--results-dir", str(tmp_path), "--to", str(tmp_path)], "where the results already are")):
        (tmp_path / "quick" / "thesis-code").mkdir(parents=True, exist_ok=True)
        with pytest.raises(SystemExit) as done:
            cli.parse(argv)
        assert done.value.code == 2 and says in capsys.readouterr().err


def test_a_committed_result_gets_its_policy_from_an_identical_rerun_only(tmp_path):
    reference = _run(tmp_path / "reference", "run", [3.0, 9.0, 5.0])
    document = results.read(reference)
    reference.with_suffix(".policy.npz").unlink()
    del document["policy"]
    results.write(reference, document)  # a committed result without its policy
    rerun = _run(tmp_path / "rerun", "run", [3.0, 9.0, 5.0])
    assert publish.attach_policy(reference, rerun) == 1
    attached = results.read(reference)
    assert attached["published_policy_seeds"] == [1] and attached["metrics"] == document["metrics"]
    assert policy.load(reference.parent / attached["policy"]).meta["seeds"] == [1]
    other = _run(tmp_path / "other", "run", [3.0, 9.0, 5.5])
    with pytest.raises(ValueError, match="its metrics is not the same"):
        publish.attach_policy(reference, other)
