"""The thesis's claims as predicates: each verdict follows from the numbers in the results files."""


from mjx_badger.records import results
from mjx_badger.scoring import claims, scoreboard
from tests.documents import simulation_document, write_run


def test_forward_claims_follow_the_numbers(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    for name, falls in (("jt-nf", 13.0), ("jt-oef", 7.0), ("jt-lpf", 6.0)):
        write_run(folder, "forward", name, simulation_document(0.55, falls))
    for name, falls in (("cpg-d", 0.0), ("cpg-vf", 0.0), ("cpg-rt", 2.0)):
        write_run(folder, "forward", name, simulation_document(0.5, falls, would_falls=4.0))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["jt-falls"].holds is True and "JT-NF 13.0" in board["jt-falls"].ours
    # CPG-RT fell twice: the claim fails, and the would-be falls are shown beside.
    assert board["cpg-never-falls"].holds is False and "would have fired: 4.0" in board["cpg-never-falls"].ours
    assert board["jt-convergence"].holds is True  # every approach reaches 0.45 m/s at chunk 5 (5k steps)
    assert board["crossq-first"].holds is None and "no results" in board["crossq-first"].ours
    text = scoreboard.scoreboard_text(list(board.values()), "quick", "thesis-code")
    assert "thesis-code protocol, quick profile: 3 of 20 hold" in text
    table = scoreboard.scoreboard_markdown({"thesis-code": list(board.values())})
    assert "| **claims that hold** | | 3 of 20 |" in table and "| not run yet |" in table


def test_a_partly_run_experiment_says_how_far_it_is_and_keeps_no_verdict(tmp_path):
    folder = tmp_path / "full" / "thesis-code"
    write_run(folder, "algo-comparison", "crossq", simulation_document(0.55, 2.0))
    board = {v.claim.id: v for v in claims.score(tmp_path / "full", "thesis-code")}
    verdict = board["crossq-first"]
    assert verdict.holds is None and verdict.ours.startswith("partly run: 1 of 4 runs of algo-comparison in")
    table = scoreboard.scoreboard_markdown({"full": list(board.values())})
    assert f"| {verdict.ours} |" in table and "| not run yet |" in table  # forward has no run at all
    assert "  -  " in scoreboard.scoreboard_text([verdict], "full", "thesis-code")
    # A board decided before keeps its verdict over a partly run cell, as over an empty one.
    old = {"full": [dict(v.as_dict(), ours="CrossQ 2.0 min", holds=True) if v is verdict else v.as_dict()
                    for v in board.values()]}
    boards, kept = scoreboard.keep_decided({"full": list(board.values())}, old)
    assert "| **holds**: CrossQ 2.0 min |" in scoreboard.scoreboard_markdown(boards) and len(kept) == 1


def test_jt_falls_fail_when_far_from_the_thesis(tmp_path):
    folder = tmp_path / "quick" / "thesis-text"
    for name, falls in (("jt-nf", 58.0), ("jt-oef", 23.0), ("jt-lpf", 5.0)):
        write_run(folder, "forward", name, simulation_document(0.5, falls))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-text")}
    assert board["jt-falls"].holds is False  # 58 is more than 3x the thesis's 13


def test_algorithm_claims_compare_falls_over_the_same_simulated_time(tmp_path):
    """DroQ's run is a quarter as long: CrossQ's falls are read where DroQ's run ends."""
    folder = tmp_path / "quick" / "thesis-code"
    write_run(folder, "algo-comparison", "crossq", simulation_document(0.55, 40.0))  # 10 falls by 2 min, 40 by 8
    write_run(folder, "algo-comparison", "droq", simulation_document(0.55, 20.0, chunks=5))  # 20 falls by 2 min, no target
    write_run(folder, "algo-comparison", "sac", simulation_document(0.3, 5.0))
    write_run(folder, "algo-comparison", "sac-utd20", simulation_document(0.55, 5.0, chunks=4))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["crossq-falls"].holds is True and "CrossQ 10.0, DroQ 20.0 in the first 2.0" in board["crossq-falls"].ours
    # CrossQ and DroQ reach 90 % of 0.5 m/s together at chunk 5 (2.0 min): CrossQ is not first.
    assert board["crossq-first"].holds is False
    assert "SAC not in 8.0" in board["crossq-first"].ours and "SAC-UTD20 not in 1.6" in board["crossq-first"].ours


def test_crossq_first_is_undecided_while_a_shorter_run_might_have_beaten_it(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    write_run(folder, "algo-comparison", "crossq", simulation_document(0.55, 4.0))  # reaches at 2.0 min
    write_run(folder, "algo-comparison", "droq", simulation_document(0.3, 4.0, chunks=4))  # stops at 1.6 min, short of it
    write_run(folder, "algo-comparison", "sac", simulation_document(0.3, 5.0))
    write_run(folder, "algo-comparison", "sac-utd20", simulation_document(0.3, 5.0, chunks=10))  # 4.0 min without reaching
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    verdict = board["crossq-first"]
    assert verdict.holds is None and "(DroQ stopped before 2.0 min)" in verdict.ours
    assert "| undecided: " in scoreboard.scoreboard_markdown({"thesis-code": list(board.values())})
    write_run(folder, "algo-comparison", "droq", simulation_document(0.3, 4.0, chunks=6))  # 2.4 min without reaching
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["crossq-first"].holds is True


def test_a_diverged_seed_is_left_out_of_the_claims_and_named(tmp_path):
    """Seed 1 of JT-NF diverged with 99 falls: the claim reads seed 0's 13 alone and says seed 1 was left out."""
    folder = tmp_path / "quick" / "thesis-code"
    diverged = simulation_document(0.55, 13.0)
    diverged["metrics"]["train/falls"] = [[f, 99.0] for f, _ in diverged["metrics"]["train/falls"]]
    diverged["diverged_at_step"] = [None, 6000]
    write_run(folder, "forward", "jt-nf", diverged)
    for name, falls in (("jt-oef", 7.0), ("jt-lpf", 6.0)):
        write_run(folder, "forward", name, simulation_document(0.55, falls))
    verdict = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}["jt-falls"]
    assert verdict.holds is True and "JT-NF 13.0" in verdict.ours
    assert "forward/jt-nf seed 1 left out: diverged at step 6000" in verdict.ours
    kept = results.healthy(diverged)
    assert kept["seeds"] == [0] and kept["metrics"]["train/falls"][-1] == [13.0]
    assert results.healthy(simulation_document(0.5, 1.0))["seeds"] == [0, 1]  # nothing diverged: unchanged




def test_maximal_velocity_is_scored_on_the_best_seed_and_on_the_seeds_mean_as_the_thesis_gives_both(tmp_path):
    """§5.1.3 gives JT-NF's best 2.2 beside its average 1.90 and the CPGs' averages: an order must hold on both."""
    folder = tmp_path / "quick" / "thesis-code"
    speeds = {"jt-nf": (1.6, 0.2), "jt-oef": (1.0, 0.9), "jt-lpf": (0.9, 0.8),  # NF's best leads, its mean trails
              "cpg-d": (0.5, 0.5), "cpg-vf": (0.7, 0.6), "cpg-rt": (0.5, 0.4)}
    for name, (best, other) in speeds.items():
        document = simulation_document(0.5, 0.0)
        document["metrics"]["eval/desired_velocity"] = [[best, other]] * len(document["steps"])
        write_run(folder, "forward-max", name, document)
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["jt-max-velocity"].holds is False and "JT-NF 1.60 / 0.90" in board["jt-max-velocity"].ours
    assert board["cpg-vf-max"].holds is True and "CPG-VF 0.70 / 0.65" in board["cpg-vf-max"].ours

