"""Sweeps: configurations that differ only in numeric parameters, trained as one program.

A grid sets fields of a run's parameter tuples (`algo_params.learning_rate`, `task_params.
target_velocity`, `approach_params.min_cutoff`, ...) to several values; its members are every
combination. The swept values are arrays in the carry, not Python constants: the program is
traced once with them as tracers (`make_train` of a config whose swept fields hold them) and
compiled once for all members. Members go through `lax.map` in groups of `vmapped` (vmapped
within a group, which must divide the members; seeds are vmapped inside each member). With groups of one, every member runs
the very program of its separate run, so the numbers equal the separate runs' to the bit; in
bigger groups XLA batches the arithmetic differently and they agree only up to float rounding
(a GPU's choice: members in parallel).

A grid is refused before anything compiles when a field is not a run parameter, its values are
not numbers, its members differ in array shapes (naming the field and the array), or the field
is fixed when the program is built (a loop length, a branch, a filter design) and so cannot be an array.
"""

import ast
import contextlib
import dataclasses
import itertools
import json
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.core import stops
from mjx_badger.learning import documents, runner
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.programs import fresh_trace, seeds_chunk
from mjx_badger.learning.train import make_train
from mjx_badger.records import results

GROUPS = ("approach_params", "algo_params", "task_params")
"""The RunSpec fields whose parameters a sweep sets."""


def parse_axis(text: str) -> tuple[str, tuple]:
    """'algo_params.learning_rate=0.001,0.003' as ('algo_params.learning_rate', (0.001, 0.003))."""
    field, sep, values = text.partition("=")
    if not sep or not values:
        raise ValueError(f"expected GROUP.NAME=V1,V2,..., got {text!r}")
    try:
        parsed = tuple(ast.literal_eval(v.strip()) for v in values.split(","))
    except (ValueError, SyntaxError):
        parsed = ()
    if not parsed or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in parsed):
        raise ValueError(f"sweep values of {field} must be numbers, not {values!r}")
    return field.strip(), parsed


def read_grid(path: Path) -> tuple:
    """A grid file: JSON {"GROUP.NAME": [values], ...}."""
    try:
        grid = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise ValueError(f"cannot read the grid file {str(path)!r}: {error}") from None
    if not isinstance(grid, dict) or not all(isinstance(v, list) and v for v in grid.values()):
        raise ValueError(f"{path}: a grid file is a JSON object of GROUP.NAME -> a non-empty list of numbers")
    return tuple((field, tuple(values)) for field, values in grid.items())


def with_values(base: TrainConfig, fields: tuple, values) -> TrainConfig:
    """`base` with each `GROUP.NAME` of `fields` set to its entry of `values` (numbers or tracers)."""
    changes = {}
    for field, value in zip(fields, values):
        group, name = field.split(".", 1)
        own = dict(changes.get(group, getattr(base, group)))
        own[name] = value
        changes[group] = tuple(own.items())
    return dataclasses.replace(base, **changes)


def members(base: TrainConfig, axes: tuple) -> list[TrainConfig]:
    """Every combination of the grid's values, each a checked config; ValueError for a field no run takes."""
    if not axes:
        raise ValueError("a sweep needs at least one --vary GROUP.NAME=V1,V2,...")
    fields = [field for field, _ in axes]
    for field, values in axes:
        group, dot, name = field.partition(".")
        if group not in GROUPS or not dot or not name:
            raise ValueError(f"cannot sweep {field!r}: a sweep sets GROUP.NAME with GROUP one of {', '.join(GROUPS)} "
                             "(other fields change the program: run `train` for each)")
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            raise ValueError(f"sweep values of {field} must be numbers, not {list(values)}")
    if len(set(fields)) != len(fields):
        raise ValueError(f"a field is swept twice: {', '.join(fields)}")
    return [with_values(base, fields, combo) for combo in itertools.product(*(values for _, values in axes))]


def parts(members: int, vmapped: int) -> list[tuple]:
    """The members' indices in groups of `vmapped`: one cluster job's or process's share each."""
    size = check_groups(members, vmapped)
    return [tuple(range(i, i + size)) for i in range(0, members, size)]


