"""Results files: one JSON document per training run, rewritten after every chunk.

Schema `mjx_badger.results/2` (files of schema 1 are read into it: `upgrade`):
    schema        "mjx_badger.results/2"
    config        the TrainConfig, with its resolved env and agent settings: config.protocol is
                  "thesis-code" or "thesis-text", config.protocol_changes the one-factor swaps
                  as [field, value] pairs, config.env.protocol every protocol field
    seeds         list of int, one per vmapped run
    complete      false until the last chunk is written (an interrupted run stays readable)
    steps         environment steps per seed at the end of each chunk, list (chunks,)
    sim_minutes   the same in simulated minutes (steps / control frequency / 60)
    metrics       name -> list (chunks,) of list (seeds,); null where undefined; the evaluation's
                  are evaluation.py's eval/{run}/{metric} and eval/{metric} (files written before
                  that schema are read into it: `upgrade`)
                  (e.g. train/episode_return in a chunk where no episode ended); falls are
                  cumulative: train/falls as the protocol counts them, train/falls_total every
                  termination, train/would_falls the times the termination rule started firing on a
                  finite state (CPG under thesis-code never terminates), train/blowups non-finite
                  physics states (schema 1 counted a blow-up as a would-be fall too)
    diverged_at_step  per seed: null, or the step at whose chunk end its agent or metrics went
                  non-finite; the seed was frozen there (its metrics are null from then) while the
                  others went on, and figures, tables and claims leave it out (`healthy`)
    policy        after the last chunk: the file name of every seed's final actor (policy.py's format)
    published_policy_seeds  only in a reference copy (publish.py), which has no agents folder: the
                  seeds its policy file still holds (the best one)
    agents        after the last chunk: the folder of every seed's whole final agent, critic and
                  optimiser states included (checkpoints.save_agents / load_agents)
    gait          after the last chunk: a deterministic run under the task's first evaluation
                  command, its second half at the physics rate: physics_dt, seconds, command,
                  contacts (seeds, T, 4) of 0/1 per foot FL, FR, RL, RR, forward_velocity (seeds, T)
    wall_clock    started / updated (ISO 8601), compile_s, run_s, checkpoint_s (saving the carry,
                  checkpoints.py), seed_steps_per_s
    versions      python and package versions
    git_commit    commit of the code that ran, "+dirty" when it had local changes
    evaluation_holds_command  true where each evaluation run kept its command past an episode's time limit
                  (absent in files from before: an omnidirectional one evaluated longer than an episode restarted
                  under a command its task drew; analysis.evaluation_crossed_episode)
    hardware      platform, cpu count, jax devices, peak resident memory (MiB)
"""

import dataclasses
import datetime
import json
import math
import os
import platform
import resource
import subprocess
import sys
from importlib import metadata
from pathlib import Path

from mjx_badger.agents.config import ADDED_LATER
from mjx_badger.core import safe_io
from mjx_badger.core.paths import REPOSITORY

SCHEMA = "mjx_badger.results/2"
OLDER_SCHEMAS = ("mjx_badger.results/1",)
PACKAGES = ("jax", "jaxlib", "mujoco", "mujoco-mjx", "brax", "flax", "optax", "numpy")


def what(docstring: str) -> str:
    """A script's docstring's first paragraph on one line: the "what" of the results file it writes."""
    return " ".join(docstring.split("\n\n")[0].split())


def now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def versions() -> dict:
    """Python and package versions."""
    found = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            found[name] = None
    return found


def git_commit() -> str:
    """HEAD of the repository this package lives in, or 'unknown'."""
    root = REPOSITORY
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True,
                                check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return commit + ("+dirty" if dirty else "")


