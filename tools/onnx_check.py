"""The committed saved policies as ONNX: for each, the largest |ONNX - JAX| action difference over 1,000
observations (onnxruntime on the CPU against the JAX agent with the saved actor), and whether the robot's onboard
runner takes it.

    python -m tools.onnx_check [--json tools/results/onnx_check.json]

Every committed thesis-text policy (figures/data/quick/thesis-text) is exported with `onnx_export.export`; one the
onboard runner refuses (cpg-rt's two PD controllers per joint) has its actor written as ONNX alone and checked the
same way. The committed thesis-code policies (figures/data/full/thesis-code, most with the released CrossQ's batch
renormalisation in the actor) are checked as a second group.
"""

import argparse
import datetime
import json
import tempfile
from pathlib import Path

from mjx_badger.core import safe_io
from mjx_badger.outputs import onnx_export
from mjx_badger.records import results

ROOT = Path(__file__).resolve().parents[1]
GROUPS = {"thesis_text_quick": ROOT / "figures" / "data" / "quick" / "thesis-text",
          "thesis_code_full": ROOT / "figures" / "data" / "full" / "thesis-code"}
N = 1000
NOTE = ("An actor that renormalises its input and every hidden layer (the released CrossQ's, thesis-code) is checked "
        "on draws from its own running statistics, the inputs it was trained on; where a running variance is near 0 "
        "its layers amplify the float32 rounding of the matrix products (XLA's against onnxruntime's order of "
        "summation) about 30-fold each, so such actors differ by more than the plain ones.")


def check_one(results_file: Path, folder: Path) -> dict:
    """The policy's seed, its max |ONNX - JAX| and 'exported', or the onboard runner's refusal."""
    out = folder / f"{results_file.parent.name}_{results_file.stem}.onnx"
    try:
        onnx_export.export(results_file, None, out)
        onboard = "exported"
    except ValueError as refusal:
        onboard = f"refused: {refusal}"
        _, _, actor = onnx_export.saved(results_file, None)
        safe_io.write_bytes(out, onnx_export.actor_model(actor).SerializeToString())
    _, _, actor = onnx_export.saved(results_file, None)
    return {"seed": actor.seed, "renormalised_input": actor.layers[0]["op"] == "renorm",
            "max_difference": onnx_export.check(results_file, None, out, N), "onboard": onboard}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", type=Path, help="write the measurements here")
    args = parser.parse_args()
    document = {"what": results.what(__doc__),
                "command": "python -m tools.onnx_check --json tools/results/onnx_check.json",
                "date": datetime.date.today().isoformat(), "machine": "2 CPU cores, no GPU",
                "git_commit": results.git_commit(), "observations": N, "limit": onnx_export.MAX_DIFFERENCE}
    with tempfile.TemporaryDirectory() as folder:
        for group, root in GROUPS.items():
            found = {}
            for results_file in sorted(root.glob("*/*.json")):
                if (results_file.parent / results_file.name.replace(".json", ".policy.npz")).is_file():
                    found[str(results_file.relative_to(root))] = row = check_one(results_file, Path(folder))
                    print(f"{group} {results_file.relative_to(root)}: {row['max_difference']:.2e} {row['onboard']}")
            document[group] = found
            document[f"{group}_worst"] = max(row["max_difference"] for row in found.values())
            document[f"{group}_worst_onboard"] = max(
                (row["max_difference"] for row in found.values() if row["onboard"] == "exported"), default=None)
            document[f"{group}_over_limit"] = sorted(k for k, row in found.items()
                                                     if row["max_difference"] > onnx_export.MAX_DIFFERENCE)
    document["note"] = NOTE
    if args.json:
        safe_io.write_text(args.json, json.dumps(document, indent=1) + "\n")


if __name__ == "__main__":
    main()