def check_groups(members: int, vmapped: int) -> int:
    """The group size: `vmapped` members at most; ValueError unless the groups are whole."""
    if vmapped < 1:
        raise ValueError(f"--vmapped must be at least 1, not {vmapped}")
    size = min(vmapped, members)
    if members % size:
        raise ValueError(f"{members} members do not split into groups of {vmapped} (--vmapped): choose a divisor "
                         f"of {members}")
    return size


def check_shapes(configs: list[TrainConfig], fields: list[str]) -> None:
    """ValueError naming the swept field and the array if two members' carries differ in shape or type."""
    shape = lambda config: jax.eval_shape(make_train(config).init, jax.random.PRNGKey(0))
    first = jax.tree_util.tree_flatten_with_path(shape(configs[0]))[0]
    for config in configs[1:]:
        other = jax.tree_util.tree_flatten_with_path(shape(config))[0]
        for (path, a), (_, b) in zip(first, other):
            if (a.shape, a.dtype) != (b.shape, b.dtype):
                differ = [f for f in fields if _value(configs[0], f) != _value(config, f)]
                raise ValueError(f"sweep members differ in shape: {', '.join(differ)} changes "
                                 f"{jax.tree_util.keystr(path)} from {a.shape} to {b.shape}; run them separately")


def _value(config: TrainConfig, field: str):
    group, name = field.split(".", 1)
    return dict(getattr(config, group)).get(name)


class Sweep:
    """The compiled program of a grid: `init(keys)`, `chunk(carry, start)`, `gait(carry)` over members x seeds."""

    def __init__(self, base: TrainConfig, axes: tuple, seeds: list[int], vmapped: int = 1, part: tuple | None = None):
        self.fields = [field for field, _ in axes]
        self.grid = members(base, axes)
        self.part = tuple(part) if part is not None else None
        """The members this program trains, by index into the grid (a cluster job's share); None: all."""
        self.configs = [self.grid[i] for i in self.part] if part is not None else self.grid
        self.seeds = list(seeds)
        self.vmapped = check_groups(len(self.configs), vmapped)
        self.values = jnp.asarray([[_value(c, f) for f in self.fields] for c in self.configs], jnp.float32)
        check_shapes(self.configs, self.fields)
        self._check_traceable(base)

    def trainer(self, values):
        """The trainer of one member whose swept fields hold `values` (tracers inside the program)."""
        # The concrete parts (the MJX model, filter tables) are built eagerly even under the trace.
        with jax.ensure_compile_time_eval():
            return make_train(with_values(self.configs[0], self.fields, list(values)))

    def _over_members(self, body, values, *xs):
        """`body(member_values, *member_xs)` for every member: lax.map in groups of `vmapped`, in one program."""
        args = (values, *xs)
        if self.vmapped == 1:
            return jax.lax.map(lambda member: body(*member), args)
        # Groups by explicit reshapes (lax.map's batch_size reshapes with -1, which an empty MJX array refuses).
        groups, size = len(self.configs) // self.vmapped, self.vmapped
        split = lambda x: x.reshape((groups, size) + x.shape[1:])
        join = lambda x: x.reshape((groups * size,) + x.shape[2:])
        out = jax.lax.map(lambda group: jax.vmap(body)(*group), jax.tree.map(split, args))
        return jax.tree.map(join, out)

    def _check_traceable(self, base: TrainConfig) -> None:
        """ValueError naming a swept field the program needs as a Python number (traced one field at a time)."""
        key = jax.random.PRNGKey(0)
        row = [float(v) for v in self.values[0]]
        for i, field in enumerate(self.fields):
            def traced(value):
                values = [value if j == i else row[j] for j in range(len(self.fields))]
                trainer = self.trainer(values)
                return trainer.chunk(trainer.init(key), 0)
            try:
                jax.eval_shape(traced, self.values[0, i])
            except (jax.errors.JAXTypeError, TypeError) as error:
                reason = str(error).strip().splitlines()[0][:120]
                raise ValueError(f"cannot sweep {field}: the program needs it as a Python number when it is built "
                                 f"(an array shape, a loop length, a branch or a filter design; {type(error).__name__}:"
                                 f" {reason}), so it cannot be an array; run `train` for each value") from None

    def init(self):
        keys = jax.vmap(jax.random.PRNGKey)(jnp.asarray(self.seeds))
        return jax.jit(lambda: self._over_members(lambda v: jax.vmap(self.trainer(v).init)(keys), self.values))()

    def compiled(self):
        """(initial carry, compiled chunk, compile seconds); the carry is (swept values, members x seeds carry)."""
        fresh_trace()  # the module a resumed sweep's new process builds: it loads from the compile cache
        carry = (self.values, self.init())

        def chunk(carry, start):
            values, state = carry
            body = lambda v, c: seeds_chunk(self.trainer(v), len(self.seeds))(c, start)
            state, metrics = self._over_members(body, values, state)
            return (values, state), metrics

        t0 = time.perf_counter()
        program = jax.jit(chunk, donate_argnums=0).lower(carry, 0).compile()
        return carry, program, time.perf_counter() - t0

    def gait(self, carry):
        values, state = carry
        return jax.device_get(jax.jit(lambda values, state: self._over_members(
            lambda v, c: jax.vmap(self.trainer(v).gait)(c), values, state))(values, state))

    def name(self, config: TrainConfig) -> str:
        """The results file name of a member: the run's name and its swept values."""
        return member_name(config, self.fields)


