"""Videos of the experiments: the best seed among an experiment's runs with saved policies, walked and drawn."""

from mjx_badger.core.paths import REFERENCE
from mjx_badger.outputs import videos
from mjx_badger.records import analysis, results
from mjx_badger.robot import mjcf
from mjx_badger.sim.render import check_gl

FORWARD = REFERENCE / "quick" / "thesis-code" / "forward"


def test_the_best_seed_is_the_highest_final_evaluation_return_among_runs_with_a_policy(tmp_path):
    path, seed, value = videos.best(FORWARD)
    with_policy = [p for p in FORWARD.glob("*.json") if (p.parent / results.read(p).get("policy", "-")).is_file()]
    returns = {p.name: analysis.best_seed(results.read(p, leave_out_diverged=True))[1] for p in with_policy}
    assert value == max(returns.values()) and returns[path.name] == value
    assert seed in results.read(path)["published_policy_seeds"]
    assert videos.best(tmp_path) is None


def test_without_an_offscreen_gl_no_video_is_drawn_and_the_reason_is_said(tmp_path, capsys):
    try:
        check_gl(mjcf.load_model())
    except RuntimeError:
        assert videos.draw(FORWARD.parent, tmp_path, "quick", ["forward"], "thesis-code") == []
        assert capsys.readouterr().out.startswith("no videos: offscreen rendering needs an OpenGL backend")
    else:  # this machine renders: the GIFs are drawn by the runner's test (tests/learning/test_runner.py)
        assert videos.check_gl is check_gl
