"""`claims`: the scoreboards by protocol and by budget, printed, written and drawn from existing results."""

from mjx_badger.pipelines import scoreboards
from tests.documents import simulation_document, write_run


def test_the_budgets_board_puts_each_profile_beside_the_thesis(tmp_path, capsys):
    # JT falls of the thesis's size at full, far from it at quick: the verdict differs by budget.
    for profile, nf_falls in (("quick", 58.0), ("full", 13.0)):
        for name, falls in (("jt-nf", nf_falls), ("jt-oef", 7.0), ("jt-lpf", 6.0)):
            write_run(tmp_path / profile / "thesis-code", "forward", name, simulation_document(0.55, falls))
    out, plot = tmp_path / "budgets.md", tmp_path / "budgets.png"
    scoreboards.by_budget(tmp_path, ("quick", "full"), None, out, None, plot)
    text = capsys.readouterr().out
    assert f"wrote {plot}" in text and plot.read_bytes().startswith(b"\x89PNG")
    assert "thesis-code protocol: 1 of 20 at quick, 2 of 20 at full hold" in text
    assert "quick   FAILS  JT-NF 58.0" in text and "full    HOLDS  JT-NF 13.0" in text
    table = out.read_text()
    assert "| thesis finding | thesis | ours at quick | ours at full |" in table
    row = next(line for line in table.splitlines() if line.startswith("| JT forward falls"))
    assert row.endswith("| fails: JT-NF 58.0, JT-OEF 7.0, JT-LPF 6.0 | **holds**: JT-NF 13.0, JT-OEF 7.0, JT-LPF 6.0 |")
