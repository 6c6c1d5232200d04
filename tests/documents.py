"""Results documents made by hand for the tests of what reads them (claims, tables, wall time), and their files."""

import numpy as np

from mjx_badger.experiments.registry import EXPERIMENTS, result_name
from mjx_badger.records import results

CHUNKS = 20


def simulation_document(velocity, falls, would_falls=0.0, chunks=CHUNKS):
    """A results document of 2 seeds whose velocity ramps to `velocity` by chunk 5 and whose falls end at `falls`."""
    ramp = np.minimum(np.arange(1, chunks + 1) / 5, 1.0) * velocity
    return {"schema": results.SCHEMA, "config": {"warmup_steps": 1000}, "seeds": [0, 1], "complete": True,
            "steps": [1000 * (i + 1) for i in range(chunks)], "sim_minutes": [0.4 * (i + 1) for i in range(chunks)],
            "metrics": {"train/forward_velocity": [[v, v] for v in ramp],
                        "train/falls": [[falls * (i + 1) / chunks] * 2 for i in range(chunks)],
                        "train/would_falls": [[would_falls] * 2 for _ in range(chunks)]}}


def real_world_document(velocity, falls, estimated=0.05, yaw_rate=0.0, conditions="office"):
    """A real-world results document of 2 seeds: final evaluation at `velocity` (true) and `estimated`, `falls`
    safety stops in all, heading turning at `yaw_rate` rad/s over a 10 s evaluation at 40 Hz."""
    per_chunk = lambda value: [[value, value] for _ in range(CHUNKS)]
    return {"schema": results.SCHEMA, "seeds": [0, 1], "complete": True,
            "config": {"eval_steps": 400, "env": {"control_hz": 40.0}, "conditions": conditions,
                       "condition_changes": [], "protocol": "thesis-code"},
            "steps": [1000 * (i + 1) for i in range(CHUNKS)], "sim_minutes": [0.4167 * (i + 1) for i in range(CHUNKS)],
            "metrics": {"eval/desired_velocity": per_chunk(velocity), "eval/estimated_desired_velocity": per_chunk(estimated),
                        "eval/yaw_rate": per_chunk(yaw_rate),
                        "train/falls_total": [[falls * (i + 1) / CHUNKS] * 2 for i in range(CHUNKS)]}}


def write_run(folder, experiment, label, document) -> None:
    """`document` as the results file of the run called `label` in `experiment`, under `folder`/<experiment>/."""
    run = next(r for r in EXPERIMENTS[experiment].runs if EXPERIMENTS[experiment].label(r) == label)
    results.write(folder / experiment / result_name(run), document)


def evaluation_schema(metrics: dict) -> tuple:
    """(run names, metric names) of a document's evaluation, checking every run has every metric over all runs."""
    per_run = [name.split("/")[1:] for name in metrics if name.startswith("eval/") and name.count("/") == 2]
    runs, names = {run for run, _ in per_run}, {name for _, name in per_run}
    assert {name.split("/")[1] for name in metrics if name.startswith("eval/") and name.count("/") == 1} == names
    assert len(per_run) == len(runs) * len(names)
    return runs, names
