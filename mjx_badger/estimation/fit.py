"""§2.6.3: the learned estimator's dataset file and its fit, as the thesis fitted it.

A dataset (written by `estimator collect`, experiments/estimator_data.py) holds what the robot's own
sensors read at every control step, noise-free as in the thesis, beside the true trunk-frame velocity,
one trajectory per env. The fit is the thesis's: per velocity component (vx, vy) one MLP of dense 256,
256, 1 with ReLU, Adam at 1e-3, mean absolute error, 100 epochs, the trajectories split 80/20 into
training and validation (held out whole, so no validation step has a neighbour in training). Inputs
are standardised with the training set's mean and std.
"""

import dataclasses
import json
import zipfile
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.estimation.learned import ESTIMATOR_FORMAT, FIELDS, INPUTS, OUTPUTS, Inputs, field_sizes, mlp
from mjx_badger.robot.description import HB40, RobotSpec

DATASET_FORMAT = "mjx_badger.estimator-dataset/1"


@dataclasses.dataclass(frozen=True)
class FitConfig:
    """The thesis's fit (§2.6.3); batch size and validation split's seed are ours (the thesis gives none)."""

    hidden: tuple = (256, 256)
    learning_rate: float = 1e-3
    epochs: int = 100
    validation_share: float = 0.2
    batch_size: int = 256
    seed: int = 0


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


def since_reset(done: np.ndarray) -> np.ndarray:
    """(steps, envs) control steps since each env's episode began. A step that ends an episode is recorded after the
    env's reset (its reading and velocity are the new episode's start), so it counts 0, as does the first step."""
    count = np.zeros_like(done, dtype=np.int32)
    for t in range(1, done.shape[0]):
        count[t] = np.where(done[t], 0, count[t - 1] + 1)
    return count


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


def fit_file(dataset: Path, inputs: str, epochs: int, batch_size: int, out: Path, progress=None) -> dict:
    """Fit the estimator of `inputs` (learned.INPUTS) on the dataset file and write it to `out`; returns `fit`'s
    document (its curves: the validation MAE per epoch)."""
    meta, arrays = load_dataset(dataset)
    fitted = fit(meta, arrays, INPUTS[inputs], FitConfig(epochs=epochs, batch_size=batch_size), progress)
    save(out, fitted)
    return fitted
