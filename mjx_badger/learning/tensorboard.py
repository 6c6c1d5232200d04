"""TensorBoard event files beside a run's results: `<name>.tb/seed_<k>/`, one scalar per metric and seed.

Each seed is its own TensorBoard run, so `tensorboard --logdir results` overlays seeds and
configurations. The step of a scalar is the environment step at the end of its chunk; a
metric with no value yet (a learner metric during warm-up) is left out. The writer is
tensorboardX, which brax already installs.
"""

import shutil
from pathlib import Path

import numpy as np


def folder(out_path: Path) -> Path:
    """The event files' folder of the results file `out_path`."""
    return Path(out_path).with_suffix(".tb")


class Writer:
    """Event files for one run; begun afresh, with the rows a resumed run already has written again."""

    def __init__(self, out_path: Path, seeds: list, document: dict):
        from tensorboardX import SummaryWriter

        shutil.rmtree(folder(out_path), ignore_errors=True)  # a resumed run's rows past its checkpoint go
        self.writers = [SummaryWriter(logdir=str(folder(out_path) / f"seed_{seed}"), flush_secs=3600)
                        for seed in seeds]
        for row, step in enumerate(document["steps"]):
            self.write({name: values[row] for name, values in document["metrics"].items()}, step)

    def write(self, metrics: dict, step: int) -> None:
        """One chunk's metrics (name -> one value per seed, or one vector per seed) at env step `step`."""
        for name, values in metrics.items():
            values = np.asarray(values, dtype=float)
            for writer, value in zip(self.writers, values):
                for index, scalar in np.ndenumerate(value):
                    if np.isfinite(scalar):
                        tag = name if value.ndim == 0 else f"{name}/{'_'.join(map(str, index))}"
                        writer.add_scalar(tag, scalar, step)
        for writer in self.writers:
            writer.flush()

    def close(self) -> None:
        for writer in self.writers:
            writer.close()
