"""The thesis's claims as predicates: each verdict follows from the numbers in the results files."""

import numpy as np

from mjx_badger import claims, results
from mjx_badger.experiments import EXPERIMENTS, result_name


def _document(velocity, falls, would_falls=0.0, chunks=20):
    """A results document of 2 seeds whose velocity ramps to `velocity` by chunk 5 and whose falls end at `falls`."""
    ramp = np.minimum(np.arange(1, chunks + 1) / 5, 1.0) * velocity
    return {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1], "complete": True,
            "steps": [1000 * (i + 1) for i in range(chunks)], "sim_minutes": [0.4 * (i + 1) for i in range(chunks)],
            "metrics": {"train/forward_velocity": [[v, v] for v in ramp],
                        "train/falls": [[falls * (i + 1) / chunks] * 2 for i in range(chunks)],
                        "train/would_falls": [[would_falls] * 2 for _ in range(chunks)]}}


def _write(folder, experiment, name, document):
    run = next(r for r in EXPERIMENTS[experiment].runs if EXPERIMENTS[experiment].label(r) == name)
    results.write(folder / experiment / result_name(run), document)


def test_forward_claims_follow_the_numbers(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    for name, falls in (("jt-nf", 13.0), ("jt-oef", 7.0), ("jt-lpf", 6.0)):
        _write(folder, "forward", name, _document(0.55, falls))
    for name, falls in (("cpg-d", 0.0), ("cpg-vf", 0.0), ("cpg-rt", 2.0)):
        _write(folder, "forward", name, _document(0.5, falls, would_falls=4.0))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["jt-falls"].holds is True and "JT-NF 13.0" in board["jt-falls"].ours
    # CPG-RT fell twice: the claim fails, and the would-be falls are shown beside.
    assert board["cpg-never-falls"].holds is False and "would have fired: 4.0" in board["cpg-never-falls"].ours
    assert board["jt-convergence"].holds is True  # every approach reaches 0.45 m/s at chunk 5 (5k steps)
    assert board["crossq-first"].holds is None and "no results" in board["crossq-first"].ours
    text = claims.scoreboard_text(list(board.values()), "quick", "thesis-code")
    assert "thesis-code protocol, quick profile: 3 of 15 hold" in text
    table = claims.scoreboard_markdown({"thesis-code": list(board.values())})
    assert "| **claims that hold** | | 3 of 15 |" in table and "| not run yet |" in table


def test_a_partly_run_experiment_says_how_far_it_is_and_keeps_no_verdict(tmp_path):
    folder = tmp_path / "full" / "thesis-code"
    _write(folder, "algo-comparison", "crossq", _document(0.55, 2.0))
    board = {v.claim.id: v for v in claims.score(tmp_path / "full", "thesis-code")}
    verdict = board["crossq-first"]
    assert verdict.holds is None and verdict.ours.startswith("partly run: 1 of 4 runs of algo-comparison in")
    table = claims.scoreboard_markdown({"full": list(board.values())})
    assert f"| {verdict.ours} |" in table and "| not run yet |" in table  # forward has no run at all
    assert "  -  " in claims.scoreboard_text([verdict], "full", "thesis-code")
    # A board decided before keeps its verdict over a partly run cell, as over an empty one.
    old = table.replace(f"| {verdict.ours} |", "| **holds**: CrossQ 2.0 min |")
    text, kept = claims.keep_decided(table, old)
    assert "| **holds**: CrossQ 2.0 min |" in text and len(kept) == 1


def test_jt_falls_fail_when_far_from_the_thesis(tmp_path):
    folder = tmp_path / "quick" / "thesis-text"
    for name, falls in (("jt-nf", 58.0), ("jt-oef", 23.0), ("jt-lpf", 5.0)):
        _write(folder, "forward", name, _document(0.5, falls))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-text")}
    assert board["jt-falls"].holds is False  # 58 is more than 3x the thesis's 13


def test_algorithm_claims_compare_falls_over_the_same_simulated_time(tmp_path):
    """DroQ's run is a quarter as long: CrossQ's falls are read where DroQ's run ends."""
    folder = tmp_path / "quick" / "thesis-code"
    _write(folder, "algo-comparison", "crossq", _document(0.55, 40.0))  # 10 falls by 2 min, 40 by 8
    _write(folder, "algo-comparison", "droq", _document(0.55, 20.0, chunks=5))  # 20 falls by 2 min, no target
    _write(folder, "algo-comparison", "sac", _document(0.3, 5.0))
    _write(folder, "algo-comparison", "sac-utd20", _document(0.55, 5.0, chunks=4))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["crossq-falls"].holds is True and "CrossQ 10.0, DroQ 20.0 in the first 2.0" in board["crossq-falls"].ours
    # CrossQ and DroQ reach 90 % of 0.5 m/s together at chunk 5 (2.0 min): CrossQ is not first.
    assert board["crossq-first"].holds is False
    assert "SAC not in 8.0" in board["crossq-first"].ours and "SAC-UTD20 not in 1.6" in board["crossq-first"].ours


def test_crossq_first_is_undecided_while_a_shorter_run_might_have_beaten_it(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    _write(folder, "algo-comparison", "crossq", _document(0.55, 4.0))  # reaches at 2.0 min
    _write(folder, "algo-comparison", "droq", _document(0.3, 4.0, chunks=4))  # stops at 1.6 min, short of it
    _write(folder, "algo-comparison", "sac", _document(0.3, 5.0))
    _write(folder, "algo-comparison", "sac-utd20", _document(0.3, 5.0, chunks=10))  # 4.0 min without reaching
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    verdict = board["crossq-first"]
    assert verdict.holds is None and "(DroQ stopped before 2.0 min)" in verdict.ours
    assert "| undecided: " in claims.scoreboard_markdown({"thesis-code": list(board.values())})
    _write(folder, "algo-comparison", "droq", _document(0.3, 4.0, chunks=6))  # 2.4 min without reaching
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["crossq-first"].holds is True


def test_a_diverged_seed_is_left_out_of_the_claims_and_named(tmp_path):
    """Seed 1 of JT-NF diverged with 99 falls: the claim reads seed 0's 13 alone and says seed 1 was left out."""
    folder = tmp_path / "quick" / "thesis-code"
    diverged = _document(0.55, 13.0)
    diverged["metrics"]["train/falls"] = [[f, 99.0] for f, _ in diverged["metrics"]["train/falls"]]
    diverged["diverged_at_step"] = [None, 6000]
    _write(folder, "forward", "jt-nf", diverged)
    for name, falls in (("jt-oef", 7.0), ("jt-lpf", 6.0)):
        _write(folder, "forward", name, _document(0.55, falls))
    verdict = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}["jt-falls"]
    assert verdict.holds is True and "JT-NF 13.0" in verdict.ours
    assert "forward/jt-nf seed 1 left out: diverged at step 6000" in verdict.ours
    kept = results.healthy(diverged)
    assert kept["seeds"] == [0] and kept["metrics"]["train/falls"][-1] == [13.0]
    assert results.healthy(_document(0.5, 1.0))["seeds"] == [0, 1]  # nothing diverged: unchanged


def test_wall_time_passes_over_the_checkpoints_of_a_running_run(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    document = dict(_document(0.5, 1.0), wall_clock={"compile_s": 60.0, "run_s": 3540.0})
    _write(folder, "forward", "jt-nf", document)
    stamp = folder / "forward" / "jt-oef_crossq_forward.ckpt" / "run.json"
    stamp.parent.mkdir(parents=True)
    stamp.write_text('{"config": {}, "seeds": [0]}')
    assert results.wall_time_words(folder) == "1 run in 1.00 h (compile 1.0 min of it)"
    # The simulation claims' wall time leaves the real-world runs out, and theirs the simulation's.
    real = dict(_document(0.5, 1.0), wall_clock={"compile_s": 0.0, "run_s": 1800.0})
    results.write(folder / "real-office" / "jt-oef_crossq_forward.json", real)
    assert results.wall_time_words(folder) == "2 runs in 1.50 h (compile 1.0 min of it)"
    assert results.wall_time_words(folder, ("forward", "omni-pdec")) == "1 run in 1.00 h (compile 1.0 min of it)"
    assert results.wall_time_words(folder, ("real-office",)) == "1 run in 0.50 h (compile 0.0 min of it)"
    # A run reproduce copied for a second experiment costs nothing of its own.
    results.write(folder / "algo-comparison" / "jt-nf_crossq_forward.json", document)
    assert results.wall_time_words(folder, ("forward", "algo-comparison")) == (
        "1 run in 1.00 h (compile 1.0 min of it; 1 more a copy of one of them)")


def test_the_budgets_board_puts_each_profile_beside_the_thesis(tmp_path, capsys):
    from mjx_badger.cli import main

    # JT falls of the thesis's size at full, far from it at quick: the verdict differs by budget.
    for profile, nf_falls in (("quick", 58.0), ("full", 13.0)):
        for name, falls in (("jt-nf", nf_falls), ("jt-oef", 7.0), ("jt-lpf", 6.0)):
            _write(tmp_path / profile / "thesis-code", "forward", name, _document(0.55, falls))
    out, plot = tmp_path / "budgets.md", tmp_path / "budgets.png"
    assert main(["claims", "--results-dir", str(tmp_path), "--budgets", "quick", "full", "--markdown", str(out),
                 "--plot", str(plot)]) == 0
    text = capsys.readouterr().out
    assert f"wrote {plot}" in text and plot.read_bytes().startswith(b"\x89PNG")
    assert "thesis-code protocol: 1 of 15 at quick, 2 of 15 at full hold" in text
    assert "quick   FAILS  JT-NF 58.0" in text and "full    HOLDS  JT-NF 13.0" in text
    table = out.read_text()
    assert "| thesis finding | thesis | ours at quick | ours at full |" in table
    row = next(line for line in table.splitlines() if line.startswith("| JT forward falls"))
    assert row.endswith("| fails: JT-NF 58.0, JT-OEF 7.0, JT-LPF 6.0 | **holds**: JT-NF 13.0, JT-OEF 7.0, JT-LPF 6.0 |")


def test_the_budgets_plot_needs_two_budgets_and_a_file_of_its_own(tmp_path, capsys):
    import pytest

    from mjx_badger.cli import main

    plot = tmp_path / "budgets.png"
    for argv, says in ((["--plot", str(plot)], "give --budgets with two profiles"),
                       (["--budgets", "full", "--plot", str(plot)], "give --budgets with two profiles"),
                       (["--budgets", "quick", "full", "--markdown", str(plot), "--plot", str(plot)],
                        "--markdown and --plot name the same file")):
        with pytest.raises(SystemExit) as exit_info:
            main(["claims", *argv])
        err = capsys.readouterr().err
        assert exit_info.value.code == 2 and says in err and err.count("\n") == 1, err
    assert not plot.exists()
