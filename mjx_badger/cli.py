"""Command line: `python -m mjx_badger {train,sweep,reproduce,figures,claims,publish,attribute,realtime,evaluate,render,
estimator,list}`.

tyro builds every option from the dataclasses below and the run specs they hold
(TrainConfig, RealtimeConfig), so each option is declared once, its docstring its help.
Every argument is checked before anything is compiled; bad input gets one line naming what
is wrong (and the valid choices) and exit code 2.
"""

import contextlib
import dataclasses
import io
import json
import re
import sys
from pathlib import Path
from typing import Annotated, Literal, Optional

import tyro

from mjx_badger import enable_compilation_cache, safe_io
from mjx_badger.actions import APPROACHES
from mjx_badger.agents import ALGORITHMS
from mjx_badger.estimator_commands import Estimator
from mjx_badger.experiments import EXPERIMENTS, GROUPS, PROFILES, expand
from mjx_badger.protocols import FIELDS, PROTOCOLS
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.robot import ROBOTS
from mjx_badger.tasks import TASKS
from mjx_badger.train import TrainConfig
from mjx_badger.validation import INT32_MAX, integer, number, writable_dir, writable_file

MAX_SEEDS = 1_000_000
"""More seeds than any machine holds; the memory check refuses far fewer on most."""
DESCRIPTION = "mjx_badger: the thesis's simulation experiments on MJX, their claims scored, and the on-robot loop."
Profile = Literal[tuple(PROFILES)]
ProtocolName = Literal[tuple(PROTOCOLS)]
ExperimentName = Literal[tuple(EXPERIMENTS) + tuple(GROUPS)]
Flat = tyro.conf.arg(name="")
"""A nested run spec whose fields are the command's own options (--approach, not --run.approach)."""


def check_seed_devices(seeds: int) -> None:
    """The seeds split evenly over this machine's devices (runner.seed_sharding), checked before any compile."""
    import jax

    from mjx_badger.runner import check_seeds_divide

    check_seeds_divide(seeds, jax.device_count())


@dataclasses.dataclass(frozen=True)
class Cluster:
    """Several processes, on one host or many, through jax.distributed; none of these: one process."""

    coordinator: Optional[str] = None
    """HOST:PORT of process 0, with --num-processes and --process-id (each process runs the same command)."""
    num_processes: Optional[int] = None
    """How many processes the cluster has (with --coordinator)."""
    process_id: Optional[int] = None
    """This process's number, 0..N-1 (with --coordinator)."""
    distributed: bool = False
    """Join the cluster JAX detects by itself (Slurm, Open MPI, Cloud TPU)."""

    def check(self) -> None:
        """ValueError for an incomplete or malformed address; joins nothing."""
        if self.coordinator is None and not self.distributed:
            if self.num_processes is not None or self.process_id is not None:
                raise ValueError("--num-processes and --process-id need --coordinator HOST:PORT")
            return
        if self.coordinator is not None:
            if self.num_processes is None or self.process_id is None:
                raise ValueError("--coordinator needs --num-processes and --process-id")
            host, _, port = self.coordinator.rpartition(":")
            if not host or not port.isdigit() or not 0 < int(port) < 65536:
                raise ValueError(f"--coordinator takes HOST:PORT with a port in 1..65535, not {self.coordinator!r}")
            integer("--num-processes", self.num_processes, 1, 4096)
            if not 0 <= self.process_id < self.num_processes:
                raise ValueError(f"--process-id must be in 0..{self.num_processes - 1}, not {self.process_id}")

    def start(self) -> None:
        """Join the cluster before JAX touches a device; ValueError for an incomplete address."""
        self.check()
        if self.coordinator is None and not self.distributed:
            return
        from mjx_badger import cluster

        cluster.join(self.coordinator, self.num_processes, self.process_id)


