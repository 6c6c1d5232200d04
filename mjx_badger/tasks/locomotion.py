"""Tasks: the command a robot is given, the reward it earns for following it, and its curriculum.

A task is pure functions over a small task state that lives in the environment state (so a
curriculum runs per seed under vmap): `init() -> state`, `command(state, key) -> (state,
[vx, vy, yaw rate])` at every episode start, `update(state, command, motion) -> state`
after every step, `progress(state) -> metrics`, and `reward(motion, command) -> (reward,
weighted terms)`. `eval_commands` are the fixed commands of the deterministic evaluation.
"""

import inspect
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp

from mjx_badger.tasks import curriculum, rewards


class Motion(NamedTuple):
    """Raw trunk quantities a reward is computed from (trunk frame)."""

    linear_velocity: jnp.ndarray  # (3,) m/s
    angular_velocity: jnp.ndarray  # (3,) rad/s
    roll: jnp.ndarray
    pitch: jnp.ndarray
    torque: jnp.ndarray  # (12,) N m, net joint torques


class Task(NamedTuple):
    """A named task; see the module docstring for the functions."""

    name: str
    command: Callable
    reward: Callable
    weights: dict
    eval_commands: dict
    """Evaluation run name -> command (3,)."""
    init: Callable = lambda: ()
    update: Callable = lambda state, command, motion: state
    progress: Callable = lambda state: {}


TARGET_VELOCITY = 0.5
FORWARD_WEIGHTS = {"velocity": 1.0, "yaw": -0.1, "roll_pitch": -10.0, "energy": -0.0003}
MAX_VELOCITY_WEIGHTS = {"velocity": 2.0, "yaw": -0.1, "roll_pitch": -10.0}
OMNI_WEIGHTS = {"velocity": 1.0, "yaw": -0.1, "roll_pitch": -10.0, "energy": -0.0003}
# The released code's track_xy: 0.5 |yaw-rate error|, no energy term (docs/thesis-code.md §5).
OMNI_WEIGHTS_CODE = {"velocity": 1.0, "yaw": -0.5, "roll_pitch": -10.0}
LATERAL_PENALTY_WEIGHT = -1.0
REWARD_SCALE = 10.0
REWARD_FORMS = ("thesis-text", "thesis-code")


def fixed(command):
    """The same command every episode."""
    # Made an array when traced: building a task must not start JAX's backend (jax.distributed comes first).
    return lambda state, key: (state, jnp.asarray(command, dtype=jnp.float32))


def _penalties(motion: Motion, squared_yaw: bool = True, energy: bool = True, yaw_target=0.0) -> dict:
    yaw_error = motion.angular_velocity[2] - yaw_target
    terms = {
        "yaw": (rewards.yaw_rate_squared if squared_yaw else rewards.yaw_rate_abs)(yaw_error),
        "roll_pitch": rewards.roll_pitch_squared(motion.roll, motion.pitch),
    }
    if energy:
        terms["energy"] = rewards.torque_squared(motion.torque)
    return terms


def forward(target_velocity: float = TARGET_VELOCITY, weights=None, form: str = "thesis-text") -> Task:
    """Forward locomotion at a target velocity (thesis §4.4.1, Table 4.5; the code's track_x under 'thesis-code')."""
    weights = dict(FORWARD_WEIGHTS if weights is None else weights)
    code = form == "thesis-code"
    tracking = rewards.velocity_tracking_code if code else rewards.velocity_tracking

    def reward(motion: Motion, cmd):
        terms = {"velocity": tracking(motion.linear_velocity[0], cmd[0]), **_penalties(motion, squared_yaw=not code)}
        return rewards.combine(terms, weights, REWARD_SCALE)

    command = (target_velocity, 0.0, 0.0)
    return Task(name="forward", command=fixed(command), reward=reward, weights=weights,
                eval_commands={"forward": command})


def forward_max(weights=None, form: str = "thesis-text") -> Task:
    """Forward locomotion as fast as possible (thesis §5.1.3, Table 4.6).

    thesis-text: clipped at 0, the command reads zero. thesis-code: unclipped, and the command
    stays the forward task's (0.5, 0, 0), as the released max-velocity scripts ran it (§10).
    """
    weights = dict(MAX_VELOCITY_WEIGHTS if weights is None else weights)
    code = form == "thesis-code"

    def reward(motion: Motion, cmd):
        terms = {"velocity": rewards.forward_minus_lateral(motion.linear_velocity[:2]),
                 **_penalties(motion, squared_yaw=False, energy=False)}
        return rewards.combine(terms, weights, REWARD_SCALE, clip=not code)

    command = (TARGET_VELOCITY, 0.0, 0.0) if code else (0.0, 0.0, 0.0)
    return Task(name="forward-max", command=fixed(command), reward=reward, weights=weights,
                eval_commands={"forward": command})


def omni_eval_commands(speed: float = TARGET_VELOCITY) -> dict:
    """§5.1.4: forward, backward, left, right at the full and half target speed."""
    directions = {"forward": (1, 0), "backward": (-1, 0), "left": (0, 1), "right": (0, -1)}
    return {f"{name}_{level}": (scale * speed * dx, scale * speed * dy, 0.0)
            for name, (dx, dy) in directions.items() for level, scale in (("full", 1.0), ("half", 0.5))}


