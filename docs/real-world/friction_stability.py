"""Where MJX's contact solver fails on the HB40 as the floor's friction falls: physics blow-ups (non-finite
states) in 8 robots x 400 steps of uniform random joint targets (JT-LPF, thesis-code), per friction, with the
released model's impratio 100 and with MuJoCo's default 1.

Writes docs/real-world/friction_stability.json. Run: `python docs/real-world/friction_stability.py`. The on-robot
conditions keep every friction they draw where this finds none (conditions.py).
"""

import dataclasses
import json
from pathlib import Path

import jax
import jax.numpy as jnp

from mjx_badger.protocol import conditions
from mjx_badger.records import results
from mjx_badger.robot import description as robot
from mjx_badger.sim.env import EnvConfig, HB40Env

OUT = Path(__file__).with_suffix(".json")
ROBOTS, STEPS = 8, 400


def blowups(friction: float, impratio: float) -> int:
    """Blow-ups of ROBOTS x STEPS random steps on a floor of this friction (compiled into the model)."""
    spec = dataclasses.replace(robot.HB40, friction=friction, impratio=impratio)
    on_floor = conditions.SIM.replace(**{"ground.friction": (friction, friction)})
    env = HB40Env("jt-lpf", "forward", EnvConfig(conditions=on_floor), spec)

    def roll(key):
        def body(state, k):
            state = env.step(state, jax.random.uniform(k, (env.action_size,), minval=-1.0, maxval=1.0))
            return state, state.info["blew_up"]
        return jax.lax.scan(body, env.reset(key), jax.random.split(key, STEPS))[1].sum()

    return int(jnp.sum(jax.jit(jax.vmap(roll))(jax.random.split(jax.random.PRNGKey(0), ROBOTS))))


def main():
    rows = []
    for impratio in (robot.HB40.impratio, 1.0):
        for friction in (0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.3):
            rows.append({"impratio": impratio, "friction": friction, "blowups": blowups(friction, impratio)})
            print(json.dumps(rows[-1]), flush=True)
    OUT.write_text(json.dumps({"what": results.what(__doc__), "date": results.now()[:10],
                               "git_commit": results.git_commit(), "robots": ROBOTS, "steps": STEPS,
                               "hardware": results.hardware(), "rows": rows}, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