@dataclasses.dataclass(frozen=True)
class Runs:
    """What `train` and `sweep` share: the run, its seeds and where the results go."""

    run: Annotated[TrainConfig, Flat] = TrainConfig()
    seeds: int = 3
    """Number of seeds, vmapped in one program (in a sweep: per member)."""
    first_seed: int = 0
    """The first seed: the run trains seeds FIRST..FIRST+SEEDS-1."""
    out: Path = Path("results")
    """Folder for the results files."""
    quiet: bool = False
    """No progress bar."""
    restart: bool = False
    """Start over, though an interrupted run of this configuration left a checkpoint to resume from."""
    tensorboard: bool = True
    """Also write TensorBoard event files beside the results (<name>.tb/seed_<k>/)."""
    dry_run: bool = False
    """Check everything and print the plan with its memory estimate; train nothing."""

    @property
    def seed_list(self) -> list[int]:
        return list(range(self.first_seed, self.first_seed + self.seeds))

    def check_runs(self) -> None:
        if self.seeds <= 0:
            raise ValueError(f"--seeds must be a positive number, not {self.seeds}")
        integer("--seeds", self.seeds, 1, MAX_SEEDS)
        integer("--first-seed", self.first_seed, 0, INT32_MAX - self.seeds + 1)
        writable_dir(self.out, "output folder")


@dataclasses.dataclass(frozen=True)
class Train(Runs):
    """Train one configuration over many seeds in one vmapped program."""

    cluster: Annotated[Cluster, Flat] = Cluster()

    def check(self) -> None:
        from mjx_badger import memory

        self.check_runs()
        self.cluster.check()
        if not self.dry_run:  # joined before JAX touches a device, which the estimate does
            self.cluster.start()
        check_seed_devices(self.seeds)
        memory.check(self.run, self.seeds)

    def __call__(self) -> int:
        from mjx_badger import memory, runner

        config = self.run
        if self.dry_run:
            print(f"would train {config.name} ({config.protocol} protocol, robot {config.robot}): {self.seeds} seeds x "
                  f"{config.total_steps} steps in {config.num_chunks} chunks, into {self.out / (config.name + '.json')}")
            print(memory.words(config, self.seeds))
            return 0
        out = self.out / f"{config.name}.json"
        print(f"protocol {config.protocol}, robot {config.robot}"
              + "".join(f", {k}={v!r}" for k, v in config.protocol_changes))
        document = runner.run(config, self.seed_list, out, progress=not self.quiet, resume=not self.restart,
                              tensorboard=self.tensorboard)
        print(f"wrote {out} ({document['wall_clock']['seed_steps_per_s']} seed-steps/s, "
              f"compile {document['wall_clock']['compile_s']} s)")
        return 0


@dataclasses.dataclass(frozen=True)
class Sweep(Runs):
    """Train every combination of a grid of numeric parameters as one program; one results file per member."""

    out: Path = Path("results/sweep")
    """Folder for the members' results files."""
    vary: Annotated[tuple[str, ...], tyro.conf.UseAppendAction] = ()
    """GROUP.NAME=V1,V2,... with GROUP approach_params, algo_params or task_params; repeat for a grid."""
    grid: Optional[Path] = None
    """A JSON file {"GROUP.NAME": [values], ...}, combined with any --vary."""
    vmapped: int = 1
    """Members vmapped together: 1 gives each member's separate-run numbers to the bit; more is faster on a GPU."""

    def axes(self) -> tuple:
        from mjx_badger import sweep

        return (sweep.read_grid(self.grid) if self.grid else ()) + tuple(sweep.parse_axis(v) for v in self.vary)

    def check(self) -> None:
        from mjx_badger import memory, sweep

        self.check_runs()
        members = sweep.members(self.run, self.axes())
        sweep.check_groups(len(members), self.vmapped)
        memory.check(self.run, self.seeds, members=len(members))

    def __call__(self) -> int:
        from mjx_badger import memory, sweep

        if self.dry_run:
            members = sweep.members(self.run, self.axes())
            print(f"would sweep {len(members)} members of {self.run.name} x {self.seeds} seeds in groups of "
                  f"{min(self.vmapped, len(members))}, into {self.out}")
            print(memory.words(self.run, self.seeds, members=len(members)))
            return 0
        try:
            documents = sweep.run(self.run, self.axes(), self.seed_list, self.out, self.vmapped, progress=not self.quiet,
                                  resume=not self.restart, tensorboard=self.tensorboard)
        except ValueError as error:  # refused after building the members: shapes, or a field fixed when built
            print(f"error: {error}", file=sys.stderr)
            return 2
        for document in documents:
            print(f"wrote {self.out / document['policy'].replace('.policy.npz', '.json')}")
        print(f"{len(documents)} members x {self.seeds} seeds: {documents[0]['wall_clock']['seed_steps_per_s']} "
              f"seed-steps/s, compile {documents[0]['wall_clock']['compile_s']} s")
        return 0


