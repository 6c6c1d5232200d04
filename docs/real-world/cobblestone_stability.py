"""Where MJX's contact solver fails on the cobblestones: physics blow-ups (non-finite states) in 8 robots x 1000
steps of uniform random joint targets (JT-NF, thesis-code, the outdoor conditions), per impratio of the contact
solver, beside the same conditions on flat ground.

Writes docs/real-world/cobblestone_stability.json. Run: `python docs/real-world/cobblestone_stability.py`. The outdoor
conditions take the impratio this finds stable (protocol/conditions.py; the field Ground.impratio of robot/terrain.py).
"""

import json
from pathlib import Path

import jax
import jax.numpy as jnp

from mjx_badger.protocol import conditions
from mjx_badger.records import results
from mjx_badger.sim.env import EnvConfig, HB40Env

OUT = Path(__file__).with_suffix(".json")
ROBOTS, STEPS = 8, 1000


def blowups(ground_changes: dict) -> dict:
    """Blow-ups and episode ends of ROBOTS x STEPS random steps under the outdoor conditions with `ground_changes`."""
    env = HB40Env("jt-nf", "forward", EnvConfig(conditions=conditions.OUTDOOR.replace(**ground_changes)))

    def roll(key):
        def body(state, k):
            state = env.step(state, jax.random.uniform(k, (env.action_size,), minval=-1.0, maxval=1.0))
            return state, (state.info["blew_up"], state.done)
        blew_up, done = jax.lax.scan(body, env.reset(key), jax.random.split(key, STEPS))[1]
        return blew_up.sum(), done.sum()

    blew_up, done = jax.jit(jax.vmap(roll))(jax.random.split(jax.random.PRNGKey(0), ROBOTS))
    return {"blowups": int(jnp.sum(blew_up)), "episode_ends": int(jnp.sum(done))}


def main():
    rows = []
    cases = [("cobblestones", impratio) for impratio in (100.0, 30.0, 10.0, 3.0, 1.0)] + [("flat", 100.0), ("flat", 1.0)]
    for terrain, impratio in cases:
        rows.append({"terrain": terrain, "impratio": impratio,
                     **blowups({"ground.terrain": terrain, "ground.impratio": impratio})})
        print(json.dumps(rows[-1]), flush=True)
    OUT.write_text(json.dumps({"what": results.what(__doc__), "date": results.now()[:10],
                               "git_commit": results.git_commit(), "robots": ROBOTS, "steps": STEPS,
                               "hardware": results.hardware(), "rows": rows}, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
