"""A claim checked: our numbers in words and a verdict, or, while its runs are missing, how far they are."""

from mjx_badger.scoring.verdicts import Claim, Results, Verdict
from tests.documents import simulation_document, write_run


def _crossq_speed(results: Results):
    speed = results.summary("algo-comparison", "crossq")["final_velocity"]
    return f"CrossQ {speed:.2f} m/s", speed >= 0.5


CLAIM = Claim("toy", "CrossQ walks 0.5 m/s", "Fig 5.2", "~0.6 m/s", "final velocity >= 0.5 m/s", _crossq_speed)


def test_a_claim_reads_its_runs_and_gives_words_and_a_verdict(tmp_path):
    write_run(tmp_path, "algo-comparison", "crossq", simulation_document(0.55, 2.0))
    verdict = CLAIM.check(Results(tmp_path))
    assert verdict == Verdict(CLAIM, "CrossQ 0.55 m/s", True)
    assert verdict.as_dict() == {"id": "toy", "finding": "CrossQ walks 0.5 m/s", "thesis_figure": "Fig 5.2",
                                 "thesis": "~0.6 m/s", "rule": "final velocity >= 0.5 m/s", "ours": "CrossQ 0.55 m/s",
                                 "holds": True}


def test_a_claim_without_its_runs_says_what_is_missing_or_how_far_the_experiment_is(tmp_path):
    assert CLAIM.check(Results(tmp_path)).ours == "no results (algo-comparison/crossq)"
    write_run(tmp_path, "algo-comparison", "droq", simulation_document(0.3, 9.0))
    verdict = CLAIM.check(Results(tmp_path))
    assert verdict.holds is None and verdict.ours == "partly run: 1 of 4 runs of algo-comparison in, waits for " \
                                                     "algo-comparison/crossq"


def test_a_seed_left_out_for_diverging_is_named_beside_the_numbers(tmp_path):
    document = dict(simulation_document(0.55, 2.0), diverged_at_step=[None, 7000])
    write_run(tmp_path, "algo-comparison", "crossq", document)
    assert CLAIM.check(Results(tmp_path)).ours == "CrossQ 0.55 m/s (algo-comparison/crossq seed 1 left out: " \
                                                  "diverged at step 7000)"


def _omni(eval_steps: int, holds_command=None) -> dict:
    """An omni-random run evaluated for `eval_steps` at 40 Hz against 10 s episodes (thesis-code)."""
    document = simulation_document(0.1, 0.0)
    document["config"].update(task="omni-random", eval_steps=eval_steps,
                              env={"control_hz": 40.0, "protocol": {"episode_seconds": 10.0}})
    if holds_command is not None:
        document["evaluation_holds_command"] = holds_command
    return document


def _omni_speed(results: Results):
    speed = results.summary("omni-random", "cpg-d")["final_velocity"]
    return f"CPG-D {speed:.2f} m/s", speed < 0.15


def test_an_omni_run_evaluated_past_an_episode_before_the_fix_leaves_its_claim_undecided(tmp_path):
    claim = Claim("omni", "CPG-D stands", "Fig 5.9", "-", "< 0.15 m/s", _omni_speed)
    write_run(tmp_path, "omni-random", "cpg-d", _omni(800))  # 20 s of evaluation over 10 s episodes
    verdict = claim.check(Results(tmp_path))
    assert verdict.holds is None and "undecided: omni-random/cpg-d evaluated past an episode's end" in verdict.ours
    write_run(tmp_path, "omni-random", "cpg-d", _omni(800, holds_command=True))  # run since the fix
    assert claim.check(Results(tmp_path)).holds is True
    write_run(tmp_path, "omni-random", "cpg-d", _omni(400))  # within one episode: never crossed
    assert claim.check(Results(tmp_path)).holds is True