@dataclasses.dataclass(frozen=True)
class Reproduce:
    """Run the thesis experiments of a profile (complete runs are kept), then draw figures and score the claims."""

    profile: Profile = "quick"
    """quick: a CPU in hours; full: the thesis's budgets, a GPU."""
    protocol: ProtocolName = "thesis-code"
    """thesis-code: as the thesis's released code ran it; thesis-text: as the thesis reads."""
    experiments: tuple[ExperimentName, ...] = ("simulation",)
    """Experiments, or groups of them: 'simulation' (the five simulation experiments) or 'real' (the real-world
    ones under on-robot conditions, §5.2)."""
    results_dir: Path = Path("results")
    """Where the runs are written (<results-dir>/<profile>/<protocol>/<experiment>/)."""
    figures_dir: Optional[Path] = None
    """Where figures, tables and the scoreboard go (default: <results-dir>/figures; the committed ones: figures)."""
    force: bool = False
    """Rerun runs whose complete results exist, and start interrupted ones over instead of resuming them."""
    tensorboard: bool = True
    """Also write TensorBoard event files beside the results (<name>.tb/seed_<k>/)."""
    cluster: Annotated[Cluster, Flat] = Cluster()

    @property
    def figures(self) -> Path:
        return self.figures_dir if self.figures_dir is not None else self.results_dir / "figures"

    def check(self) -> None:
        from mjx_badger import memory

        if not self.experiments:
            raise ValueError(f"--experiments needs at least one name; choose from {', '.join((*EXPERIMENTS, *GROUPS))}")
        if len(set(self.experiments)) != len(self.experiments):
            raise ValueError(f"--experiments names an experiment twice: {' '.join(self.experiments)}")
        writable_dir(self.results_dir, "results folder")
        writable_dir(self.figures, "figures folder")
        self.cluster.start()  # before JAX touches a device, which the estimate does
        seeds = PROFILES[self.profile].seeds
        check_seed_devices(seeds)
        for name in expand(self.experiments):  # one run at a time: the largest decides
            experiment = EXPERIMENTS[name]
            for run in experiment.runs:
                memory.check(experiment.train_config(run, self.profile, self.protocol), seeds)

    def __call__(self) -> int:
        from mjx_badger import reproduce

        return reproduce.command(self)


@dataclasses.dataclass(frozen=True)
class Figures:
    """Draw the figures and tables of existing results."""

    profile: Profile = "quick"
    protocol: ProtocolName = "thesis-code"
    results_dir: Path = Path("results")
    """Where the results are read from (<results-dir>/<profile>/<protocol>/<experiment>/; the committed ones:
    figures/data)."""
    figures_dir: Optional[Path] = None
    """Where they go (default: <results-dir>/figures; the committed ones: figures)."""

    @property
    def figures(self) -> Path:
        return self.figures_dir if self.figures_dir is not None else self.results_dir / "figures"

    def check(self) -> None:
        writable_dir(self.figures, "figures folder")

    def __call__(self) -> int:
        from mjx_badger import plots

        folder = self.results_dir / self.profile / self.protocol
        kept = []
        written = plots.draw(folder, self.figures, self.profile, protocol=self.protocol, kept=kept)
        for path, why in kept:
            print(f"kept {path}: {why}")
        if not written and not kept:
            print(f"no results under {folder}", file=sys.stderr)
            return 1
        for path in written:
            print(f"wrote {path}")
        return 0


