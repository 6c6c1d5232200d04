"""What the thesis-code robot costs MJX: physics steps/s of the old and new HB40 models, with and
without the extra floor contacts, at several solver iteration counts; and the full env step.

Prints a table and writes benchmarks/results/bench_contacts.json. Run: `python -m benchmarks.bench_contacts`.
The old model is the one this suite used before issue 12 (feet-only contacts, 4 Newton iterations,
its own geometry), read from git history.
"""

import contextlib
import dataclasses
import io
import json
import subprocess
from pathlib import Path

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from benchmarks.common import RESULTS, timed
from mjx_badger.records import results
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf
from mjx_badger.sim.env import HB40Env

with contextlib.redirect_stdout(io.StringIO()):
    from mujoco import mjx

OUT = RESULTS / "bench_contacts.json"
OLD_MODEL_COMMIT = "2b26d22"
STEPS = 200


def old_model() -> mujoco.MjModel:
    xml = subprocess.run(["git", "show", f"{OLD_MODEL_COMMIT}:mjx_badger/assets/hb40.xml"], capture_output=True,
                         text=True, check=True, cwd=Path(__file__).parent).stdout
    return mujoco.MjModel.from_xml_string(xml)


def feet_only(spec: robot.RobotSpec) -> robot.RobotSpec:
    """The new robot with only the four foot-floor pairs."""
    return dataclasses.replace(spec, floor_contacts=("foot",))


def physics_steps_per_s(model: mujoco.MjModel, batch: int, nominal) -> float:
    """Physics steps/s of mjx.step under a PD wave around the stance, `batch` robots vmapped."""
    mx = mjx.put_model(model)
    data = mujoco.MjData(model)
    data.qpos[:3] = [0, 0, 0.3]
    data.qpos[3] = 1.0
    data.qpos[7:] = nominal
    dx = mjx.put_data(model, data)
    wave = nominal + 0.2 * np.sin(np.arange(STEPS)[:, None] * 0.1 + np.arange(12))

    def rollout(dx):
        def body(dx, u):
            return mjx.step(mx, dx.replace(ctrl=u)), None

        return jax.lax.scan(body, dx, jnp.asarray(wave, jnp.float32))[0].qpos

    batched = jax.jit(jax.vmap(rollout)) if batch > 1 else jax.jit(rollout)
    start = jax.tree.map(lambda x: jnp.stack([x] * batch), dx) if batch > 1 else dx
    return batch * STEPS / timed(batched, start)


def env_steps_per_s(approach: str, batch: int, spec: robot.RobotSpec = robot.HB40) -> float:
    """Full environment steps/s (thesis-code protocol, random actions)."""
    env = HB40Env(approach, "forward", spec=spec)

    def rollout(keys):
        def body(state, key):
            action = jax.random.uniform(key, (batch, env.action_size), minval=-1, maxval=1)
            return jax.vmap(env.step)(state, action), None

        state = jax.vmap(env.reset)(keys)
        return jax.lax.scan(body, state, jax.random.split(keys[0], STEPS))[0].obs

    return batch * STEPS / timed(jax.jit(rollout), jax.random.split(jax.random.PRNGKey(0), batch))


def main():
    rows = []
    # The old model's nominal pose had the hip mirrored per side and one thigh/knee convention for all legs.
    old_nominal = np.concatenate([[0.1 * side, 0.6, -1.2] for side in (1, -1, 1, -1)])
    variants = [("old model: 4 foot pairs, 4 iterations", old_model(), old_nominal)]
    for iterations in (4, 10, 50):
        spec = dataclasses.replace(robot.HB40, solver_iterations=iterations, solver_ls_iterations=min(iterations, 10))
        variants.append((f"new model: 4 foot pairs, {iterations} iterations", mjcf.load_model(feet_only(spec)),
                         robot.nominal_pose()))
        variants.append((f"new model: 13 floor pairs, {iterations} iterations", mjcf.load_model(spec),
                         robot.nominal_pose()))
    for name, model, nominal in variants:
        row = {"variant": name, "contacts": int(model.npair)}
        for batch in (1, 16):
            row[f"physics_steps_per_s_batch{batch}"] = round(physics_steps_per_s(model, batch, nominal), 1)
        rows.append(row)
        print(f"{name:45s} " + "  ".join(f"{k}: {v}" for k, v in row.items() if k.startswith("physics")), flush=True)
    env_rows = {}
    # The env step before the extra contacts (feet only) and after (all 13 floor pairs), same code otherwise.
    for approach in ("jt-oef", "cpg-d"):
        for contacts, spec in (("", robot.HB40), ("_feet_only", feet_only(robot.HB40))):
            for batch in (1, 16):
                name = f"{approach}{contacts}_batch{batch}"
                env_rows[name] = round(env_steps_per_s(approach, batch, spec), 1)
                print(f"env step {name}: {env_rows[name]} steps/s", flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps({"physics": rows, "env_steps_per_s": env_rows, "physics_steps_per_rollout": STEPS,
                               "hardware": results.hardware(), "versions": results.versions(),
                               "git_commit": results.git_commit(), "date": results.now()}, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
