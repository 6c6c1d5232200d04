"""`reproduce`: plan a profile's runs, skip or reuse the complete ones, estimate the time, run the rest, then draw,
render and score.

`command(args)` takes the checked `cli.experiments.Reproduce` (profile, protocol, experiments, results and figures folders,
force, tensorboard); everything it writes lies under those folders.
"""

import functools
import json
import shutil
import time
from pathlib import Path

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.core import cluster, launch, stops
from mjx_badger.experiments import eta
from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES, expand
from mjx_badger.learning import checkpoints, documents, programs, runner, tensorboard
from mjx_badger.learning.progress import progress_wanted, run_progress, time_left
from mjx_badger.outputs import plots, videos
from mjx_badger.protocol.protocols import PROTOCOLS
from mjx_badger.records import policy, results
from mjx_badger.scoring import claims, scoreboard

# Seed-steps (one env step and one update each) per second of CrossQ with JT on the 2-core
# CPU this suite is developed on (benchmarks/bench_spine.py); only used to print an
# estimate before a long run starts, counting updates as the cost.
CPU_SEED_STEPS_PER_S = 174.0


def command(args) -> int:
    """`reproduce`: SIGINT or SIGTERM stop it after the chunk at hand (or between runs), saved, to resume."""
    with stops.graceful():
        return _reproduce(args)


def _reproduce(args) -> int:
    folder = args.results_dir / args.profile / args.protocol
    names = expand(args.experiments)
    todo = plan(args, folder, names)
    work = announce(args, todo)
    started = time.perf_counter()
    run_all(args, folder, todo, work)
    if not cluster.writes() or not args.draw:  # process 0 of a jax.distributed run draws and scores
        return 0
    draw(args, folder, names)
    print(f"done in {(time.perf_counter() - started) / 60:.1f} min")
    print()
    score(args)
    return 0


def plan(args, folder: Path, names: tuple) -> list:
    """(experiment, run, results path) of every run to train: those without complete results of their configuration."""
    seeds = list(range(PROFILES[args.profile].seeds))
    todo = []
    for name in names:
        experiment = EXPERIMENTS[name]
        for run in experiment.runs:
            path = folder / name / experiment.result_name(run)
            config = experiment.train_config(run, args.profile, args.protocol)
            if not args.force and same_run(path.parent, config, seeds, path.name):
                print(f"skip {path}: complete results of this configuration exist (--force reruns)")
                continue
            todo.append((experiment, run, path))
    return todo


def announce(args, todo: list) -> list:
    """Print the plan's size and time estimate; returns each run's gradient updates, all seeds together."""
    profile = PROFILES[args.profile]
    work = [experiment.steps(run, args.profile) * ALGORITHMS[run.algo]().updates_per_step * profile.seeds
            for experiment, run, _ in todo]
    updates = sum(work)
    print(f"profile {args.profile}, protocol {args.protocol}: {len(todo)} runs x {profile.seeds} seeds, "
          f"{updates:,} gradient updates in all; "
          f"about {updates / CPU_SEED_STEPS_PER_S / 3600:.1f} h on a 2-core CPU, plus ~1-2 min compile per run")
    if args.profile == "full" and todo and args.launch.here:  # elsewhere this machine's speed says nothing
        print(measured_estimate(todo, args, profile.seeds), flush=True)
    return work


def run_all(args, folder: Path, todo: list, work: list) -> None:
    """Train the planned runs one after another (a run another experiment shares is copied), with the time left."""
    if not args.launch.here:
        return launch_all(args, folder, todo)
    profile = PROFILES[args.profile]
    updates = sum(work)
    configs = [experiment.train_config(run, args.profile, args.protocol) for experiment, run, _ in todo]
    seeds = list(range(profile.seeds))
    plans = [eta.planned(config, profile.seeds, copy=config in configs[:i] or same_run(folder, config, seeds)
                         is not None) for i, config in enumerate(configs)]
    done = []
    for index, ((experiment, run, path), config) in enumerate(zip(todo, configs)):
        if stops.requested():
            raise stops.Interrupted(stops.requested(), f"stopped by {stops.name(stops.requested())} before run "
                                    f"{index + 1} of {len(todo)}; the runs done are saved: run the same command "
                                    "again to go on")
        print(overall_progress(index, len(todo), sum(work[:index]), updates, eta.seconds_left(plans[index:], done)),
              flush=True)
        run_started = time.perf_counter()
        twin = same_run(folder, config, seeds)
        if twin is not None and not args.force:
            # Experiments share runs (CrossQ JT-NF forward is in two); a run is deterministic per seed.
            print(f"reuse {twin} for {path}: the same configuration and seeds")
            done.append(eta.Done(plans[index], 0.0, 0.0))
            if not cluster.writes():  # another process of a jax.distributed run copies it
                continue
            copy_run(twin, path)
            continue
        document = runner.run(config, seeds, path, progress=progress_wanted(), resume=not args.force,
                              tensorboard=args.tensorboard)
        # A resumed run trained only part of its work here: its rate is not this machine's.
        if document and document.get("wall_clock", {}).get("resumed_at_step") is None:
            train_s = document["wall_clock"].get("run_s", 0.0)
            done.append(eta.Done(plans[index], train_s, time.perf_counter() - run_started - train_s))


