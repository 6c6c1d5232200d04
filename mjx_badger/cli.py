"""Command line: `python -m mjx_badger {train,reproduce,figures,realtime,list}`.

Every argument is checked before anything is compiled; bad input gets one message naming
the valid choices and exit code 2.
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

from mjx_badger import enable_compilation_cache
from mjx_badger.actions import APPROACHES
from mjx_badger.agents import ALGORITHMS
from mjx_badger.experiments import EXPERIMENTS, PROFILES, result_name
from mjx_badger.protocols import FIELDS, PROTOCOLS
from mjx_badger.robot import ROBOTS
from mjx_badger.tasks import TASKS

# Seed-steps (one env step and one update each) per second of CrossQ with JT on the 2-core
# CPU this suite is developed on (benchmarks/bench_spine.py); only used to print an
# estimate before a long run starts, counting updates as the cost.
CPU_SEED_STEPS_PER_S = 174.0


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def writable_dir(parser: argparse.ArgumentParser, path: Path, what: str) -> Path:
    """Create `path` if needed and prove it is writable, or exit 2 with a message."""
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".write-test-{os.getpid()}"
        probe.write_text("")
        probe.unlink()
    except OSError as error:
        parser.error(f"{what} {str(path)!r} is not writable: {error.strerror or error}")
    return path


def name_value(text: str) -> tuple:
    """NAME=VALUE with VALUE read as a Python literal (a bare word stays a string)."""
    import ast

    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE; got {text!r}")
    try:
        parsed = ast.literal_eval(value)
    except (ValueError, SyntaxError):
        parsed = value  # a bare word such as thesis-text or butterworth
    return name, tuple(parsed) if isinstance(parsed, list) else parsed


def protocol_change(text: str) -> tuple:
    """FIELD=VALUE, one protocol field set by hand (a one-factor swap)."""
    field, value = name_value(text) if "=" in text else (text, None)
    if "=" not in text or field not in FIELDS:
        raise argparse.ArgumentTypeError(f"expected FIELD=VALUE with FIELD one of: {', '.join(FIELDS)}; got {text!r}")
    return field, value


def add_protocol_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--protocol", choices=list(PROTOCOLS), default="thesis-code",
                        help="thesis-code: as the thesis's released code ran it; thesis-text: as the thesis reads")


def add_configuration_arguments(parser: argparse.ArgumentParser) -> None:
    """--approach, --algo and --task, shared by the commands that train one configuration."""
    parser.add_argument("--approach", choices=list(APPROACHES), default="jt-oef")
    parser.add_argument("--algo", choices=list(ALGORITHMS), default="crossq")
    parser.add_argument("--task", choices=list(TASKS), default="forward")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m mjx_badger", description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)

    train = commands.add_parser("train", help="train one configuration over many seeds in one vmapped program")
    add_configuration_arguments(train)
    train.add_argument("--seeds", type=positive_int, default=3, help="number of seeds, run in parallel")
    train.add_argument("--first-seed", type=int, default=0)
    train.add_argument("--steps", type=positive_int, default=50_000, help="environment steps per seed")
    train.add_argument("--chunk-steps", type=positive_int, default=1_000)
    train.add_argument("--warmup-steps", type=positive_int, default=1_000)
    train.add_argument("--eval-steps", type=positive_int, default=400)
    add_protocol_argument(train)
    train.add_argument("--set", dest="changes", type=protocol_change, action="append", default=[], metavar="FIELD=VALUE",
                       help="change one protocol field (repeatable), e.g. --set action_delay=False")
    for what, example in (("approach", "cutoff_hz=2.0"), ("algo", "learning_rate=0.001"),
                          ("task", "target_velocity=0.3")):
        train.add_argument(f"--{what}-param", dest=f"{what}_params", type=name_value, action="append", default=[],
                           metavar="NAME=VALUE", help=f"one {what} parameter (repeatable), e.g. {example}; "
                                                      "`list` shows which each takes")
    train.add_argument("--robot", choices=list(ROBOTS), default="hb40",
                       help="hb40: the thesis code's model; hb40-v1: this suite's first (JT approaches only)")
    train.add_argument("--out", type=Path, default=Path("results"), help="folder for the results file")
    train.add_argument("--quiet", action="store_true", help="no progress bar")

    reproduce = commands.add_parser("reproduce", help="run the thesis experiments of a profile, then draw figures")
    reproduce.add_argument("--profile", choices=list(PROFILES), default="quick")
    add_protocol_argument(reproduce)
    reproduce.add_argument("--experiments", nargs="+", choices=list(EXPERIMENTS), default=list(EXPERIMENTS))
    reproduce.add_argument("--results-dir", type=Path, default=Path("results"))
    reproduce.add_argument("--figures-dir", type=Path, default=Path("figures"))
    reproduce.add_argument("--force", action="store_true", help="rerun runs whose complete results exist")

    figures = commands.add_parser("figures", help="draw figures from existing results")
    figures.add_argument("--profile", choices=list(PROFILES), default="quick")
    add_protocol_argument(figures)
    figures.add_argument("--results-dir", type=Path, default=Path("results"))
    figures.add_argument("--figures-dir", type=Path, default=Path("figures"))

    realtime = commands.add_parser("realtime", help="train on one robot at wall-clock rate (a simulated HB40 here)")
    add_configuration_arguments(realtime)
    realtime.add_argument("--steps", type=positive_int, default=20_000, help="control steps, warm-up included")
    realtime.add_argument("--warmup-steps", type=positive_int, default=1_000)
    realtime.add_argument("--control-hz", type=float, default=None,
                          help="control rate (default: the algorithm's, 40 Hz CrossQ, 20 Hz the others)")
    realtime.add_argument("--target-velocity", type=float, default=0.25, help="forward task target (m/s)")
    realtime.add_argument("--planned-contacts", action="store_true",
                          help="CPG approaches: leg odometry from the planned stance legs, not all four")
    realtime.add_argument("--reset-seconds", type=float, default=2.0,
                          help="simulated manual reset after a safety stop (not counted as training time)")
    realtime.add_argument("--no-sensor-noise", action="store_true", help="simulated robot: perfect sensors")
    realtime.add_argument("--unthrottled", action="store_true",
                          help="learner updates flat out instead of the algorithm's updates per step")
    realtime.add_argument("--seed", type=int, default=0)
    realtime.add_argument("--out", type=Path, default=Path("results/realtime"), help="folder for results")
    realtime.add_argument("--restart", action="store_true", help="ignore a saved checkpoint and start over")
    realtime.add_argument("--quiet", action="store_true", help="no live view")

    claims = commands.add_parser("claims", help="score the thesis's simulation claims against existing results")
    claims.add_argument("--profile", choices=list(PROFILES), default="quick")
    claims.add_argument("--protocol", choices=list(PROTOCOLS), default=None, help="one protocol (default: both)")
    claims.add_argument("--results-dir", type=Path, default=Path("results"))
    claims.add_argument("--json", type=Path, default=None, help="also write the scoreboard here")
    claims.add_argument("--markdown", type=Path, default=None,
                        help="also write the protocols' scoreboards side by side as a Markdown table here")

    attribute = commands.add_parser("attribute", help="one-factor protocol swaps beside their baselines (2 seeds x 10k)")
    attribute.add_argument("--results-dir", type=Path, default=Path("results"))
    attribute.add_argument("--only", nargs="+", default=None, metavar="SWAP",
                           help="run only these swaps (names as `list` prints them)")

    commands.add_parser("list", help="list approaches, algorithms, tasks, experiments, profiles and protocols")
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    enable_compilation_cache()
    if args.command == "list":
        for title, names in (("approaches", APPROACHES), ("algorithms", ALGORITHMS), ("tasks", TASKS),
                             ("experiments", EXPERIMENTS), ("profiles", PROFILES), ("protocols", PROTOCOLS),
                             ("protocol fields", FIELDS), ("robots", ROBOTS), ("attribution swaps", _swap_names())):
            print(f"{title}: {', '.join(names)}")
        from mjx_badger import spec, tasks

        print("approach parameters: " + "; ".join(f"{name}: {', '.join(a.params)}"
                                                  for name, a in APPROACHES.items() if a.params))
        print("task parameters: " + "; ".join(f"{name}: {', '.join(tasks.task_params(name))}"
                                              for name in TASKS if tasks.task_params(name)))
        print(f"algorithm parameters: {', '.join(spec.AGENT_FIELDS)}")
        return 0
    if args.command == "train":
        if args.warmup_steps >= args.steps:
            parser.error(f"--warmup-steps ({args.warmup_steps}) must be smaller than --steps ({args.steps})")
        if args.chunk_steps > args.steps:
            parser.error(f"--chunk-steps ({args.chunk_steps}) must not exceed --steps ({args.steps})")
        try:
            config = train_config(args)  # checked when built
        except ValueError as error:
            parser.error(str(error))
        writable_dir(parser, args.out, "output folder")
        return train_command(args, config)
    if args.command == "realtime":
        from mjx_badger.realtime.loop import RealtimeConfig

        try:  # checked when built
            config = RealtimeConfig(approach=args.approach, algo=args.algo, task=args.task, steps=args.steps,
                                    warmup_steps=args.warmup_steps, control_hz=args.control_hz,
                                    target_velocity=args.target_velocity, planned_contacts=args.planned_contacts,
                                    unthrottled=args.unthrottled, seed=args.seed)
        except ValueError as error:
            parser.error(str(error))
        if args.warmup_steps >= args.steps:
            parser.error(f"--warmup-steps ({args.warmup_steps}) must be smaller than --steps ({args.steps})")
        if args.reset_seconds < 0:
            parser.error("--reset-seconds must not be negative")
        writable_dir(parser, args.out, "output folder")
        return realtime_command(args, config)
    if args.command == "claims":
        return claims_command(args)
    if args.command == "attribute":
        from mjx_badger.attribution import SWAPS_BY_NAME

        unknown = set(args.only or ()) - set(SWAPS_BY_NAME)
        if unknown:
            parser.error(f"unknown swap(s) {sorted(unknown)}; choose from: {', '.join(SWAPS_BY_NAME)}")
        writable_dir(parser, args.results_dir, "results folder")
        return attribute_command(args)
    if args.command == "reproduce":
        writable_dir(parser, args.results_dir, "results folder")
        writable_dir(parser, args.figures_dir, "figures folder")
        return reproduce_command(args)
    writable_dir(parser, args.figures_dir, "figures folder")
    return figures_command(args)


def realtime_command(args, config) -> int:
    from mjx_badger import plots
    from mjx_badger.realtime import loop
    from mjx_badger.realtime.simulated import SensorNoise, SimulatedHB40

    # A real robot's adapter (interface.Robot) goes here in place of the simulated one.
    bot = SimulatedHB40(noise=None if args.no_sensor_noise else SensorNoise(), reset_seconds=args.reset_seconds,
                        seed=args.seed, spec=config.robot_spec)
    try:
        document = loop.run(config, bot, args.out, resume=not args.restart, view=not args.quiet)
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if document["steps"]:
        path = plots.realtime_figure(document, loop.load_trace(args.out, config), args.out / f"{config.name}.png")
        print(f"figure: {path}")
    return 0


def train_config(args):
    from mjx_badger.train import TrainConfig

    return TrainConfig(approach=args.approach, algo=args.algo, task=args.task, total_steps=args.steps,
                       chunk_steps=args.chunk_steps, warmup_steps=args.warmup_steps, eval_steps=args.eval_steps,
                       protocol=args.protocol, protocol_changes=tuple(args.changes), robot=args.robot,
                       approach_params=tuple(args.approach_params), algo_params=tuple(args.algo_params),
                       task_params=tuple(args.task_params))


def train_command(args, config) -> int:
    from mjx_badger import runner

    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    out = args.out / f"{args.approach}_{args.algo}_{args.task}.json"
    print(f"protocol {args.protocol}, robot {args.robot}" + "".join(f", {k}={v!r}" for k, v in args.changes))
    document = runner.run(config, seeds, out, progress=not args.quiet)
    print(f"wrote {out} ({document['wall_clock']['seed_steps_per_s']} seed-steps/s, "
          f"compile {document['wall_clock']['compile_s']} s)")
    return 0


def overall_progress(index: int, runs: int, done: float, total: float, elapsed_s: float) -> str:
    """'run i of n, p % of the work done, ~t left': the ETA at the rate measured so far (none before a run ends)."""
    line = f"run {index + 1} of {runs}, {100 * done / max(total, 1):.0f} % of the gradient updates done"
    if done > 0 and elapsed_s > 0:
        left_h = (total - done) * elapsed_s / done / 3600
        line += f", ~{left_h:.1f} h left at the rate so far"
    return line


def reproduce_command(args) -> int:
    from mjx_badger import claims, plots, results, runner

    profile = PROFILES[args.profile]
    folder = args.results_dir / args.profile / args.protocol
    todo = []
    for name in args.experiments:
        experiment = EXPERIMENTS[name]
        for run in experiment.runs:
            path = folder / name / result_name(run)
            config = experiment.train_config(run, args.profile, args.protocol)
            if not args.force and _same_run(path.parent, config, list(range(profile.seeds)), path.name):
                print(f"skip {path}: complete results of this configuration exist (--force reruns)")
                continue
            todo.append((experiment, run, path))
    work = [experiment.steps(run, args.profile) * ALGORITHMS[run.algo]().updates_per_step * profile.seeds
            for experiment, run, _ in todo]
    updates = sum(work)
    print(f"profile {args.profile}, protocol {args.protocol}: {len(todo)} runs x {profile.seeds} seeds, {updates:,} gradient updates in all; "
          f"about {updates / CPU_SEED_STEPS_PER_S / 3600:.1f} h on a 2-core CPU, plus ~1 min compile per run")
    started = time.perf_counter()
    for index, (experiment, run, path) in enumerate(todo):
        print(overall_progress(index, len(todo), sum(work[:index]), updates, time.perf_counter() - started),
              flush=True)
        config = experiment.train_config(run, args.profile, args.protocol)
        seeds = list(range(profile.seeds))
        twin = _same_run(folder, config, seeds)
        if twin is not None and not args.force:
            # Experiments share runs (CrossQ JT-NF forward is in two); a run is deterministic per seed.
            print(f"reuse {twin} for {path}: the same configuration and seeds")
            results.write(path, results.read(twin))
            continue
        runner.run(config, seeds, path, progress=sys.stderr.isatty() or os.environ.get("CI") is None)
    for path in plots.draw(folder, args.figures_dir, args.profile, args.experiments, args.protocol):
        print(f"wrote {path}")
    print(f"done in {(time.perf_counter() - started) / 60:.1f} min")
    print()
    boards = {name: claims.score(args.results_dir / args.profile, name) for name in PROTOCOLS}
    print(claims.scoreboard_text(boards[args.protocol], args.profile, args.protocol))
    write_scoreboard_markdown(args.figures_dir / f"claims_{args.profile}.md", boards, args.results_dir / args.profile)
    return 0


def _same_run(folder: Path, config, seeds, pattern: str | None = None):
    """A complete results file matching `pattern` under `folder` for exactly this configuration and seeds."""
    from mjx_badger import results

    from mjx_badger.train import TrainConfig

    as_stored = lambda c: json.loads(json.dumps(results.config_dict(c)))  # tuples become lists
    wanted, defaults = as_stored(config), as_stored(TrainConfig())
    pattern = pattern or f"*/{config.approach}_{config.algo}_{config.task}.json"
    for path in sorted(folder.glob(pattern)):
        document = results.read(path)
        # A field added after a file was written counts as its default value.
        stored = {**{k: defaults[k] for k in wanted if k not in document["config"]}, **document["config"]}
        if document.get("complete") and stored == wanted and document["seeds"] == seeds:
            return path
    return None


def figures_command(args) -> int:
    from mjx_badger import plots

    folder = args.results_dir / args.profile / args.protocol
    written = plots.draw(folder, args.figures_dir, args.profile, protocol=args.protocol)
    if not written:
        print(f"no results under {folder}", file=sys.stderr)
        return 1
    for path in written:
        print(f"wrote {path}")
    return 0


def claims_command(args) -> int:
    from mjx_badger import claims, results

    names = [args.protocol] if args.protocol else list(PROTOCOLS)
    boards = {name: claims.score(args.results_dir / args.profile, name) for name in names}
    for name, board in boards.items():
        print(claims.scoreboard_text(board, args.profile, name))
        print(f"  wall time: {results.wall_time_words(args.results_dir / args.profile / name)}")
        print()
    if args.markdown:
        write_scoreboard_markdown(args.markdown, boards, args.results_dir / args.profile)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({name: [v.as_dict() for v in board] for name, board in boards.items()},
                                        indent=1))
    return 0


def write_scoreboard_markdown(path: Path, boards: dict, profile_folder: Path) -> None:
    """The side-by-side scoreboard the README quotes, with each protocol's wall time under it."""
    from mjx_badger import claims, results

    times = "; ".join(f"{name}: {results.wall_time_words(profile_folder / name)}" for name in boards)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(claims.scoreboard_markdown(boards) + f"\nWall time on this machine: {times}.\n")
    print(f"wrote {path}")


def _swap_names():
    from mjx_badger.attribution import SWAPS_BY_NAME

    return [f"'{name}'" for name in SWAPS_BY_NAME]


def attribute_command(args) -> int:
    from mjx_badger import attribution, results, runner

    swaps = tuple(swap for swap in attribution.SWAPS if args.only is None or swap.name in args.only)
    todo = list(attribution.planned(args.results_dir, swaps))
    seeds = list(range(attribution.PROFILE.seeds))
    for swap, run, config, path in todo:
        if path.exists() and results.read(path).get("complete"):
            print(f"skip {path}: complete")
            continue
        runner.run(config, seeds, path, progress=sys.stderr.isatty() or os.environ.get("CI") is None)
    print(attribution.table(args.results_dir))
    return 0
