"""Saved policies: each seed's final actor, run with NumPy alone, so a robot's computer needs no JAX.

Format `mjx_badger.policy/1`, one `<name>.policy.npz` beside a run's results file:
    meta              JSON: format, seeds, config (the results file's: robot, approach and its
                      parameters, algorithm, task, protocol, resolved env and agent settings),
                      observation_layout [[block, size, scale], ...] (the observation is the
                      blocks in this order, each multiplied by its scale), observation_size,
                      action_size, control_hz, and layers, the actor as a list of operations
    <layer>/<array>   each layer's arrays with a leading seed axis
The layers run in order: {"op": "renorm", "name", "epsilon"} y = (x - mean) / sqrt(var + eps)
* scale + bias (batch renormalisation with its running statistics, the released CrossQ's
actor), {"op": "dense", "name"} y = x @ kernel + bias, {"op": "relu"}. The deterministic
action, in [-1, 1] per action dimension, is tanh of the last layer's output (the mean of
the tanh-Gaussian policy); `actions.py` turns it into joint targets.
"""

import json
from pathlib import Path

import numpy as np

from mjx_badger.core import safe_io

FORMAT = "mjx_badger.policy/1"
RENORM_EPSILON = 1e-3  # agents/layers.BatchRenorm's


def path_for(results_path: Path) -> Path:
    return Path(results_path).with_suffix(".policy.npz")


def unsupported(agent: dict) -> str:
    """'' or why an actor of these agent settings (a results file's config["agent"]) has no NumPy policy: the format
    holds the thesis's agents' dense, ReLU and batch-renorm layers only."""
    if agent.get("trunk", "mlp") != "mlp":
        return f"{agent['name']}'s {agent['trunk']!r} network is not in the NumPy policy format (thesis agents' only)"
    if agent.get("observation_norm"):
        return f"{agent['name']} standardises its observations, which the NumPy policy format does not hold"
    return ""


def actor_layers(hidden_layers: int, batch_renorm: bool) -> list[dict]:
    """The operations of the flax Actor (agents/networks.py) up to its mean, by its modules' names."""
    renorm = lambda i: [{"op": "renorm", "name": f"BatchRenorm_{i}", "epsilon": RENORM_EPSILON}] if batch_renorm else []
    layers = renorm(0)
    for i in range(hidden_layers):
        layers += [{"op": "dense", "name": f"Dense_{i}"}, {"op": "relu"}] + renorm(i + 1)
    return layers + [{"op": "dense", "name": f"Dense_{hidden_layers}"}]


def save(path: Path, params: dict, stats: dict, meta: dict) -> Path:
    """Write the actors (flax `params` and `batch_stats` as NumPy arrays with a leading seed axis) and `meta`."""
    params = params.get("params", params)  # the agent keeps flax's {"params": ...} wrapper
    agent = meta["config"]["agent"]
    layers = actor_layers(len(agent["hidden"]), agent["actor_batch_renorm"])
    arrays = {}
    for layer in layers:
        if layer["op"] == "dense":
            arrays |= {f"{layer['name']}/{k}": params[layer["name"]][k] for k in ("kernel", "bias")}
        elif layer["op"] == "renorm":
            arrays |= {f"{layer['name']}/{k}": params[layer["name"]][k] for k in ("scale", "bias")}
            arrays |= {f"{layer['name']}/{k}": stats[layer["name"]][k] for k in ("mean", "var")}
    return _write(path, dict(meta, format=FORMAT, layers=layers),
                  {k: np.asarray(v, np.float32) for k, v in arrays.items()})


def _write(path: Path, meta: dict, arrays: dict) -> Path:
    """Write atomically, so an interrupted save never leaves a half-written policy."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return safe_io.save_npz(path, meta=np.array(json.dumps(meta)), **arrays)


def keep_seeds(path: Path, out: Path, seeds: list[int]) -> Path:
    """A copy of the saved policy at `path` holding only `seeds` (e.g. a run's best seed, to commit)."""
    with np.load(path) as data:
        meta = json.loads(str(data["meta"]))
        missing = sorted(set(seeds) - set(meta["seeds"]))
        if missing:
            raise ValueError(f"{path} holds seeds {meta['seeds']}, not {missing}")
        index = [meta["seeds"].index(seed) for seed in seeds]
        arrays = {k: data[k][index] for k in data.files if k != "meta"}
    return _write(out, dict(meta, seeds=list(seeds)), arrays)


class Policy:
    """One seed's saved actor: `policy(observation) -> action` in [-1, 1], NumPy only."""

    def __init__(self, path: Path, seed: int | None = None):
        try:
            with np.load(path) as data:
                self.meta = json.loads(str(data["meta"]))
                if not isinstance(self.meta, dict) or self.meta.get("format") != FORMAT:
                    raise ValueError(f"{path}: not a {FORMAT} file")
                seeds = self.meta["seeds"]
                seed = seeds[0] if seed is None else seed
                if seed not in seeds:
                    raise ValueError(f"{path} holds seeds {seeds}, not {seed}")
                index = seeds.index(seed)
                self.arrays = {k: data[k][index] for k in data.files if k != "meta"}
            self.layers = self.meta["layers"]
            self._check()
        except ValueError:
            raise
        except Exception as error:  # cut short or edited: zip, pickle, JSON or shape errors, whichever came first
            raise ValueError(f"{path}: damaged policy file ({type(error).__name__}: {error})") from None
        self.seed = seed

    def _check(self) -> None:
        """Every layer's arrays are there, of sizes that chain from the observation to the action (ValueError)."""
        width = self.observation_size
        for layer in self.layers:
            a = lambda name: self.arrays[f"{layer['name']}/{name}"]
            if layer["op"] == "dense":
                if a("kernel").shape[0] != width or a("bias").shape != a("kernel").shape[1:]:
                    raise ValueError(f"layer {layer['name']} does not fit a width of {width}")
                width = a("kernel").shape[1]
            elif layer["op"] == "renorm":
                if any(a(k).shape != (width,) for k in ("scale", "bias", "mean", "var")):
                    raise ValueError(f"layer {layer['name']} does not fit a width of {width}")
            elif layer["op"] != "relu":
                raise ValueError(f"unknown layer {layer['op']!r}")
            if not all(np.all(np.isfinite(v)) for k, v in self.arrays.items() if k.startswith(f"{layer.get('name')}/")):
                raise ValueError(f"layer {layer.get('name')} holds a non-finite number")

    @property
    def observation_size(self) -> int:
        return self.meta["observation_size"]

    def __call__(self, observation) -> np.ndarray:
        x = np.asarray(observation, np.float32)
        if x.shape[-1] != self.observation_size:
            raise ValueError(f"observation of size {x.shape[-1]}, the policy takes {self.observation_size}")
        return self.apply(x)

    def apply(self, x, xp=np):
        """The action of observation `x` with `xp` (numpy, or jax.numpy inside a traced program)."""
        for layer in self.layers:
            a = lambda name: self.arrays[f"{layer['name']}/{name}"]
            if layer["op"] == "dense":
                x = x @ a("kernel") + a("bias")
            elif layer["op"] == "relu":
                x = xp.maximum(x, 0.0)
            else:
                x = (x - a("mean")) / xp.sqrt(a("var") + layer["epsilon"]) * a("scale") + a("bias")
        return xp.tanh(x)


def load(path: Path, seed: int | None = None) -> Policy:
    """The saved policy of `seed` (default the first seed of the run)."""
    return Policy(path, seed)
