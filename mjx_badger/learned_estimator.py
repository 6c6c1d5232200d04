"""§2.6.3: a learned trunk-velocity estimator: its dataset, its fit, and the fitted file (NumPy alone runs it).

The dataset (`estimator collect`) holds what the robot's own sensors read at every control step,
noise-free as in the thesis, beside the true trunk-frame velocity, from a trained policy walking
under a task's commands in the vmapped MJX env, one trajectory per env. The fit (`estimator
fit`) is the thesis's: per velocity component (vx, vy) one MLP of dense 256, 256, 1 with ReLU,
Adam at 1e-3, mean absolute error, 100 epochs, the trajectories split 80/20 into training and
validation (held out whole, so no validation step has a neighbour in training). Two inputs:

- `thesis`: joint angles and IMU acceleration, one control step (the thesis's features);
- `rich`: the fix the thesis names: also joint velocities, motor torques, foot contacts
  (estimated from the motor torques, estimators.estimated_contacts), the gyro and
  gravity in the trunk frame, over a window of the last `history` control steps.

Inputs are standardised with the training set's mean and std; steps of a window from before the
episode began are zeros (after standardising), at fit time as when it runs.
"""

import dataclasses
import json
import zipfile
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger import estimators
from mjx_badger.robot import HB40, RobotSpec

DATASET_FORMAT = "mjx_badger.estimator-dataset/1"
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


@dataclasses.dataclass(frozen=True)
class FitConfig:
    """The thesis's fit (§2.6.3); batch size and validation split's seed are ours (the thesis gives none)."""

    hidden: tuple = (256, 256)
    learning_rate: float = 1e-3
    epochs: int = 100
    validation_share: float = 0.2
    batch_size: int = 256
    seed: int = 0


def frame(reading: estimators.Reading, fields: tuple, xp=jnp):
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


# The dataset.

