"""One-factor swaps: each sets real protocol fields to the other protocol's values, or one on-robot condition to
another, beside a shared baseline."""

import dataclasses
import json

import pytest

from mjx_badger.cli.main import main
from mjx_badger.learning.config import TrainConfig
from mjx_badger.protocol import protocols
from mjx_badger.records import results
from mjx_badger.scoring import attribution, claims, real_world


def written(config: TrainConfig) -> dict:
    """A config as a results file holds it (JSON: lists for tuples)."""
    return json.loads(json.dumps(results.config_dict(config)))


def test_every_swap_changes_fields_to_the_other_protocols_values_and_names_real_claims():
    real = {claim.id for claim in real_world.CLAIMS}
    for swap in attribution.SWAPS:
        assert swap.changes or swap.robot != "hb40" or swap.condition_changes, swap.name
        base = protocols.PROTOCOLS[swap.base]
        for field, value in swap.changes:
            assert getattr(base, field) != value, (swap.name, field)
        conditions = TrainConfig(conditions=swap.conditions).conditions_spec
        for field, value in swap.condition_changes:  # a condition swap sets a field to another value
            assert conditions.replace(**{field: value}) != conditions, (swap.name, field)
        assert set(swap.claims) <= set(claims.CLAIMS_BY_ID) | real, swap.name


def test_planned_runs_share_baselines_and_are_small(tmp_path):
    planned = list(attribution.planned(tmp_path))
    paths = [path for *_, path in planned]
    assert len(paths) == len(set(paths))
    baselines = [config for _, _, config, path in planned if any(p.startswith("baseline") for p in path.parts)]
    assert baselines and all(config.protocol_changes == () and config.robot == "hb40" and config.condition_changes == ()
                             for config in baselines)
    assert all(config.total_steps == 10_000 for *_, config, _ in planned)
    swapped = [config for _, _, config, path in planned if not any(p.startswith("baseline") for p in path.parts)]
    assert all(config.protocol_changes or config.robot != "hb40" or config.condition_changes for config in swapped)
    for config in swapped:
        config.validate()  # the swapped protocol is a valid one


def test_attribute_refuses_unknown_swaps(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["attribute", "--only", "everything"])
    assert exit_info.value.code == 2 and "termination rule" in capsys.readouterr().err


def test_the_table_reads_evaluation_measures_as_final_seed_means(tmp_path):

    swap = attribution.SWAPS_BY_NAME["curriculum rules"]
    run = swap.runs()[0]
    for where, maes in ((None, [0.4, 0.2]), (swap, [0.3, 0.1])):
        path = attribution.folder(tmp_path, where, swap.base) / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        document = {"schema": results.SCHEMA, "steps": [1000, 2000], "complete": True,
                    "metrics": {"eval/desired_mae": [[0.9, 0.9], maes]}}
        path.write_text(json.dumps(document))
    row = [line for line in attribution.table(tmp_path).splitlines() if line.startswith("| curriculum rules")]
    assert row and "| 0.30 m/s desired MAE | 0.20 m/s desired MAE |" in row[0]


def test_a_swap_run_alone_brings_its_baselines(tmp_path):
    swap = attribution.SWAPS_BY_NAME["JT gains and rate"]  # its baselines are shared with earlier swaps
    paths = [path for *_, path in attribution.planned(tmp_path, (swap,))]
    assert sum("baseline" in path.parts for path in paths) == len(swap.approaches) == len(paths) // 2


def test_a_swap_with_two_measures_shows_both_in_each_cell(tmp_path):

    swap = attribution.SWAPS_BY_NAME["JT gains and rate"]
    run = swap.runs()[0]
    for where, falls in ((None, [6.0, 4.0]), (swap, [1.0, 2.0])):
        path = attribution.folder(tmp_path, where, swap.base) / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        document = {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1],
                    "complete": True, "steps": [1000, 2000], "sim_minutes": [0.3, 0.7],
                    "metrics": {"train/falls": [[0, 0], falls], "train/forward_velocity": [[0.0, 0.0], [0.6, 0.6]]}}
        path.write_text(json.dumps(document))
    row = [line for line in attribution.table(tmp_path).splitlines() if line.startswith("| JT gains")]
    assert row and "| 2k steps; 5.0 falls; no gait | 2k steps; 1.5 falls; no gait |" in row[0]


