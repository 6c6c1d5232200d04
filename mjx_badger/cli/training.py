"""`train` one configuration over many seeds, and `sweep` a grid of its numeric parameters, as one program each."""

import dataclasses
import functools
import shutil
import sys
from pathlib import Path
from typing import Annotated, Optional

import tyro

from mjx_badger.cli.common import Cluster, Flat, Launch, Runs, check_seed_devices
from mjx_badger.core import launch
from mjx_badger.learning import memory, runner, sweep
from mjx_badger.learning.progress import run_progress
from mjx_badger.records import results


@dataclasses.dataclass(frozen=True)
class Train(Runs):
    """Train one configuration over many seeds in one vmapped program."""

    cluster: Annotated[Cluster, Flat] = Cluster()

    def check(self) -> None:
        self.check_runs()
        self.cluster.check()
        if not self.dry_run:  # joined before JAX touches a device, which the estimate does
            self.cluster.start()
        check_seed_devices(self.seeds)
        memory.check(self.run, self.seeds)

    def __call__(self) -> int:
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
    launch: Annotated[Launch, Flat] = Launch()
    """With --runs-per-device or --launcher slurm, each group of --vmapped members is a run of its own."""

    def axes(self) -> tuple:
        return (sweep.read_grid(self.grid) if self.grid else ()) + tuple(sweep.parse_axis(v) for v in self.vary)

    def check(self) -> None:
        self.check_runs()
        self.launch.check()
        members = sweep.members(self.run, self.axes())
        sweep.check_groups(len(members), self.vmapped)
        memory.check(self.run, self.seeds, members=len(members))

    def __call__(self) -> int:
        if self.dry_run:
            members = sweep.members(self.run, self.axes())
            print(f"would sweep {len(members)} members of {self.run.name} x {self.seeds} seeds in groups of "
                  f"{min(self.vmapped, len(members))}, into {self.out}")
            print(memory.words(self.run, self.seeds, members=len(members)))
            return 0
        if not self.launch.here:
            return self.launched()
        try:
            documents = sweep.run(self.run, self.axes(), self.seed_list, self.out, self.vmapped, progress=not self.quiet,
                                  resume=not self.restart, tensorboard=self.tensorboard)
        except ValueError as error:  # refused after building the members: shapes, or a field fixed when built
            print(f"error: {error}", file=sys.stderr)
            return 2
        for document in documents:
            print(f"wrote {self.out / document['agents'].replace('.agents', '.json')}")  # every agent has these
        print(f"{len(documents)} members x {self.seeds} seeds: {documents[0]['wall_clock']['seed_steps_per_s']} "
              f"seed-steps/s, compile {documents[0]['wall_clock']['compile_s']} s")
        return 0

    def launched(self) -> int:
        """Each group of --vmapped members as a run of its own process or cluster job (each resumes when requeued)."""
        axes = self.axes()
        grid, fields = sweep.members(self.run, axes), [field for field, _ in axes]
        since = results.now() if self.restart else ""  # what landed before a --restart is trained again
        # A group's members train in one program and save together: its first member's file says how far it has come.
        jobs = [launch.Job(f"members {part[0]}-{part[-1]}", sweep.run,
                           (self.run, axes, self.seed_list, self.out, self.vmapped, False, True, self.tensorboard, part,
                            since),
                           functools.partial(run_progress, self.out / f"{sweep.member_name(grid[part[0]], fields)}.json",
                                             grid[part[0]].num_chunks * grid[part[0]].chunk_steps))
                for part in sweep.parts(len(grid), self.vmapped)]
        if self.restart:  # a requeued job resumes its own start, not an older sweep's checkpoint: those go first
            for path in [self.out / f"sweep_{self.run.name}.ckpt", *self.out.glob(f"sweep_{self.run.name}_members_*.ckpt")]:
                shutil.rmtree(path, ignore_errors=True)
        self.launch.run(jobs, self.out)
        print(f"{len(grid)} members x {self.seeds} seeds in {len(jobs)} runs: results in {self.out}")
        return 0
