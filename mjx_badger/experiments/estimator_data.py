"""§2.6.3: the learned estimator's dataset, walked by a trained policy in the vmapped MJX env.

What the robot's own sensors read at every control step, noise-free as in the thesis, beside the true
trunk-frame velocity, from a run's best saved seed walking under a task's commands, one trajectory
per env (`estimator collect`; the file's format and the fit: estimation/fit.py).
"""

import dataclasses
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.core.paths import REPOSITORY
from mjx_badger.estimation import fit, sensors
from mjx_badger.estimation.learned import FIELDS, frame
from mjx_badger.learning.config import from_results
from mjx_badger.records import analysis, policy, results
from mjx_badger.sim.env import HB40Env


def collect(results_path: Path, steps: int, envs: int, task: str = "omni-random", seed: int = 0,
            chunk: int = 500, progress=None, action_noise: float = 0.0) -> tuple[dict, dict]:
    """(meta, arrays) of a dataset: the best seed's saved policy of a run walking under `task`'s commands in
    `envs` MJX envs for `steps` control steps each, its sensors exact, Gaussian noise of std `action_noise` on its
    actions (as a policy still exploring in training acts). `progress(steps_done)` after each chunk."""
    document = results.read(results_path)
    if "policy" not in document:
        raise ValueError(f"{results_path} has no saved policy")
    config = from_results(document)
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
    where = Path(results_path).resolve()
    shown = where.relative_to(REPOSITORY) if where.is_relative_to(REPOSITORY) else where  # no machine's folders
    meta = {"robot": config.robot_spec.name, "fields": [list(f) for f in FIELDS], "policy": str(shown),
            "policy_seed": policy_seed, "approach": config.approach, "task": task,
            "protocol": env_config.protocol.name, "control_hz": env.control_hz, "steps": steps, "envs": envs,
            "seed": seed, "action_noise": action_noise, "sensors": "exact (no noise, as the thesis's dataset)"}
    return meta, arrays


def write(results_path: Path, steps: int, envs: int, task: str, seed: int, action_noise: float, out: Path,
          progress=None) -> Path:
    """`collect` a dataset of `steps` control steps in all over `envs` envs and write it to `out`."""
    meta, arrays = collect(results_path, steps // envs, envs, task, seed, progress=progress, action_noise=action_noise)
    return fit.save_dataset(out, arrays, meta)