def test_a_swap_still_running_is_left_out_of_the_table(tmp_path):

    swap = attribution.SWAPS_BY_NAME["action delay"]
    path = attribution.folder(tmp_path, swap, swap.base) / swap.experiment / attribution.result_name(swap.runs()[0])
    path.parent.mkdir(parents=True)
    path.write_text(json.dumps({"schema": results.SCHEMA, "complete": False, "steps": [1000], "metrics": {}}))
    assert "action delay" not in attribution.table(tmp_path)


def test_fall_counting_trains_nothing_and_reads_the_baselines_count_from_step_0(tmp_path):

    swap = attribution.SWAPS_BY_NAME["fall counting"]
    paths = [path for *_, path in attribution.planned(tmp_path, (swap,))]
    assert paths and all("baseline" in path.parts for path in paths)  # counting alone does not change a run
    run = swap.runs()[0]
    path = attribution.folder(tmp_path, None, swap.base) / swap.experiment / attribution.result_name(run)
    path.parent.mkdir(parents=True)
    document = {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1],
                "complete": True, "steps": [1000, 2000], "sim_minutes": [0.3, 0.7],
                "metrics": {"train/falls": [[0, 0], [1.0, 3.0]], "train/falls_total": [[4, 2], [5.0, 9.0]],
                            "train/forward_velocity": [[0.0, 0.0], [0.1, 0.1]]}}
    path.write_text(json.dumps(document))
    row = [line for line in attribution.table(tmp_path).splitlines() if line.startswith("| fall counting")]
    assert row and "falls_after_warmup=False" in row[0] and "| 2.0 falls | 7.0 falls |" in row[0]


def test_cpg_fall_swaps_read_the_falls_the_rule_would_have_counted(tmp_path):

    swap = attribution.SWAPS_BY_NAME["action delay, CPG falls"]
    run = swap.runs()[0]
    for where, would in ((None, [0.0, 0.0]), (swap, [3.0, 5.0])):
        path = attribution.folder(tmp_path, where, swap.base) / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        document = {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1],
                    "complete": True, "steps": [1000, 2000], "sim_minutes": [0.3, 0.7],
                    "metrics": {"train/falls": [[0, 0], [0, 0]], "train/would_falls": [[0, 0], would],
                                "train/forward_velocity": [[0.0, 0.0], [0.1, 0.1]]}}
        path.write_text(json.dumps(document))
    row = [line for line in attribution.table(tmp_path).splitlines() if line.startswith("| action delay, CPG")]
    assert row and "| 0.0 would-be falls | 4.0 would-be falls |" in row[0]


def test_a_swap_of_another_algorithm_runs_it_and_names_it_in_the_table(tmp_path):

    swap = attribution.SWAPS_BY_NAME["JT gains and rate, DroQ"]
    (run,) = swap.runs()
    assert run.algo == "droq"
    configs = [config for _, _, config, _ in attribution.planned(tmp_path, (swap,))]
    assert {config.algo for config in configs} == {"droq"} and len(configs) == 2
    for where, minutes in ((None, [0.3, 0.7]), (swap, [0.5, 1.2])):
        path = attribution.folder(tmp_path, where, swap.base) / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        document = {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1],
                    "complete": True, "steps": [1000, 2000], "sim_minutes": minutes,
                    "metrics": {"train/falls": [[0, 0], [2.0, 4.0]],
                                "train/forward_velocity": [[0.0, 0.0], [0.5, 0.5]]}}
        path.write_text(json.dumps(document))
    row = [line for line in attribution.table(tmp_path).splitlines() if line.startswith("| JT gains and rate, DroQ")]
    assert row and "| algo-comparison jt-nf droq |" in row[0]
    assert "| 0.7 simulated min; 3.0 falls | 1.2 simulated min; 3.0 falls |" in row[0]