@dataclasses.dataclass(frozen=True)
class Claims:
    """Score the thesis's simulation claims against existing results."""

    profile: Profile = "quick"
    protocol: Optional[ProtocolName] = None
    """One protocol (default: both)."""
    results_dir: Path = Path("results")
    """Where the results are read from (the committed ones: figures/data)."""
    json: Optional[Path] = None
    """Also write the scoreboard here."""
    markdown: Optional[Path] = None
    """Also write the protocols' scoreboards side by side as a Markdown table here."""
    budgets: tuple[Profile, ...] = ()
    """Score these profiles side by side instead (e.g. --budgets quick full), one protocol (thesis-code unless
    --protocol): one table, thesis | ours at each budget."""
    plot: Optional[Path] = None
    """With --budgets: also draw every experiment's headline curve and the falls at each budget into this image."""

    def check(self) -> None:
        if len(set(self.budgets)) != len(self.budgets):
            raise ValueError(f"--budgets names a profile twice: {' '.join(self.budgets)}")
        if self.plot is not None and len(self.budgets) < 2:
            raise ValueError("--plot draws the budgets side by side: give --budgets with two profiles or more")
        outputs = (("--json", self.json), ("--markdown", self.markdown), ("--plot", self.plot))
        for option, path in outputs:
            if path is not None:
                writable_file(path, option)
        named = [(option, path.resolve()) for option, path in outputs if path is not None]
        for i, (option, path) in enumerate(named):
            for other, other_path in named[i + 1:]:
                if path == other_path:
                    raise ValueError(f"{option} and {other} name the same file")

    def __call__(self) -> int:
        from mjx_badger import claims, real_world, results

        if self.budgets:
            return self.by_budget()
        names = [self.protocol] if self.protocol else list(PROTOCOLS)
        boards = {name: claims.score(self.results_dir / self.profile, name) for name in names}
        for name, board in boards.items():
            print(claims.scoreboard_text(board, self.profile, name))
            print(f"  wall time: {results.wall_time_words(self.results_dir / self.profile / name, GROUPS['simulation'])}")
            print()
        for name in names:  # the real-world findings, in their own section
            real = claims.score(self.results_dir / self.profile, name, real_world.real_claims())
            print(claims.scoreboard_text(real, self.profile, name).replace("thesis claims", "real-world findings", 1))
            print(f"  wall time: {results.wall_time_words(self.results_dir / self.profile / name, GROUPS['real'])}")
            print()
        if self.markdown:
            from mjx_badger import reproduce

            reproduce.write_scoreboard_markdown(self.markdown, boards, self.results_dir / self.profile)
        if self.json:
            safe_io.write_text(self.json, json.dumps({name: [v.as_dict() for v in board]
                                                      for name, board in boards.items()}, indent=1))
        return 0


    def by_budget(self) -> int:
        from mjx_badger import claims, results

        protocol = self.protocol or "thesis-code"
        boards = {name: claims.score(self.results_dir / name, protocol) for name in self.budgets}
        print(claims.budgets_text(boards, protocol))
        for name in boards:
            print(f"  wall time at {name}: {results.wall_time_words(self.results_dir / name / protocol, GROUPS['simulation'])}")
        if self.markdown:
            times = "; ".join(f"{name}: {results.wall_time_words(self.results_dir / name / protocol, GROUPS['simulation'])}"
                              for name in boards)
            safe_io.write_text(self.markdown, f"Protocol: {protocol}\n\n" + claims.scoreboard_markdown(boards, "ours at {}")
                               + f"\nWall time on this machine: {times}.\n")
            print(f"wrote {self.markdown}")
        if self.plot:
            from mjx_badger import plots
            from mjx_badger.analysis import load_experiment

            loaded = {budget: {name: load_experiment(EXPERIMENTS[name], self.results_dir / budget / protocol / name)
                               for name in GROUPS["simulation"]} for budget in self.budgets}
            print(f"wrote {plots.budgets_figure(loaded, self.plot, protocol)}")
        if self.json:
            safe_io.write_text(self.json, json.dumps({name: [v.as_dict() for v in board]
                                                      for name, board in boards.items()}, indent=1))
        return 0


