"""`evaluate` and `render`: a missing, damaged or diverged saved policy is refused in one line."""

import json
import shutil
from pathlib import Path

import pytest

from mjx_badger.cli import saved_runs
from tests.commands import refused

REPO = Path(__file__).resolve().parents[2]


REFERENCE = REPO / "figures" / "data" / "quick" / "thesis-code"
WALKER = REFERENCE / "forward" / "jt-oef_crossq_forward.json"  # a committed result with its policy


@pytest.mark.parametrize("command", ["evaluate", "render"])
def test_evaluate_and_render_name_a_missing_saved_policy(capsys, command, tmp_path):
    committed = REFERENCE / "forward" / "cpg-vf_crossq_forward.json"  # "policy" named, the file not committed
    assert "policy" in json.loads(committed.read_text())
    out = ["--out", str(tmp_path / "x.gif")] if command == "render" else []
    refused(capsys, [command, str(committed), *out], "cpg-vf_crossq_forward.policy.npz", "is missing")


def test_evaluate_refuses_a_diverged_seed_named_or_by_default(capsys, tmp_path):
    """The saved policy's only seed (1) diverged: evaluate refuses it whether --seed names it or is left out."""
    for name in ("jt-oef_crossq_forward.json", "jt-oef_crossq_forward.policy.npz"):
        shutil.copy(REFERENCE / "forward" / name, tmp_path / name)
    edited = tmp_path / "jt-oef_crossq_forward.json"
    document = json.loads(edited.read_text())
    document["diverged_at_step"] = [None, 6000, None]
    edited.write_text(json.dumps(document))
    for seed in ([], ["--seed", "1"]):
        refused(capsys, ["evaluate", str(edited), *seed], "seed 1 of jt-oef_crossq_forward.json diverged at step 6000")


@pytest.fixture
def damaged_forward(tmp_path):
    """The committed quick forward results copied, one of them cut short and one policy cut short."""
    folder = tmp_path / "results" / "quick" / "thesis-code" / "forward"
    shutil.copytree(REFERENCE / "forward", folder)
    cut = folder / "jt-nf_crossq_forward.json"
    cut.write_text(cut.read_text()[:5000])
    policy = folder / "cpg-d_crossq_forward.policy.npz"
    policy.write_bytes(policy.read_bytes()[:3000])
    return folder


@pytest.mark.parametrize("command", ["evaluate", "render"])
def test_evaluate_and_render_refuse_a_damaged_results_file_or_policy(capsys, damaged_forward, tmp_path, command):
    out = ["--out", str(tmp_path / "x.gif")] if command == "render" else []
    refused(capsys, [command, str(damaged_forward / "jt-nf_crossq_forward.json"), *out], "cannot be read")
    refused(capsys, [command, str(damaged_forward / "cpg-d_crossq_forward.json"), *out], "damaged policy file")
    edited = damaged_forward / "jt-oef_crossq_forward.json"
    document = json.loads(edited.read_text())
    document["metrics"]["train/falls"] = document["metrics"]["train/falls"][:-1]
    edited.write_text(json.dumps(document))
    refused(capsys, [command, str(edited), *out], "damaged results file", "train/falls")
    assert not (tmp_path / "x.gif").exists()


def test_a_video_is_a_gif_and_an_evaluation_takes_an_hour_at_most(tmp_path):
    with pytest.raises(ValueError, match=r"--out x.mp4: videos are written as .gif"):
        saved_runs.Render(results=WALKER, out=tmp_path / "x.mp4").check()
    assert saved_runs.Evaluate.max_seconds == 3600.0 and saved_runs.Render.max_seconds == 60.0
    with pytest.raises(ValueError, match=r"--seconds must be a finite number in \(0, 60\]"):
        saved_runs.Render(results=WALKER, seconds=61.0, out=tmp_path / "x.gif").check()
