"""`estimator collect|fit|figures`: every argument checked, in one line, before anything compiles or is written."""

import pytest

from mjx_badger.cli import estimator
from mjx_badger.cli.main import main
from mjx_badger.core.paths import REFERENCE

WALKER = REFERENCE / "quick" / "thesis-code" / "forward" / "jt-oef_crossq_forward.json"  # with its best seed's policy


@pytest.mark.parametrize("argv, says", [
    (["collect", "--steps", "1000", "--envs", "4"], "--steps 1000: at least 500 per env (2000 for --envs 4)"),
    (["collect", "--task", "dance"], "unknown task 'dance'; choose from forward"),
    (["collect", "--action-noise", "3"], "--action-noise 3.0: choose within 0..2"),
    (["collect", "--results", str(REFERENCE / "quick" / "thesis-code" / "forward" / "jt-nf_crossq_forward.json")],
     "has no saved policy beside it"),
    (["fit", "--epochs", "0"], "--epochs must be a positive number"),
    (["fit", "--dataset", "none.npz"], "no dataset 'none.npz' (write one with `estimator collect`)"),
    (["figures", "--seconds", "0"], "--seconds must be a positive number"),
])
def test_bad_estimator_arguments_are_refused_in_one_line(capsys, tmp_path, argv, says):
    with pytest.raises(SystemExit) as exit_info:
        main(["estimator", *argv, *(["--out", str(tmp_path / "x.npz")] if argv[0] != "figures" else [])])
    err = capsys.readouterr().err
    assert exit_info.value.code == 2 and says in err and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


def test_the_default_policy_is_the_committed_omnidirectional_one_and_fit_names_its_file():
    assert estimator.OMNI_POLICY.is_file() and estimator.OMNI_POLICY.with_suffix(".policy.npz").is_file()
    assert estimator.Fit(inputs="rich").destination.name == "rich.estimator.npz"
    assert estimator.Collect(results=WALKER).results == WALKER