def member_name(config: TrainConfig, fields: list[str]) -> str:
    """The results file name of a sweep member (without .json): the run's name and its swept values."""
    swept = "_".join(f"{f.split('.', 1)[1]}={_value(config, f):g}" for f in fields)
    return f"{config.name}_{swept}"


def run(base: TrainConfig, axes: tuple, seeds: list[int], out_dir: Path, vmapped: int = 1, progress: bool = True,
        resume: bool = True, tensorboard: bool = True, part: tuple | None = None, keep_landed_since: str | None = None) -> list[dict]:
    """Train every member of the grid (or the members `part` names) in one program; one results file per member
    in `out_dir`. With `keep_landed_since`, members that all landed already are not trained again (runner.run)."""
    sweep = Sweep(base, axes, seeds, vmapped, part)
    share = "" if part is None else f"_members_{min(part)}-{max(part)}"
    checkpoint_path = Path(out_dir) / f"sweep_{base.name}{share}.json"
    with contextlib.ExitStack() as held:
        for path in [checkpoint_path] + [Path(out_dir) / f"{sweep.name(config)}.json" for config in sweep.configs]:
            held.enter_context(runner.writing(path))  # one sweep at a time into these files
        held.enter_context(stops.graceful())
        paths = [Path(out_dir) / f"{sweep.name(config)}.json" for config in sweep.configs]
        if resume:
            for path in paths:
                documents.check_resumable(path)
        done = [documents.landed(path, config, seeds, keep_landed_since) for path, config in zip(paths, sweep.configs)]
        if all(document is not None for document in done):  # a requeued task, a rerun
            return done
        return _run(sweep, checkpoint_path, seeds, out_dir, progress, resume, tensorboard)


def _run(sweep: Sweep, checkpoint_path: Path, seeds: list[int], out_dir: Path, progress: bool, resume: bool,
         tensorboard: bool) -> list[dict]:
    started = results.now()
    carry, chunk, compile_s = sweep.compiled()
    members = [documents.Member(config, list(seeds), Path(out_dir) / f"{sweep.name(config)}.json",
                                make_train(config).env) for config in sweep.configs]
    views = lambda carry, metrics: [(jax.tree.map(lambda x: x[m], metrics), carry[1].diverged_at[m])
                                    for m in range(len(members))]
    carry, written = runner.train_loop(members, carry, chunk, views, checkpoint_path, started, compile_s,
                                       progress, resume, tensorboard)
    gait = sweep.gait(carry)
    for m, member in enumerate(members):
        document = written[m]
        document["sweep"] = {"fields": sweep.fields, "values": [_value(member.config, f) for f in sweep.fields],
                             "members": len(sweep.grid), "vmapped": sweep.vmapped}
        documents.finish(member, document, jax.tree.map(lambda x: x[m], gait),
                         jax.tree.map(lambda x: np.asarray(x[m]), carry[1].agent_state))
    runner.remove_checkpoints(checkpoint_path)
    return written