def omni_reward(weights: dict, rotated: bool, form: str = "thesis-text"):
    """§4.4.2 velocity reward plus penalties.

    `rotated` is approach 1 (velocity turned into the command's frame, the Table 4.5 term on
    the along-command speed, and a lateral penalty |v_lat|); otherwise approach 2, the joint
    2-D tracking term the thesis's experiments use. thesis-code: 0.5 |yaw-rate error|, no energy.
    """
    code = form == "thesis-code"

    def reward(motion: Motion, cmd):
        velocity = motion.linear_velocity[:2]
        if rotated:
            along, lateral = rewards.along_and_lateral(velocity, cmd[:2])
            terms = {"velocity": rewards.velocity_tracking(along, jnp.linalg.norm(cmd[:2])),
                     "lateral": jnp.abs(lateral)}
        else:
            terms = {"velocity": rewards.planar_velocity_tracking(velocity, cmd[:2])}
        terms.update(_penalties(motion, squared_yaw=not code, energy=not code, yaw_target=cmd[2] if code else 0.0))
        return rewards.combine(terms, weights, REWARD_SCALE)

    return reward


def omni_random(speed: float = TARGET_VELOCITY, rotated: bool = False, form: str = "thesis-text",
                weights=None) -> Task:
    """Omnidirectional locomotion, direction uniform on the circle every episode (§5.1.4)."""
    base = OMNI_WEIGHTS_CODE if form == "thesis-code" else OMNI_WEIGHTS
    weights = dict(base, **({"lateral": LATERAL_PENALTY_WEIGHT} if rotated else {})) if weights is None else dict(weights)

    def command(state, key):
        angle = jax.random.uniform(key, minval=-jnp.pi, maxval=jnp.pi)
        return state, jnp.array([speed * jnp.cos(angle), speed * jnp.sin(angle), 0.0])

    return Task(name="omni-random-rotated" if rotated else "omni-random", command=command,
                reward=omni_reward(weights, rotated, form), weights=weights, eval_commands=omni_eval_commands(speed))


def omni_pdec(speed: float = TARGET_VELOCITY, form: str = "thesis-text", rules: str | None = None,
              weights=None) -> Task:
    """Omnidirectional locomotion under the Progressive Directional Expansion Curriculum (§4.5.1).

    `rules` names the curriculum's rule set (`curriculum.RULES`); by default the reward form's.
    """
    weights = dict((OMNI_WEIGHTS_CODE if form == "thesis-code" else OMNI_WEIGHTS) if weights is None else weights)
    chosen = curriculum.RULES[rules or form]

    def update(state, cmd, motion: Motion):
        return curriculum.record(state, cmd, motion.linear_velocity[:2], motion.angular_velocity[2], chosen)

    return Task(name="omni-pdec", command=lambda state, key: curriculum.sample(state, key, speed, chosen),
                reward=omni_reward(weights, rotated=False, form=form), weights=weights,
                eval_commands=omni_eval_commands(speed), init=curriculum.init, update=update,
                progress=curriculum.progress)


TASKS = {
    "forward": lambda form, rules, target_velocity=TARGET_VELOCITY, weights=None: forward(target_velocity, weights,
                                                                                          form=form),
    "forward-max": lambda form, rules, weights=None: forward_max(weights, form=form),
    "omni-random": lambda form, rules, speed=TARGET_VELOCITY, weights=None: omni_random(speed, form=form,
                                                                                       weights=weights),
    "omni-random-rotated": lambda form, rules, speed=TARGET_VELOCITY, weights=None: omni_random(
        speed, rotated=True, form=form, weights=weights),
    "omni-pdec": lambda form, rules, speed=TARGET_VELOCITY, weights=None: omni_pdec(speed, form=form, rules=rules,
                                                                                   weights=weights),
}
"""Task name -> (reward form, curriculum rules, **params, weights=None) -> Task; its keyword parameters
are the task's, and `weights` (term -> weight, None for the task's own) replaces its reward weights."""

WEIGHT_SUFFIX = "_weight"
"""A task parameter <term>_weight sets the weight of one reward term (e.g. energy_weight=0)."""


def takes_weights(name: str) -> bool:
    """Whether the task `name`'s factory takes `weights=` (or any keyword), so its reward weights can be set."""
    parameters = inspect.signature(TASKS[name]).parameters.values()
    return any(p.name == "weights" or p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters)


def task_params(name: str, form: str = "thesis-text") -> tuple:
    """The keyword parameters the task `name` takes under a reward form: its own, then one <term>_weight per term
    where its factory takes `weights`."""
    own = tuple(p for p in tuple(inspect.signature(TASKS[name]).parameters)[2:] if p != "weights")
    if not takes_weights(name):
        return own
    return own + tuple(f"{term}{WEIGHT_SUFFIX}" for term in TASKS[name](form, None).weights)


def check_params(name: str, params: dict, form: str = "thesis-text"):
    """Raise ValueError for a parameter the task does not take under `form`, naming the ones it does."""
    unknown = sorted(set(params) - set(task_params(name, form)))
    if not unknown:
        return
    if any(p.endswith(WEIGHT_SUFFIX) for p in unknown) and not takes_weights(name):
        raise ValueError(f"task {name!r} cannot take reward weights ({', '.join(unknown)}): its factory has no "
                         "weights=None parameter")
    raise ValueError(f"task {name!r} takes {', '.join(task_params(name, form)) or 'no parameters'}, "
                     f"not {', '.join(unknown)}")


def make_task(name: str, form: str = "thesis-text", curriculum_rules: str | None = None, **params) -> Task:
    """The task `name` with a protocol's reward forms and curriculum rules ('thesis-text' or 'thesis-code')."""
    check_params(name, params, form)
    own = {k: v for k, v in params.items() if not k.endswith(WEIGHT_SUFFIX)}
    weights = {k[:-len(WEIGHT_SUFFIX)]: v for k, v in params.items() if k.endswith(WEIGHT_SUFFIX)}
    task = TASKS[name](form, curriculum_rules, **own)
    return TASKS[name](form, curriculum_rules, weights={**task.weights, **weights}, **own) if weights else task
