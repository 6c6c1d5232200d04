"""The scoreboards: text and Markdown of the verdicts, and a written board that keeps what it had decided."""

import json

from mjx_badger.scoring import claims, scoreboard
from mjx_badger.scoring.verdicts import Verdict
from tests.documents import simulation_document, write_run


def test_the_scoreboard_takes_new_verdicts_and_keeps_only_the_missing_ones():
    old = {"thesis-code": [Verdict(c, "old", True).as_dict() for c in claims.CLAIMS]}
    new = [Verdict(c, "new", False) if i == 0 else Verdict(c, "no results yet", None)
           for i, c in enumerate(claims.CLAIMS)]
    boards, kept = scoreboard.keep_decided({"thesis-code": new}, old)
    text = scoreboard.scoreboard_markdown(boards)
    assert "fails: new" in text and text.count("**holds**: old") == len(claims.CLAIMS) - 1
    assert len(kept) == len(claims.CLAIMS) - 1 and kept[0].endswith("[thesis-code]")
    assert f"| **claims that hold** | | {len(claims.CLAIMS) - 1} of {len(claims.CLAIMS)} |" in text
    undecided = {"thesis-code": [Verdict(c, "undecided: too short", None).as_dict() for c in claims.CLAIMS]}
    assert len(scoreboard.keep_decided({"thesis-code": new}, undecided)[1]) == len(claims.CLAIMS) - 1  # decided too


def test_the_text_board_marks_each_verdict_and_counts_what_holds():
    board = [Verdict(claims.CLAIMS[0], "CrossQ 2.0", True), Verdict(claims.CLAIMS[1], "no results (x)", None),
             Verdict(claims.CLAIMS[2], "JT-NF 8k", False), Verdict(claims.CLAIMS[3], "one run short", None)]
    text = scoreboard.scoreboard_text(board, "quick", "thesis-code")
    assert text.startswith("thesis claims, thesis-code protocol, quick profile: 1 of 4 hold (2 checked)")
    assert "  HOLDS  CrossQ reaches" in text and "    -    CrossQ falls less" in text
    assert "  FAILS  JT-NF" in text and "  ?    JT forward falls" in text


def test_a_written_board_keeps_its_verdicts_beside_it_and_a_rewrite_from_fewer_results_keeps_them(tmp_path, capsys):
    results_dir = tmp_path / "quick"
    write_run(results_dir / "thesis-code", "algo-comparison", "crossq", simulation_document(0.55, 2.0))
    for name in ("sac", "sac-utd20", "droq"):
        write_run(results_dir / "thesis-code", "algo-comparison", name, simulation_document(0.2, 20.0))
    path = tmp_path / "figures" / "claims_quick.md"
    scoreboard.write_markdown(path, {"thesis-code": claims.score(results_dir, "thesis-code")}, results_dir)
    saved = json.loads(path.with_suffix(".json").read_text())["thesis-code"]
    assert [v["holds"] for v in saved if v["id"] == "crossq-first"] == [True]
    for name in ("sac", "sac-utd20", "droq"):  # a later, partial results folder
        (results_dir / "thesis-code" / "algo-comparison" / f"jt-nf_{name}_forward.json").unlink()
    scoreboard.write_markdown(path, {"thesis-code": claims.score(results_dir, "thesis-code")}, results_dir)
    assert "| **holds**: SAC not in" in path.read_text() and "verdicts kept from the scoreboard there before" in \
        path.read_text()
    assert "kept CrossQ reaches 0.5 m/s first (Fig 5.2, §5.1.1) [thesis-code]" in capsys.readouterr().out