def peak_memory_mib() -> float:
    """Peak resident memory of this process (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def hardware() -> dict:
    import jax

    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "jax_devices": [str(d) for d in jax.devices()],
        "device_kind": jax.devices()[0].device_kind,
        "matmul_precision": jax.config.jax_default_matmul_precision,
        "peak_memory_mib": round(peak_memory_mib(), 1),
    }


# Fields added after results were first committed, with the value that means "as before": left out at that
# value, so that a run without them writes (and rebuilds from) the same document as before they existed.
LATER_ENV_FIELDS = {"sensing": None, "conditions": None}
LATER_RUN_FIELDS = {"conditions": "sim", "condition_changes": (), "num_envs": 1}
# The agent settings added with the newer agents (agents.config.ADDED_LATER) are left out at their defaults too.


def config_dict(config) -> dict:
    """A TrainConfig as plain JSON data, with its resolved env and agent settings."""
    data = dataclasses.asdict(config)
    data = {k: v for k, v in data.items() if k not in LATER_RUN_FIELDS or v != LATER_RUN_FIELDS[k]}
    data["env"] = dataclasses.asdict(config.env_config)
    data["env"] = {k: v for k, v in data["env"].items() if k not in LATER_ENV_FIELDS or v != LATER_ENV_FIELDS[k]}
    agent = config.agent_config
    defaults = {f.name: f.default for f in dataclasses.fields(agent)}
    data["agent"] = {k: v for k, v in dataclasses.asdict(agent).items()
                     if k not in ADDED_LATER or v != defaults[k]}  # a thesis agent's document as it always read
    return data


def _clean(value):
    """JSON has no NaN: undefined numbers become null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [_clean(v) for v in value]
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    return value


def write(path: Path, document: dict) -> None:
    """Write atomically, so an interrupted run never leaves a half-written file."""
    safe_io.write_text(path, json.dumps(_clean(document), indent=1))


def read(path: Path, leave_out_diverged: bool = False) -> dict:
    """The results document at `path` in today's schema, its diverged seeds left out if asked (`healthy`).

    ValueError naming the file for one that cannot be read, is cut short or was edited out of shape.
    """
    try:
        document = json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"{path} cannot be read: {getattr(error, 'strerror', None) or error}") from None
    if not isinstance(document, dict) or document.get("schema") not in (SCHEMA, *OLDER_SCHEMAS):
        raise ValueError(f"{path}: not a {SCHEMA} results file")
    problem = shape_problem(document)
    if problem:
        raise ValueError(f"{path}: damaged results file ({problem})")
    document = upgrade(document)
    return healthy(document) if leave_out_diverged else document


def shape_problem(document: dict) -> str:
    """'' or what in `document` is not where or what the schema says (a hand edit, a partial copy)."""
    number = lambda v: v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))
    for key, kind in (("config", dict), ("seeds", list), ("steps", list), ("metrics", dict)):
        if not isinstance(document.get(key, kind()), kind):
            return f"{key} is not a {kind.__name__}"
    seeds, steps = document.get("seeds", []), document.get("steps", [])
    if not all(isinstance(s, int) and not isinstance(s, bool) for s in seeds) or len(set(seeds)) != len(seeds):
        return "seeds are not distinct integers"
    if not all(number(s) for s in steps):
        return "steps are not numbers"
    for name, rows in document.get("metrics", {}).items():
        if not isinstance(rows, list) or len(rows) != len(steps):
            return f"metric {name} has not one row per chunk"
        width = len(seeds) if "seeds" in document else None  # a sketch of a document (tests) may leave them out
        if not all(isinstance(row, list) and len(row) == (width or len(row)) and all(map(number, row)) for row in rows):
            return f"metric {name} has not one number per seed in every row"
    for key, kind in (("complete", bool), ("policy", str), ("wall_clock", dict), ("gait", dict),
                      ("diverged_at_step", list), ("evaluation_holds_command", bool)):
        if document.get(key) is not None and not isinstance(document[key], kind):
            return f"{key} is not a {kind.__name__}"
    if document.get("diverged_at_step") is not None and len(document["diverged_at_step"]) != len(seeds):
        return "diverged_at_step has not one entry per seed"
    return ""


def read_or_skip(path: Path, leave_out_diverged: bool = False) -> dict | None:
    """The document at `path`, or None after a line on stderr naming the file and why it is skipped."""
    try:
        return read(path, leave_out_diverged)
    except ValueError as error:
        print(f"skipping {error}", file=sys.stderr)
        return None


