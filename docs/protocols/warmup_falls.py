"""Falls per 1000 uniform random steps for each approach on the HB40, under each protocol, in native MuJoCo.

The warm-up of every run is 1000 such steps, so this is what an approach pays before learning
starts. Each protocol brings its own gains, control rate, action pipeline, action delay and
termination rule (the environment's own functions, run step by step against native MuJoCo);
a fall resets the robot. Under thesis-code a CPG episode never terminates, so for CPG the
count is the rule's would-be falls, with the same reset. Writes docs/protocols/warmup_falls.json.
Run: `python docs/protocols/warmup_falls.py [--steps 1000] [--seeds 3]`.
"""

import argparse
import json
import types
from pathlib import Path

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger.control import actions
from mjx_badger.experiments.registry import THESIS_APPROACHES
from mjx_badger.protocol import protocols
from mjx_badger.records import results
from mjx_badger.robot import description as robot
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.sim.observation import roll_pitch
from mjx_badger.tasks import locomotion as tasks

OUT = Path(__file__).with_suffix(".json")


def falls_per_run(approach: str, protocol: protocols.Protocol, steps: int, seed: int,
                  spec: robot.RobotSpec = robot.HB40) -> int:
    """Falls (or, for a CPG that never terminates, would-be falls) in `steps` random control steps."""
    env = HB40Env(approach, "forward", EnvConfig(protocol=protocol), spec)
    model = env.mj_model
    data = mujoco.MjData(model)
    act = jax.jit(env.action_space.step)
    rule = env._fall_rule  # eager: it reads a native MjData through the same attribute names
    rng = np.random.default_rng(seed)

    def reset():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = robot.standing_qpos(model, spec)
        data.ctrl[:] = env.action_space.rest_ctrl()
        mujoco.mj_forward(model, data)
        return env.action_space.init(), np.asarray(env.action_space.rest_ctrl())

    action_state, previous = reset()
    falls, power_steps = 0, 0
    for _ in range(steps):
        action_state, target = act(action_state, jnp.asarray(rng.uniform(-1, 1, env.action_size), jnp.float32))
        target = np.asarray(target)
        delay = 0
        if protocol.action_delay:
            delay = int(np.clip(round(abs(0.03 + 0.05 * rng.normal()) / spec.physics_dt), 0, env.substeps))
        for i in range(env.substeps):
            data.ctrl[:] = previous if i < delay else target
            torque = env._kp * (data.ctrl[:12] - data.qpos[7:]) - env._kd * data.qvel[6:]
            mujoco.mj_step(model, data)
            if protocol.joint_velocity_clip is not None:
                data.qvel[6:] = np.clip(data.qvel[6:], -protocol.joint_velocity_clip, protocol.joint_velocity_clip)
        previous = target
        power_steps = power_steps + 1 if np.sum(np.abs(torque * data.qvel[6:])) > 1500.0 else 0
        rot = data.xmat[env._trunk].reshape(3, 3)
        motion = tasks.Motion(None, None, *roll_pitch(jnp.asarray(rot)), None)
        view = types.SimpleNamespace(xmat=data.xmat.reshape(-1, 3, 3), xpos=data.xpos, qpos=data.qpos, qvel=data.qvel)
        if bool(rule(view, motion, power_steps)):
            falls += 1
            action_state, previous = reset()
            power_steps = 0
    return falls


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    table = {}
    for name, protocol in protocols.PROTOCOLS.items():
        for approach in THESIS_APPROACHES:
            # The JT approaches also on this suite's first robot (the CPG's kinematics are the HB40's).
            for spec in (robot.HB40,) if actions.is_cpg(approach) else robot.ROBOTS.values():
                label = name if spec == robot.HB40 else f"{name} on {spec.name}"
                counts = [falls_per_run(approach, protocol, args.steps, seed, spec) for seed in range(args.seeds)]
                table.setdefault(approach, {})[label] = counts
                print(f"{approach:7s} {label:24s} falls per {args.steps} random steps: {counts} "
                      f"(mean {np.mean(counts):.1f})", flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps({"steps": args.steps, "seeds": args.seeds, "falls": table,
                               "note": "CPG under thesis-code: would-be falls (its episodes never terminate)",
                               "hardware": results.hardware(), "versions": results.versions(),
                               "git_commit": results.git_commit(), "date": results.now()}, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
