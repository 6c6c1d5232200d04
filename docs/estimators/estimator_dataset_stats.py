"""How much the trunk velocity varies in the learned estimator's data, and the MAE of predicting its mean (what a
network that learned nothing scores): the committed omnidirectional CPG-VF policy walking under random commands,
as `estimator collect` walks it.

    python docs/estimators/estimator_dataset_stats.py [--steps 128000]  -> docs/estimators/estimator_dataset_stats.json
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np

from mjx_badger.cli.estimator import OMNI_POLICY
from mjx_badger.estimation.learned import OUTPUTS
from mjx_badger.experiments.estimator_data import collect
from mjx_badger.records import results

OUT = Path(__file__).with_suffix(".json")


def stats(arrays: dict) -> dict:
    """Per output component: its standard deviation and the MAE of predicting its mean, over every step."""
    velocity = arrays["velocity"]
    out = {}
    for index, name in enumerate(OUTPUTS):
        v = velocity[..., index].astype(np.float64)
        out[name] = {"std": float(v.std()), "mae_of_the_mean": float(np.abs(v - v.mean()).mean())}
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=results.what(__doc__))
    parser.add_argument("--steps", type=int, default=128_000, help="control steps over every env")
    parser.add_argument("--envs", type=int, default=128)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    start = time.perf_counter()
    meta, arrays = collect(OMNI_POLICY, args.steps // args.envs, args.envs, seed=args.seed)
    document = {"what": results.what(__doc__), "date": results.now()[:10], "git_commit": results.git_commit(),
                "dataset": meta, "collect_s": round(time.perf_counter() - start, 1), "velocity": stats(arrays)}
    args.out.write_text(json.dumps(document, indent=1) + "\n")
    print(json.dumps(document["velocity"], indent=1))


if __name__ == "__main__":
    main()