def launch_all(args, folder: Path, todo: list) -> None:
    """The planned runs as processes or cluster jobs, each configuration once; then the shared runs copied."""
    seeds = list(range(PROFILES[args.profile].seeds))
    since = results.now() if args.force else ""  # with --force what landed before is trained again
    jobs, copies, first = [], [], {}
    for experiment, run, path in todo:
        config = experiment.train_config(run, args.profile, args.protocol)
        key = json.dumps(results.config_dict(config), sort_keys=True)
        twin = None if args.force else same_run(folder, config, seeds)
        if twin is not None or key in first:
            copies.append((twin or first[key], path))
            continue
        first[key] = path
        if args.force:  # a requeued job must resume its own start, not an older run's checkpoint: those go first
            shutil.rmtree(checkpoints.folder(path), ignore_errors=True)
        jobs.append(launch.Job(str(path.relative_to(folder)), runner.run,
                               (config, seeds, path, False, True, args.tensorboard, since),
                               functools.partial(run_progress, path, config.num_chunks * config.chunk_steps)))
    print(f"{len(jobs)} runs to train ({args.launch.launcher}, {args.launch.runs_per_device} per device)", flush=True)
    try:
        args.launch.run(jobs, args.results_dir)
    finally:  # a run that landed is copied to the experiments sharing it, though another failed
        for twin, path in copies:
            if (results.read_or_skip(twin) or {}).get("complete"):
                print(f"reuse {twin} for {path}: the same configuration and seeds")
                copy_run(twin, path)


def draw(args, folder: Path, names: tuple) -> None:
    """The experiments' figures and tables, and the best seed's gait of each run, into the figures folder."""
    kept = []
    for path in plots.draw(folder, args.figures, args.profile, names, args.protocol, kept=kept):
        print(f"wrote {path}")
    for path in videos.draw(folder, args.figures, args.profile, names, args.protocol, kept=kept):
        print(f"wrote {path} (the best seed's gait, native MuJoCo)")
    for path, why in kept:
        print(f"kept {path}: {why}")


def score(args) -> None:
    """The claims of both protocols scored; this protocol's printed, both written side by side."""
    boards = {name: claims.score(args.results_dir / args.profile, name) for name in PROTOCOLS}
    print(scoreboard.scoreboard_text(boards[args.protocol], args.profile, args.protocol))
    scoreboard.write_markdown(args.figures / f"claims_{args.profile}.md", boards, args.results_dir / args.profile)


def overall_progress(index: int, runs: int, done: float, total: float, left_s: float | None) -> str:
    """'run i of n, p % of the gradient updates done, ~t left' (eta.py: no ETA before a run has ended)."""
    line = f"run {index + 1} of {runs}, {100 * done / max(total, 1):.0f} % of the gradient updates done"
    if left_s is not None:
        line += f", {time_left(left_s)}"
    return line


def measured_estimate(todo: list, args, seeds: int) -> str:
    """The time the runs in `todo` will take here, from one short timed chunk, with its share of evaluation,
    per algorithm and evaluation size among them (an omni run's eight evaluation commands about halve its rate)."""
    speed, seconds = {}, 0.0
    for experiment, run, _ in todo:
        config = experiment.train_config(run, args.profile, args.protocol)
        kind = (run.algo, len(config.make_task().eval_commands))
        if kind not in speed:
            print(f"timing a short {run.approach} {run.algo} {run.task} chunk on this machine ...", flush=True)
            speed[kind] = programs.measure_speed(config, list(range(seeds)), evaluation=True) | {"task": run.task}
        measured = speed[kind]
        seconds += experiment.steps(run, args.profile) * seeds / measured["seed_steps_per_s"] + measured["compile_s"]
    rates = ", ".join(f"{algo} {m['task']} {m['seed_steps_per_s']:.0f} seed-steps/s" for (algo, _), m in speed.items())
    return (f"measured here ({rates}; compile {max(m['compile_s'] for m in speed.values()):.0f} s at most): "
            f"about {seconds / 3600:.1f} h for " + ("this run" if len(todo) == 1 else f"these {len(todo)} runs"))


def copy_run(twin: Path, path: Path) -> None:
    """`twin`'s results at `path`, with what lies beside them: the saved policy (`evaluate`, `render` and
    `publish` read it), the agents and the event files."""
    results.write(path, results.read(twin))
    if policy.path_for(twin).is_file():
        shutil.copyfile(policy.path_for(twin), policy.path_for(path))
    for folder in (checkpoints.agents_folder, tensorboard.folder):
        if folder(twin).is_dir():
            shutil.copytree(folder(twin), folder(path), dirs_exist_ok=True)


def same_run(folder: Path, config, seeds, pattern: str | None = None):
    """A complete results file matching `pattern` under `folder` for exactly this configuration and seeds."""
    base = f"{config.approach}_{config.algo}_{config.task}"
    paths = folder.glob(pattern) if pattern else [*folder.glob(f"*/{base}.json"), *folder.glob(f"*/{base}__*.json")]
    return next((path for path in sorted(paths) if documents.landed(path, config, seeds) is not None), None)
