"""benchmarks/bench_gpu_check.py: what it measures, in order, and its refusal where JAX finds no GPU."""

import json
from types import SimpleNamespace

import pytest

from benchmarks import bench_gpu_check


def test_the_check_plans_three_seed_counts_the_precisions_cost_and_a_full_run_per_task():
    rows = bench_gpu_check.plan(SimpleNamespace(seeds=[10, 64, 1024], tasks=list(bench_gpu_check.TASK_RUNS)))
    names = [name for name, *_ in rows]
    assert names[:4] == ["quick jt-oef crossq x10", "quick jt-oef crossq x64", "quick jt-oef crossq x1024",
                         "quick jt-oef crossq x64 at default precision"]
    assert [(seeds, precision) for _, _, seeds, precision in rows[:4]] == [(10, "highest"), (64, "highest"),
                                                                         (1024, "highest"), (64, "default")]
    assert names[4:] == [f"full {task} x10" for task in ("forward", "forward-max", "omni-random", "omni-pdec")]
    assert {config.total_steps for _, config, *_ in rows[4:]} == {50_000}
    assert rows[0][1].approach == "jt-oef" and rows[0][1].algo == "crossq" and rows[0][1].total_steps == 20_000


def test_without_a_gpu_it_refuses_in_one_line_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "gpu_check.json"
    with pytest.raises(SystemExit) as stop:
        bench_gpu_check.main(["--out", str(out)])
    assert stop.value.code == 2 and not out.exists()
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "JAX finds no GPU here (cpu cpu)" in err and "--allow-cpu" in err


def test_a_measurement_past_the_budget_is_named_as_left_out(tmp_path, monkeypatch):
    monkeypatch.setattr(bench_gpu_check, "measure", lambda name, *args: {"name": name})
    out = tmp_path / "gpu_check.json"
    assert bench_gpu_check.main(["--allow-cpu", "--seeds", "2", "--tasks", "forward", "--budget-s", "-1",
                                 "--out", str(out)]) == 0
    document = json.loads(out.read_text())
    assert document["rows"] == [] and document["left_out"] == ["quick jt-oef crossq x2",
                                                               "quick jt-oef crossq x2 at default precision",
                                                               "full forward x10"]
    assert document["device"] == "cpu cpu" and document["hardware"]["matmul_precision"] == "highest"
