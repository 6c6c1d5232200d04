"""The operator's terminal line: steps, velocities, falls, timing, the learner's rate and the time left."""

from mjx_badger.realtime import report, view
from tests.realtime.test_report import CONFIG, _progress


class _Learner:
    updates = 0


def test_the_line_shows_the_runs_figures_and_notes_go_to_stderr(capsys):
    timing = report.timing_log(fifo=False, locked=False, page_faults=0)
    timing.update(periods=[0.025] * 10 + [0.035], late=1)
    learner = _Learner()
    line = view.View(True, CONFIG, _progress(), learner, timing)
    learner.updates = 500
    line.last = -1e9  # show now, whatever the interval
    line.show()
    err = capsys.readouterr().err
    assert "step 300/400 | v est +" in err and "falls 1 |" in err and "late 1" in err and "upd/s" in err
    assert "period p50 25.0 p99 34.0 ms" in err and "ETA" in err
    view.say(False, "hidden")
    view.say(True, "shown")
    assert capsys.readouterr().err == "shown\n"


def test_a_disabled_view_prints_nothing(capsys):
    line = view.View(False, CONFIG, _progress(), _Learner(), report.timing_log(False, False, 0))
    line.show()
    line.note("a note")
    line.close()
    assert capsys.readouterr().err == ""
