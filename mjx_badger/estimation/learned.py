"""§2.6.3: a learned trunk-velocity estimator as it runs: what it reads, its networks, and its file.

Per velocity component (vx, vy) one MLP of dense layers with ReLU (the thesis's 256, 256, 1) over
standardised inputs, fitted by `estimator fit` (fit.py). Two inputs:

- `thesis`: joint angles and IMU acceleration, one control step (the thesis's features);
- `rich`: the fix the thesis names: also joint velocities, motor torques, foot contacts
  (estimated from the motor torques, estimators.estimated_contacts), the gyro and
  gravity in the trunk frame, over a window of the last `history` control steps.

Steps of a window from before the episode began are zeros (after standardising), at fit time as
when it runs. A fitted file runs as pure JAX (`estimator()`) or with NumPy alone (`numpy()`).
"""

import dataclasses
import json
import zipfile
from pathlib import Path

import jax.numpy as jnp
import numpy as np

from mjx_badger.estimation.reading import Estimator, Reading
from mjx_badger.robot.description import HB40, RobotSpec

ESTIMATOR_FORMAT = "mjx_badger.velocity-estimator/1"
OUTPUTS = ("vx", "vy")
"""The velocity components predicted, one network each (trunk frame)."""


FIELDS = (("joint_angle", 12), ("joint_velocity", 12), ("joint_torque", 12), ("contacts", 4), ("acceleration", 3),
          ("angular_velocity", 3), ("gravity", 3))
"""Every reading field a dataset stores per control step, with its size."""


@dataclasses.dataclass(frozen=True)
class Inputs:
    """What a learned estimator reads: reading fields over a window of control steps."""

    name: str
    fields: tuple
    history: int = 1


INPUTS = {
    "thesis": Inputs("thesis", ("joint_angle", "acceleration")),
    "rich": Inputs("rich", tuple(name for name, _ in FIELDS), history=8),
}


def frame(reading: Reading, fields: tuple, xp=jnp):
    """One control step's input vector: the reading's `fields` in order (gravity: the world's down in the trunk frame)."""
    values = {"gravity": -reading.rotation[2]}
    return xp.concatenate([values[name] if name in values else xp.ravel(getattr(reading, name)) for name in fields])


def field_sizes(fields: tuple) -> int:
    sizes = dict(FIELDS)
    return sum(sizes[name] for name in fields)


def mlp(layers: list, x, xp=jnp):
    """Dense layers with ReLU between them; `layers` [(kernel, bias), ...]."""
    for i, (kernel, bias) in enumerate(layers):
        x = x @ kernel + bias
        if i < len(layers) - 1:
            x = xp.maximum(x, 0.0)
    return x


class LearnedEstimator:
    """A fitted estimator: `estimator()` for JAX programs, `numpy()` to run it with NumPy alone."""

    def __init__(self, path: Path, spec: RobotSpec = HB40):
        try:
            with np.load(path) as data:
                self.meta = json.loads(str(data["meta"]))
                self.arrays = {k: data[k] for k in data.files if k != "meta"}
        except (OSError, KeyError, ValueError, EOFError, zipfile.BadZipFile) as error:
            raise ValueError(f"{path}: not a fitted velocity estimator ({error or type(error).__name__})") from None
        if self.meta.get("format") != ESTIMATOR_FORMAT:
            raise ValueError(f"{path}: not a {ESTIMATOR_FORMAT} file")
        if self.meta["robot"] != spec.name:
            raise ValueError(f"{path}: an estimator of robot {self.meta['robot']!r}, not {spec.name!r}")
        self.inputs = Inputs(self.meta["inputs"]["name"], tuple(self.meta["inputs"]["fields"]),
                             self.meta["inputs"]["history"])
        self.size = field_sizes(self.inputs.fields)

    def _layers(self, output: str, xp):
        return [(xp.asarray(self.arrays[f"{output}/dense_{i}/kernel"]), xp.asarray(self.arrays[f"{output}/dense_{i}/bias"]))
                for i in range(self.meta["layers"])]

    def _predict(self, history, xp):
        x = history.reshape(-1)
        components = [mlp(self._layers(name, xp), x, xp)[0] for name in self.meta["outputs"]]
        return xp.concatenate([xp.stack(components), xp.zeros(3 - len(components))])

    def _push(self, history, reading, xp):
        row = (frame(reading, self.inputs.fields, xp) - xp.asarray(self.arrays["mean"])) / xp.asarray(self.arrays["std"])
        return xp.concatenate([row[None], history[:-1]])

    def estimator(self) -> Estimator:
        """The estimator as pure JAX functions: state the standardised window, newest step first."""

        def init():
            return jnp.zeros((self.inputs.history, self.size), jnp.float32)

        def step(history, reading: Reading, dt):
            history = self._push(history, reading, jnp)
            return history, self._predict(history, jnp)

        return Estimator(init, step)

    def numpy(self):
        """`update(reading) -> (3,) velocity` with NumPy alone, and `reset()`; the same numbers as `estimator()`."""
        outer = self

        class Runner:
            def __init__(self):
                self.reset()

            def reset(self):
                self.history = np.zeros((outer.inputs.history, outer.size), np.float32)

            def update(self, reading) -> np.ndarray:
                self.history = outer._push(self.history, reading, np)
                return outer._predict(self.history, np)

        return Runner()


def load(path: Path, spec: RobotSpec = HB40) -> LearnedEstimator:
    """The fitted estimator at `path`; ValueError for another file or robot."""
    return LearnedEstimator(path, spec)