@dataclasses.dataclass(frozen=True)
class Publish:
    """Copy a profile's complete results into a reference folder, each with its best seed's policy only."""

    profile: Profile = "quick"
    protocol: ProtocolName = "thesis-code"
    results_dir: Path = Path("results")
    """Where the results are read from (<results-dir>/<profile>/<protocol>/)."""
    to: Optional[Path] = None
    """The reference folder, named explicitly (results land in <to>/<profile>/<protocol>/<experiment>/; the
    committed one is figures/data)."""

    def check(self) -> None:
        source = self.results_dir / self.profile / self.protocol
        if not source.is_dir():
            raise ValueError(f"no results folder {str(source)!r}")
        if self.to is None:
            raise ValueError("--to names the reference folder to publish into (the committed one: figures/data)")
        if (self.to / self.profile / self.protocol).resolve() == source.resolve():
            raise ValueError(f"--to {str(self.to)!r} is where the results already are; name another folder")
        writable_dir(self.to, "reference folder")

    def __call__(self) -> int:
        from mjx_badger import publish

        for path, what in publish.publish(self.results_dir / self.profile / self.protocol,
                                          self.to / self.profile / self.protocol):
            print(f"{path}: {what}")
        return 0


@dataclasses.dataclass(frozen=True)
class Attribute:
    """One-factor protocol swaps beside their baselines (2 seeds x 10k steps each)."""

    results_dir: Path = Path("results")
    """Where the swaps' runs are written."""
    only: Optional[tuple[str, ...]] = None
    """Run only these swaps (names as `list` prints them)."""

    def check(self) -> None:
        from mjx_badger.attribution import SWAPS_BY_NAME

        if self.only is not None and not self.only:
            raise ValueError(f"--only needs at least one swap; choose from: {', '.join(SWAPS_BY_NAME)}")
        unknown = sorted(set(self.only or ()) - set(SWAPS_BY_NAME))
        if unknown:
            raise ValueError(f"unknown swap(s) {unknown}; choose from: {', '.join(SWAPS_BY_NAME)}")
        writable_dir(self.results_dir, "results folder")

    def __call__(self) -> int:
        from mjx_badger import attribution, results, runner

        swaps = tuple(swap for swap in attribution.SWAPS if self.only is None or swap.name in self.only)
        seeds = list(range(attribution.PROFILE.seeds))
        for swap, run, config, path in attribution.planned(self.results_dir, swaps):
            if path.exists() and (results.read_or_skip(path) or {}).get("complete"):
                print(f"skip {path}: complete")
                continue
            runner.run(config, seeds, path, progress=runner.progress_wanted())
        print(attribution.table(self.results_dir))
        print(attribution.table(self.results_dir, conditions=True))
        return 0


@dataclasses.dataclass(frozen=True)
class Realtime:
    """Train on one robot at wall-clock rate, learner beside the control loop (by default a simulated HB40)."""

    run: Annotated[RealtimeConfig, Flat] = RealtimeConfig()
    robot_adapter: str = "simulated"
    """The robot to train on, by its adapter's name (realtime/adapters.py): 'simulated', the HB40 in native MuJoCo."""
    reset_seconds: float = 2.0
    """Simulated manual reset after a safety stop (not counted as training time)."""
    no_sensor_noise: bool = False
    """Simulated robot: perfect sensors."""
    out: Path = Path("results/realtime")
    """Folder for results."""
    restart: bool = False
    """Ignore a saved checkpoint and start over."""
    quiet: bool = False
    """No live view."""

    def check(self) -> None:
        from mjx_badger import memory
        from mjx_badger.realtime import adapters

        adapters.check(self.robot_adapter)
        if self.reset_seconds < 0:
            raise ValueError("--reset-seconds must not be negative")
        number("--reset-seconds", self.reset_seconds, 0.0, 3600.0)
        writable_dir(self.out, "output folder")
        memory.check_realtime(self.run)

    def __call__(self) -> int:
        from mjx_badger.realtime import adapters, figure, loop

        config = self.run
        bot = adapters.make(self.robot_adapter, config, reset_seconds=self.reset_seconds,
                            sensor_noise=not self.no_sensor_noise)
        try:
            document = loop.run(config, bot, self.out, resume=not self.restart, view=not self.quiet)
        except ValueError as error:  # a saved run of another configuration in the folder
            print(f"error: {error}", file=sys.stderr)
            return 2
        if document["steps"]:
            path = figure.draw(document, loop.load_trace(self.out, config), self.out / f"{config.name}.png")
            print(f"figure: {path}")
        return 0


