"""A training run's results documents as it writes them: new, a chunk at a time, resumed from the file an
interrupted run left, and completed with the gait record, the saved policy and the agents."""

import json
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
from tqdm import tqdm

from mjx_badger.core.cluster import gather, writes
from mjx_badger.core.validation import Refused
from mjx_badger.learning import checkpoints
from mjx_badger.learning.config import TrainConfig
from mjx_badger.records import policy, results


class Member(NamedTuple):
    """One results file a program writes: its configuration, seeds, path and (concrete) environment."""

    config: TrainConfig
    seeds: list
    out_path: Path
    env: object


def new(member: Member, started: str, compile_s: float) -> dict:
    """A member's results document before its first chunk (schema in records/results.py)."""
    return {
        "schema": results.SCHEMA,
        "config": results.config_dict(member.config),
        "seeds": list(member.seeds),
        "complete": False,
        "steps": [],
        "sim_minutes": [],
        "metrics": {},
        "wall_clock": {"started": started, "compile_s": round(compile_s, 2)},
        "versions": results.versions(),
        "git_commit": results.git_commit(),
        "evaluation_holds_command": True,  # sim/evaluation.py holds each run's command past an episode's end
    }


def add_chunk(document: dict, member: Member, own: dict, diverged_at, steps: int, clock: dict) -> None:
    """A chunk's metrics (`own`, a leading seed axis) and the clock after it, appended to a member's document;
    `clock` holds run_s, checkpoint_s and every member's seed count."""
    document["steps"].append(steps)
    document["sim_minutes"].append(round(steps / member.env.control_hz / 60, 4))
    for name, values in own.items():
        document["metrics"].setdefault(name, []).append(np.asarray(values, dtype=float).round(5).tolist())
    document["complete"] = False  # until `finish` has written the policy and agents too
    note_divergence(document, gather(diverged_at), member.out_path)
    document["wall_clock"].update(updated=results.now(), run_s=round(clock["run_s"], 2),
                                  checkpoint_s=round(clock["checkpoint_s"], 2),
                                  seed_steps_per_s=round(steps * clock["seeds"] / clock["run_s"], 1))
    document["hardware"] = results.hardware()


def landed(path: Path, config: TrainConfig, seeds: list, since: str | None = "") -> dict | None:
    """The complete results document at `path` for exactly this configuration and seeds, started `since` (an ISO
    time; "" for any, None for none), else None (a field added after the file was written counts as its default)."""
    document = results.read_or_skip(path) if since is not None and Path(path).is_file() else None
    if document is None or not document.get("complete") or document["seeds"] != list(seeds):
        return None
    if document.get("wall_clock", {}).get("started", "") < since:
        return None
    as_stored = lambda c: json.loads(json.dumps(results.config_dict(c)))  # tuples become lists
    wanted, defaults = as_stored(config), as_stored(TrainConfig())
    stored = {**{k: defaults[k] for k in wanted if k not in document["config"]}, **document["config"]}
    return document if stored == wanted else None


def check_resumable(path: Path) -> None:
    """Refused, before anything compiles, if a results file to resume from is there but cannot be read."""
    if Path(path).exists():
        previous(path, None)


def finish(member: Member, document: dict, gait: dict, agent_states) -> dict:
    """The results file completed: the gait record, the saved policy and the agents beside it."""
    document["gait"] = gait_record(member, gait)
    document["agents"] = checkpoints.save_agents(member.out_path, agent_states).name  # every process: orbax's own
    numpy_policy = not policy.unsupported(document["config"]["agent"])  # a newer agent's network: its agents only
    if numpy_policy:
        document["policy"] = policy.path_for(member.out_path).name
    actor = gather((agent_states.actor_params, agent_states.actor_stats))  # every process takes part
    if writes():
        if numpy_policy:
            save_policy(member, actor, document)
        document["complete"] = True  # last: a run stopped before this point resumes from its checkpoint
        results.write(member.out_path, document)
    return document


def save_policy(member: Member, actor: tuple, document: dict) -> Path:
    """Every seed's final actor (parameters, statistics) beside the results file, in policy.py's NumPy format."""
    env = member.env
    params, stats = actor
    meta = {"seeds": document["seeds"], "config": document["config"], "control_hz": env.control_hz,
            "observation_layout": [list(block) for block in env.observation_layout],
            "observation_size": env.observation_size, "action_size": env.action_size}
    return policy.save(policy.path_for(member.out_path), params, stats, meta)


def previous(path: Path, fresh: dict | None) -> dict | None:
    """The incomplete results file of this very configuration and seeds at `path`, or None."""
    if not Path(path).exists():
        return None
    try:
        previous = results.read(path)
    except ValueError as error:
        raise Refused(f"cannot resume: {error}; move it away, or start the run over (train, sweep: --restart; "
                      "reproduce: --force)") from None
    if fresh is None:
        return previous
    same = previous["config"] == json.loads(json.dumps(fresh["config"])) and previous["seeds"] == fresh["seeds"]
    return previous if same and not previous.get("complete") else None


def truncated(document: dict, chunks: int) -> dict:
    """`document` as it was after `chunks` chunks (the rows past the checkpoint are run again)."""
    document["steps"], document["sim_minutes"] = document["steps"][:chunks], document["sim_minutes"][:chunks]
    document["metrics"] = {name: rows[:chunks] for name, rows in document["metrics"].items()}
    return document


def note_divergence(document: dict, diverged_at, out_path: Path) -> None:
    """Record each seed's `diverged_at_step` (train.py freezes such a seed) and say so once when one diverges."""
    steps = [None if step < 0 else int(step) for step in np.asarray(diverged_at).reshape(-1)]
    before = document.get("diverged_at_step") or [None] * len(steps)
    for seed, old, new in zip(document["seeds"], before, steps):
        if old is None and new is not None:
            tqdm.write(f"{out_path.name}: seed {seed} went non-finite by step {new}; frozen there, the others go on",
                       file=sys.stderr)
    document["diverged_at_step"] = steps


def gait_record(member: Member, trace: dict) -> dict:
    """Foot contacts and forward velocity at the physics rate from a deterministic run after training (`trace`)."""
    env = member.env
    return {
        "physics_dt": env.mj_model.opt.timestep,
        "seconds": member.config.gait_seconds / 2,
        "command": list(map(float, next(iter(env.task.eval_commands.values())))),
        "contacts": np.asarray(trace["contacts"], dtype=int).tolist(),
        "forward_velocity": np.asarray(trace["forward_velocity"], dtype=float).round(4).tolist(),
    }