def test_the_reality_gaps_swaps_have_their_own_table(tmp_path):

    swap = attribution.SWAPS_BY_NAME["true velocity in the loop"]
    run = swap.runs()[0]
    for where, (true, estimated) in ((None, (0.01, 0.0)), (swap, (0.28, 0.01))):
        base = attribution.folder(tmp_path, where, swap.base, swap.conditions)
        path = base / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        metrics = {"eval/desired_velocity": [[0.0, 0.0], [true, true]],
                   "eval/estimated_desired_velocity": [[0.0, 0.0], [estimated, estimated]],
                   "train/falls_total": [[1.0, 3.0], [2.0, 4.0]], "train/falls": [[1.0, 3.0], [2.0, 4.0]],
                   "train/forward_velocity": [[0.0, 0.0], [true, true]]}
        config = written(attribution.train_config(swap, run, baseline=where is None))
        path.write_text(json.dumps({"schema": results.SCHEMA, "steps": [1000, 2000], "sim_minutes": [0.4, 0.8],
                                    "seeds": [0, 1], "complete": True, "config": config, "metrics": metrics}))
    gap = attribution.table(tmp_path, conditions=True)
    assert gap.startswith("| condition set back to the simulation's | run | outdoor baseline |")
    row = [line for line in gap.splitlines() if line.startswith("| true velocity in the loop")]
    assert row and "| 0.01 m/s; 0.00 m/s estimated;" in row[0] and "| 0.28 m/s; 0.01 m/s estimated;" in row[0]
    assert "true velocity in the loop" not in attribution.table(tmp_path)  # not among the protocol's departures


def test_attribute_hands_its_missing_runs_to_the_launcher_once_each(tmp_path, monkeypatch):
    for name in ("XLA_PYTHON_CLIENT_PREALLOCATE", "MJX_BADGER_PREALLOCATE_BEFORE"):  # the waiting process's
        monkeypatch.delenv(name, raising=False)
    launched = []
    monkeypatch.setattr("mjx_badger.cli.common.Launch.run", lambda self, jobs, shared: launched.extend(jobs))
    monkeypatch.setattr(attribution, "table", lambda *args, **kwargs: "")
    swap = next(iter(attribution.SWAPS_BY_NAME))
    assert main(["attribute", "--only", swap, "--results-dir", str(tmp_path), "--runs-per-device", "2"]) == 0
    planned = [path for *_, path in attribution.planned(tmp_path, (attribution.SWAPS_BY_NAME[swap],))]
    assert [job.args[2] for job in launched] == planned and len(set(planned)) == len(planned)
    assert [job.name for job in launched] == [str(path.relative_to(tmp_path / "attribution")) for path in planned]
    # The waiting process reads each run's progress from its own results file.
    assert [job.progress.args[0] for job in launched] == planned and launched[0].progress() == ""


def test_a_swap_that_ran_beside_another_baseline_is_named_not_scored(tmp_path):
    # The baseline reran after a condition's default changed (here the robot's CPG swing); the swapped run did not.
    swap = attribution.SWAPS_BY_NAME["no incline"]
    run = swap.runs()[0]
    swapped = attribution.train_config(swap, run)
    older = dataclasses.replace(swapped, condition_changes=swapped.condition_changes + (("cpg_swing_height_m", None),
                                                                                        ("stop_on_sensed", False)))
    base = {"config": written(attribution.train_config(swap, run, baseline=True))}
    assert attribution.baseline_differs(swap, base, {"config": written(swapped)}) == []
    assert attribution.baseline_differs(swap, base, {"config": written(older)}) == [
        "cpg_swing_height_m", "stop_on_sensed"]
    for where, config in ((None, base["config"]), (swap, written(older))):
        path = attribution.folder(tmp_path, where, swap.base, swap.conditions) / swap.experiment / attribution.result_name(run)
        path.parent.mkdir(parents=True)
        path.write_text(json.dumps({"schema": results.SCHEMA, "steps": [1000], "sim_minutes": [0.4], "seeds": [0, 1],
                                    "complete": True, "config": config, "metrics": {}}))
    row = [line for line in attribution.table(tmp_path, conditions=True).splitlines() if line.startswith("| no incline")]
    assert row == ["| no incline (ground.incline_deg=0.0) | real-outdoor jt-oef | ran beside another baseline "
                   "(cpg_swing_height_m, stop_on_sensed differ): rerun it | | real-outdoor-jt, real-outdoor-cpg |"]