@dataclasses.dataclass(frozen=True)
class SavedRun:
    """A training run's saved policy, one seed of it, under one command for some seconds."""

    results: tyro.conf.Positional[Path]
    """A training run's results file; its saved policy lies beside it."""
    seed: Optional[int] = None
    """Which seed's policy (default: the first the saved policy holds; a committed result holds its best seed's)."""
    command: Optional[str] = None
    """VX,VY,YAW (m/s, m/s, rad/s); default: the task's first evaluation command."""
    max_seconds = 3600.0  # the longest --seconds a command takes (a render keeps every frame in memory: less)
    seconds: float = 20.0
    """Simulated seconds to run the policy for, up to 3600."""
    conditions: Optional[str] = None
    """Run it under other conditions than it trained in (sim, office, outdoor): the thesis tested its office policy
    in simulation (§5.2.1). Default: the run's own."""

    def check(self) -> None:
        from mjx_badger import policy, results
        from mjx_badger.conditions import CONDITIONS

        number("--seconds", self.seconds, 0.0, self.max_seconds, low_open=True)
        if self.conditions is not None and self.conditions not in CONDITIONS:
            raise ValueError(f"--conditions {self.conditions!r}: choose from {', '.join(CONDITIONS)}")
        if self.seed is not None:
            integer("--seed", self.seed, 0, INT32_MAX)
        if not self.results.is_file():
            raise ValueError(f"no results file {str(self.results)!r}")
        document = results.read(self.results)
        if "policy" not in document:
            raise ValueError(f"{self.results} has no saved policy (complete runs since policies are saved have one)")
        saved = self.results.parent / document["policy"]
        if not saved.is_file():
            raise ValueError(f"{self.results}: its saved policy {str(saved)!r} is missing (a committed reference "
                             "result keeps only its best seed's, where one was attached)")
        seed = policy.load(saved, self.seed).seed  # the seed exists (default: the file's first), the file is whole
        results.train_config(document)  # the run can be rebuilt
        if seed in results.diverged(document):
            raise ValueError(f"seed {seed} of {self.results.name} diverged at step "
                             f"{results.diverged(document)[seed]}; its policy is frozen from before, choose another")
        if self.command is not None:
            try:
                vx, vy, yaw = [float(x) for x in self.command.split(",")]
            except ValueError:
                raise ValueError(f"--command takes VX,VY,YAW, three numbers; got {self.command!r}") from None
            for name, value in (("VX", vx), ("VY", vy), ("YAW", yaw)):
                number(f"--command {name}", value, -10.0, 10.0)

    def load(self):
        """(env, actor, command) of the run: its env with one long episode, the seed's NumPy actor, the command."""
        from mjx_badger import native, policy, results

        document = results.read(self.results)
        actor = policy.load(self.results.parent / document["policy"], self.seed)
        config = results.train_config(document)
        if self.conditions is not None:  # the whole set of the named conditions, none of the run's own changes
            config = dataclasses.replace(config, conditions=self.conditions, condition_changes=())
        env = native.evaluation_env(config, self.seconds)
        command = ([float(x) for x in self.command.split(",")] if self.command
                   else list(next(iter(env.task.eval_commands.values()))))
        return env, actor, command


@dataclasses.dataclass(frozen=True)
class Evaluate(SavedRun):
    """Run a run's saved policy on native MuJoCo (or MJX): velocity from the trunk's positions, falls, gait frequency."""

    engine: Literal["native", "mjx"] = "native"
    """native: mujoco.mj_step, as a robot's computer could; mjx: the training env, for comparison."""
    json: Optional[Path] = None
    """Also write the report here."""

    def check(self) -> None:
        super().check()
        if self.json is not None:
            writable_file(self.json, "--json")

    def __call__(self) -> int:
        from mjx_badger import native

        env, actor, command = self.load()
        run = native.run_native if self.engine == "native" else native.run_mjx
        report = dict(run(env, actor, command, self.seconds), engine=self.engine, seed=actor.seed,
                      conditions=env.conditions.name)
        print(json.dumps(report, indent=1))
        if self.json:
            safe_io.write_text(self.json, json.dumps(report, indent=1))
        return 0