def save_dataset(path: Path, arrays: dict, meta: dict) -> Path:
    """Write a dataset: per field (steps, envs, size), `velocity` (steps, envs, 3), `done` (steps, envs)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez(tmp, meta=np.array(json.dumps(dict(meta, format=DATASET_FORMAT))), **arrays)
    tmp.replace(path)
    return path


def load_dataset(path: Path, spec: RobotSpec = HB40) -> tuple[dict, dict]:
    """(meta, arrays) of a dataset; ValueError for another file, robot or field layout."""
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            arrays = {k: data[k] for k in data.files if k != "meta"}
    except (OSError, KeyError, ValueError, EOFError, zipfile.BadZipFile) as error:
        raise ValueError(f"{path}: not an estimator dataset ({error or type(error).__name__})") from None
    if meta.get("format") != DATASET_FORMAT:
        raise ValueError(f"{path}: not a {DATASET_FORMAT} file")
    if meta.get("robot") != spec.name:
        raise ValueError(f"{path}: a dataset of robot {meta.get('robot')!r}, not {spec.name!r}")
    if [list(f) for f in meta.get("fields", [])] != [list(f) for f in FIELDS]:
        raise ValueError(f"{path}: its fields {meta.get('fields')} are not this version's {[list(f) for f in FIELDS]}")
    return meta, arrays


def collect(results_path: Path, steps: int, envs: int, task: str = "omni-random", seed: int = 0,
            chunk: int = 500, progress=None, action_noise: float = 0.0) -> tuple[dict, dict]:
    """(meta, arrays) of a dataset: the best seed's saved policy of a run walking under `task`'s commands in
    `envs` MJX envs for `steps` control steps each, its sensors exact, Gaussian noise of std `action_noise` on its
    actions (as a policy still exploring in training acts). `progress(steps_done)` after each chunk."""
    from mjx_badger import analysis, policy, results, sensors
    from mjx_badger.env import HB40Env

    document = results.read(results_path)
    if "policy" not in document:
        raise ValueError(f"{results_path} has no saved policy")
    config = results.train_config(document)
    policy_seed, _ = analysis.best_seed(results.read(results_path, leave_out_diverged=True))
    saved = policy.load(Path(results_path).parent / document["policy"], policy_seed)
    actor = {k: jnp.asarray(v) for k, v in saved.arrays.items()}
    saved.arrays = actor
    env_config = dataclasses.replace(config.env_config, sensing=sensors.Sensing(sensors.EXACT))
    env = HB40Env(config.approach, task, env_config, config.robot_spec, config.approach_params)
    if env.observation_size != saved.observation_size:
        raise ValueError(f"{results_path}: its policy observes {saved.observation_size} values, the env {env.observation_size}")

    def one(state, key):
        action = saved.apply(state.obs, jnp)
        if action_noise:
            action = jnp.clip(action + action_noise * jax.random.normal(key, action.shape), -1.0, 1.0)
        state = env.step(state, action)
        reading = state.info["reading"]
        rotation = state.pipeline_state.xmat[env._trunk]
        record = {name: frame(reading, (name,)) for name, _ in FIELDS}
        record.update(velocity=rotation.T @ state.pipeline_state.qvel[:3], done=state.done > 0)
        return state, record

    run = jax.jit(jax.vmap(lambda s, k: jax.lax.scan(one, s, jax.random.split(k, chunk))))
    state = jax.jit(jax.vmap(env.reset))(jax.random.split(jax.random.PRNGKey(seed), envs))
    noise_key = jax.random.PRNGKey(seed + 1)
    parts = []
    for done in range(0, steps, chunk):
        state, record = run(state, jax.random.split(jax.random.fold_in(noise_key, done), envs))
        parts.append(jax.tree.map(lambda x: np.swapaxes(np.asarray(x), 0, 1), record))  # (chunk, envs, ...)
        if progress is not None:
            progress(min(done + chunk, steps))
    arrays = {k: np.concatenate([p[k] for p in parts])[:steps] for k in parts[0]}
    repository = Path(__file__).resolve().parent.parent
    where = Path(results_path).resolve()
    shown = where.relative_to(repository) if where.is_relative_to(repository) else where  # no machine's folders
    meta = {"robot": config.robot_spec.name, "fields": [list(f) for f in FIELDS], "policy": str(shown),
            "policy_seed": policy_seed, "approach": config.approach, "task": task,
            "protocol": env_config.protocol.name, "control_hz": env.control_hz, "steps": steps, "envs": envs,
            "seed": seed, "action_noise": action_noise, "sensors": "exact (no noise, as the thesis's dataset)"}
    return meta, arrays


def since_reset(done: np.ndarray) -> np.ndarray:
    """(steps, envs) control steps since each env's episode began. A step that ends an episode is recorded after the
    env's reset (its reading and velocity are the new episode's start), so it counts 0, as does the first step."""
    count = np.zeros_like(done, dtype=np.int32)
    for t in range(1, done.shape[0]):
        count[t] = np.where(done[t], 0, count[t - 1] + 1)
    return count


# The fit.

def _init(key, sizes: tuple):
    """He-uniform kernels, zero biases (Keras's Dense defaults are Glorot; ReLU nets train as well either way)."""
    layers = []
    for fan_in, fan_out in zip(sizes[:-1], sizes[1:]):
        key, sub = jax.random.split(key)
        limit = jnp.sqrt(6.0 / fan_in)
        layers.append((jax.random.uniform(sub, (fan_in, fan_out), minval=-limit, maxval=limit), jnp.zeros(fan_out)))
    return layers


def fit(meta: dict, arrays: dict, inputs: Inputs, config: FitConfig = FitConfig(), progress=None) -> dict:
    """Fit one MLP per output on the dataset; returns the estimator document (arrays and meta) and its curves.

    `progress(epoch, train_mae, validation_mae)` is called after every epoch."""
    import optax

    steps, envs = arrays["done"].shape
    frames = np.concatenate([arrays[name] for name in inputs.fields], axis=-1).astype(np.float32)  # (T, B, F)
    target = arrays["velocity"][..., :len(OUTPUTS)].astype(np.float32)
    order = np.random.default_rng(config.seed).permutation(envs)
    held = max(1, int(round(config.validation_share * envs)))
    train_envs, validation_envs = np.sort(order[held:]), np.sort(order[:held])
    mean = frames[:, train_envs].reshape(-1, frames.shape[-1]).mean(0)
    std = frames[:, train_envs].reshape(-1, frames.shape[-1]).std(0) + 1e-6
    normalised = jnp.asarray((frames - mean) / std)
    age = jnp.asarray(since_reset(arrays["done"]))
    target = jnp.asarray(target)

    def window(t, b):
        """(history * F,) the input of step t of env b: this step first, then earlier ones, zeros before the episode."""
        lags = jnp.arange(inputs.history)
        rows = normalised[jnp.maximum(t - lags, 0), b]
        return (rows * (lags <= age[t, b])[:, None]).reshape(-1)

    windows = jax.vmap(window)
    sizes = (field_sizes(inputs.fields) * inputs.history, *config.hidden, 1)
    keys = jax.random.split(jax.random.PRNGKey(config.seed), len(OUTPUTS))
    params = jax.vmap(lambda k: _init(k, sizes))(keys)  # one network per output, stacked
    optimiser = optax.adam(config.learning_rate)
    opt_state = optimiser.init(params)

    def loss(params, x, y):
        predicted = jax.vmap(lambda p: mlp(p, x)[:, 0], out_axes=1)(params)  # (batch, outputs)
        return jnp.mean(jnp.abs(predicted - y), axis=0).sum(), predicted

    def update(carry, index):
        params, opt_state = carry
        t, b = index
        (_, predicted), grads = jax.value_and_grad(loss, has_aux=True)(params, windows(t, b), target[t, b])
        changes, opt_state = optimiser.update(grads, opt_state, params)
        return (optax.apply_updates(params, changes), opt_state), jnp.abs(predicted - target[t, b]).mean(0)

    @jax.jit
    def epoch(params, opt_state, key, train_env_index):
        t = jnp.repeat(jnp.arange(steps), train_env_index.size)
        b = jnp.tile(train_env_index, steps)
        shuffled = jax.random.permutation(key, t.size)
        batches = t.size // config.batch_size
        take = shuffled[:batches * config.batch_size].reshape(batches, config.batch_size)
        (params, opt_state), errors = jax.lax.scan(update, (params, opt_state), (t[take], b[take]))
        return params, opt_state, errors.mean(0)

    @jax.jit
    def validation_error(params, env_index):
        t = jnp.repeat(jnp.arange(steps), env_index.size)
        b = jnp.tile(env_index, steps)
        chunks = t.reshape(-1, env_index.size), b.reshape(-1, env_index.size)
        errors = jax.lax.map(lambda c: jnp.abs(jax.vmap(lambda p: mlp(p, windows(*c))[:, 0], out_axes=1)(params)
                                                - target[c[0], c[1]]).sum(0), chunks)
        return errors.sum(0) / t.size

    curves = {"train_mae": [], "validation_mae": []}
    key = jax.random.PRNGKey(config.seed + 1)
    for number in range(config.epochs):
        key, sub = jax.random.split(key)
        params, opt_state, train_mae = epoch(params, opt_state, sub, jnp.asarray(train_envs))
        validation_mae = validation_error(params, jnp.asarray(validation_envs))
        curves["train_mae"].append([float(x) for x in train_mae])
        curves["validation_mae"].append([float(x) for x in validation_mae])
        if progress is not None:
            progress(number + 1, curves["train_mae"][-1], curves["validation_mae"][-1])
    arrays_out = {"mean": mean, "std": std}
    for o, name in enumerate(OUTPUTS):
        for i, (kernel, bias) in enumerate(params):
            arrays_out[f"{name}/dense_{i}/kernel"] = np.asarray(kernel[o])
            arrays_out[f"{name}/dense_{i}/bias"] = np.asarray(bias[o])
    meta_out = {"format": ESTIMATOR_FORMAT, "robot": meta["robot"], "inputs": dataclasses.asdict(inputs),
                "outputs": list(OUTPUTS), "layers": len(params), "control_hz": meta["control_hz"],
                "fit": dataclasses.asdict(config), "dataset": {k: meta.get(k, 0.0) for k in ("policy", "steps", "envs", "task", "action_noise")},
                "train_envs": [int(e) for e in train_envs], "validation_envs": [int(e) for e in validation_envs],
                "curves": curves}
    return {"meta": meta_out, "arrays": arrays_out}


def save(path: Path, fitted: dict) -> Path:
    """Write a fitted estimator (`fit`'s document) to `path` (.npz)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez(tmp, meta=np.array(json.dumps(fitted["meta"])), **fitted["arrays"])
    tmp.replace(path)
    return path


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

    def estimator(self) -> estimators.Estimator:
        """The estimator as pure JAX functions: state the standardised window, newest step first."""

        def init():
            return jnp.zeros((self.inputs.history, self.size), jnp.float32)

        def step(history, reading: estimators.Reading, dt):
            history = self._push(history, reading, jnp)
            return history, self._predict(history, jnp)

        return estimators.Estimator(init, step)

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
