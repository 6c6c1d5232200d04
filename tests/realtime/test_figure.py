"""The figure of an on-robot run, drawn from its results document and trace alone."""

from mjx_badger.realtime import figure, report
from tests.realtime.test_report import CONFIG, _progress


def test_a_run_is_drawn_from_its_document_and_trace(tmp_path):
    timing = report.timing_log(fifo=True, locked=True, page_faults=0)
    timing.update(periods=[0.025] * 100, work=[0.004] * 100, wake=[0.0001] * 100, at_step=list(range(100)),
                  at_time=[0.0] * 100, ticks=100)
    progress = _progress()
    document = report.document(CONFIG, progress, timing, updates=400, compile_s=3.0, started="now", complete=True,
                               evaluation={})
    out = figure.draw(document, progress.trace[:progress.step], tmp_path / "run.png")
    assert out == tmp_path / "run.png" and out.read_bytes().startswith(b"\x89PNG") and out.stat().st_size > 20_000
    assert [p.name for p in tmp_path.iterdir()] == ["run.png"]  # written whole, no temporary file left