@dataclasses.dataclass(frozen=True)
class Render(SavedRun):
    """A GIF of a run's saved policy walking on native MuJoCo, rendered offscreen (EGL or OSMesa)."""

    max_seconds = 60.0
    seconds: float = 5.0
    """Simulated seconds of video, up to 60."""
    out: Path = Path("gait.gif")
    """The video file (.gif)."""

    def check(self) -> None:
        super().check()
        if self.out.suffix.lower() != ".gif":
            raise ValueError(f"--out {self.out.name}: videos are written as .gif (an .mp4 needs ffmpeg, not installed)")
        writable_file(self.out, "--out")
        from mjx_badger import mjcf, render

        try:
            render.check_gl(mjcf.load_model())
        except RuntimeError as error:
            raise ValueError(str(error)) from None

    def __call__(self) -> int:
        from mjx_badger import render

        env, actor, command = self.load()
        report = render.record(env, actor, command, self.seconds, self.out)
        print(f"wrote {self.out} ({report['frames']} frames; {report['velocity_along_command']:.2f} m/s along "
              f"the command, {report['falls']} falls)")
        return 0


@dataclasses.dataclass(frozen=True)
class List:
    """List approaches, algorithms, tasks, experiments, profiles, protocols, robots, robot adapters and everyone's
    parameters."""

    def check(self) -> None:
        pass

    def __call__(self) -> int:
        from mjx_badger import spec, tasks
        from mjx_badger.attribution import SWAPS_BY_NAME
        from mjx_badger.realtime.adapters import ADAPTERS

        for title, names in (("approaches", APPROACHES), ("algorithms", ALGORITHMS), ("tasks", TASKS),
                             ("experiments", EXPERIMENTS), ("profiles", PROFILES), ("protocols", PROTOCOLS),
                             ("protocol fields", FIELDS), ("robots", ROBOTS), ("robot adapters", ADAPTERS),
                             ("attribution swaps", [f"'{name}'" for name in SWAPS_BY_NAME])):
            print(f"{title}: {', '.join(names)}")
        print("approach parameters: " + "; ".join(f"{name}: {', '.join(a.params)}"
                                                  for name, a in APPROACHES.items() if a.params))
        print("task parameters: " + "; ".join(f"{name}: {', '.join(tasks.task_params(name))}"
                                              for name in TASKS if tasks.task_params(name)))
        print(f"algorithm parameters: {', '.join(spec.AGENT_FIELDS)}")
        return 0


COMMANDS = {"train": Train, "sweep": Sweep, "reproduce": Reproduce, "figures": Figures, "claims": Claims,
            "publish": Publish, "attribute": Attribute, "realtime": Realtime, "evaluate": Evaluate, "render": Render,
            "estimator": Estimator, "list": List}


def one_line(box: str) -> str:
    """tyro's framed error message as one line: the message rows, without frame, title, help text or footer."""
    rows = [re.sub(r"^[\s│─]+|[\s│─]+$", "", line) for line in box.splitlines() if not line.startswith(("╭", "╰"))]
    sections, current = [], []
    for row in rows + [""]:
        if row:
            current.append(row)
        elif current:  # a rule between sections, its frame stripped away
            sections.append(" ".join(current))
            current = []
    kept = [s for s in sections if not s.startswith(("Argument helptext", "For full helptext", "usage:"))]
    return "; ".join(kept[:2]) or "bad arguments"


def parse(argv=None):
    """The command `argv` asks for, built and checked; SystemExit(2) with one line on stderr if it cannot be."""
    argv = sys.argv[1:] if argv is None else list(argv)
    errors = io.StringIO()
    try:
        with contextlib.redirect_stderr(errors):
            command = tyro.extras.subcommand_cli_from_dict(COMMANDS, args=argv, prog="python -m mjx_badger",
                                                           description=DESCRIPTION)
        command.check()
    except SystemExit as done:
        if done.code:
            print(f"error: {one_line(errors.getvalue())} (see --help)", file=sys.stderr)
        else:
            sys.stderr.write(errors.getvalue())
        raise
    except ValueError as error:  # a spec or a check refused the input
        print(f"error: {error}", file=sys.stderr)
        raise SystemExit(2) from None
    return command


def main(argv=None) -> int:
    command = parse(argv)
    enable_compilation_cache()
    return run_safely(command)


def run_safely(command) -> int:
    """Run a checked command; a refusal, a stop by signal or a failed write ends it in one line, not a traceback."""
    from mjx_badger import faults

    return faults.run(command)