def upgrade(document: dict) -> dict:
    """A document in today's schema: older files named the one forward run's desired velocity
    eval/forward_velocity and kept no means of the omni runs' velocities, and schema 1 counted
    every blow-up as a would-be fall too."""
    metrics = document.get("metrics", {})
    if document.get("schema") in OLDER_SCHEMAS and "train/would_falls" in metrics and "train/blowups" in metrics:
        # A schema-1 blow-up added one would-be fall unless the rule was already firing (then none), so
        # this is exact where episodes end on a fall or nothing blew up, and a lower bound otherwise.
        metrics["train/would_falls"] = [
            [None if w is None or b is None else max(w - b, 0.0) for w, b in zip(would, blowups)]
            for would, blowups in zip(metrics["train/would_falls"], metrics["train/blowups"])]
    document["schema"] = SCHEMA
    if "eval/forward_velocity" in metrics and "eval/desired_velocity" not in metrics:
        metrics["eval/desired_velocity"] = metrics.pop("eval/forward_velocity")
    for name in ("desired_velocity", "lateral_velocity", "yaw_rate"):
        per_run = [v for k, v in metrics.items() if k.startswith("eval/") and k.endswith(f"/{name}")]
        if f"eval/{name}" not in metrics and per_run:
            metrics[f"eval/{name}"] = [[None if None in seeds else sum(seeds) / len(seeds) for seeds in zip(*rows)]
                                       for rows in zip(*per_run)]
    return document


def diverged(document: dict) -> dict:
    """{seed: step it diverged at} of the seeds frozen for non-finite numbers (train.py)."""
    steps = document.get("diverged_at_step") or []
    return {seed: step for seed, step in zip(document.get("seeds", []), steps) if step is not None}


def healthy(document: dict) -> dict:
    """The document without its diverged seeds, which `left_out` then names; unchanged if none diverged."""
    gone = diverged(document)
    if not gone:
        return document
    keep = [i for i, seed in enumerate(document["seeds"]) if seed not in gone]
    pick = lambda rows: [[row[i] for i in keep] for row in rows]
    kept = dict(document, seeds=[document["seeds"][i] for i in keep],
                diverged_at_step=[None] * len(keep),
                metrics={name: pick(rows) for name, rows in document["metrics"].items()},
                left_out=[{"seed": seed, "diverged_at_step": step} for seed, step in gone.items()])
    if document.get("gait"):
        gait = document["gait"]
        kept["gait"] = dict(gait, contacts=[gait["contacts"][i] for i in keep],
                            forward_velocity=[gait["forward_velocity"][i] for i in keep])
    return kept


def left_out_words(document: dict) -> str:
    """'' or e.g. 'seed 2 left out: diverged at step 12000' for a document `healthy` has trimmed."""
    gone = document.get("left_out") or []
    return "; ".join(f"seed {g['seed']} left out: diverged at step {g['diverged_at_step']}" for g in gone)


# A run's own seconds in its wall_clock (a resumed run's compile is its last attempt's); its span from started to
# updated also holds the gaps between attempts.
OWN_SECONDS = ("compile_s", "run_s", "checkpoint_s")


def run_key(document: dict) -> str:
    """What makes two results files one run: `reproduce` copies a run two experiments share, clock and all."""
    return json.dumps([document.get("config"), document.get("seeds"), document.get("wall_clock")], sort_keys=True)


def wall_time(folder: Path, experiments: tuple | None = None) -> dict:
    """A run's own seconds (OWN_SECONDS) summed over the complete results files under `folder` (under its
    `experiments` subfolders only, if given), a copied run counted once."""
    # Not the run.json stamps inside a running or interrupted run's checkpoint folder.
    documents = [read_or_skip(path) for path in sorted(Path(folder).glob("**/*.json"))
                 if not any(part.endswith((".ckpt", ".agents")) for part in path.parent.parts)
                 and (experiments is None or path.relative_to(folder).parts[0] in experiments)]
    complete = [d for d in documents if d is not None and d.get("complete")]
    # A file without a clock (a hand-made one) is its own run.
    clocks = [d.get("wall_clock") or {} for d in {run_key(d) if d.get("wall_clock") else i: d
                                                  for i, d in enumerate(complete)}.values()]
    return {"runs": len(clocks), "copies": len(complete) - len(clocks),
            **{key: sum(c.get(key) or 0.0 for c in clocks) for key in OWN_SECONDS}}


def wall_time_words(folder: Path, experiments: tuple | None = None) -> str:
    """'N runs in H h (compile M min)', for scoreboards, the README and docs/results.md."""
    time = wall_time(folder, experiments)
    hours = sum(time[key] for key in OWN_SECONDS) / 3600
    runs = f"{time['runs']} run" + ("" if time["runs"] == 1 else "s")
    copies = f"; {time['copies']} more a copy of one of them" if time["copies"] else ""
    return f"{runs} in {hours:.2f} h (compile {time['compile_s'] / 60:.1f} min of it{copies})"
