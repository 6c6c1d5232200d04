"""The estimate-gain figure: the band of gains at which most findings hold, and the drawing of the study's rows."""

from mjx_badger.outputs import estimate_gain


def _row(value, slope, holding, walk=None):
    findings = {claim: {"holds": claim in holding, "ours": ""} for claim in ("a", "b", "c")}
    return {"value": value, "gain": None if slope is None else {"slope": slope, "correlation": 0.9, "walk_ratio": walk},
            "findings": findings, "runs": {"real-office": {"jt-oef": {"velocity": 0.2 + slope if slope else 0.2}}}}


def test_the_band_spans_the_gains_at_which_the_most_findings_hold():
    rows = [_row(0.0, 0.02, {"a"}), _row(0.25, 0.2, {"a", "b"}), _row(0.5, 0.45, {"a", "c"}), _row(1.0, 0.8, set()),
            _row(0.75, None, {"a", "b", "c"})]  # no moments: not placed, whatever it scored
    assert estimate_gain.band(rows) == (0.2, 0.45)
    assert estimate_gain.band([_row(0.0, 0.02, set())]) is None


def test_the_band_is_also_given_in_the_walks_own_ratio_where_measured():
    rows = [_row(0.0, 0.6, {"a"}, walk=0.02), _row(0.25, 0.7, {"a", "b"}, walk=0.1), _row(0.5, 0.8, {"a", "b"}),
            _row(1.0, 0.9, {"a", "b"}, walk=0.4)]  # 0.5: nobody walked, no ratio
    assert estimate_gain.band(rows, "walk_ratio") == (0.1, 0.4)
    assert estimate_gain.walk_label(rows[2]) == "walk: none" and estimate_gain.walk_label(rows[3]) == "walk 0.40"
    assert estimate_gain.band_line(rows) == "most findings hold at slope 0.70-0.90, walk ratio 0.10-0.40"
    assert estimate_gain.band_line([_row(0.0, 0.6, set())]) == "no value makes any finding hold: no band"


def test_the_figure_draws_the_placed_rows(tmp_path):
    rows = [_row(0.0, 0.02, {"a"}), _row(0.5, 0.45, {"a", "c"})]
    assert estimate_gain.figure(rows, tmp_path / "gain.png", "test").exists()
