"""What the commands share: the profile, protocol and experiment names they take, several processes (`Cluster`),
and the options of a run's seeds and output (`Runs`)."""

import dataclasses
from pathlib import Path
from typing import Annotated, Literal, Optional

import jax
import tyro

from mjx_badger.core import cluster, launch, slurm
from mjx_badger.core.validation import INT32_MAX, integer, writable_dir
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, PROFILES
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.programs import check_seeds_divide
from mjx_badger.protocol.protocols import PROTOCOLS

MAX_SEEDS = 1_000_000
"""More seeds than any machine holds; the memory check refuses far fewer on most."""
DESCRIPTION = "mjx_badger: the thesis's simulation experiments on MJX, their claims scored, and the on-robot loop."
Profile = Literal[tuple(PROFILES)]
ProtocolName = Literal[tuple(PROTOCOLS)]
ExperimentName = Literal[tuple(EXPERIMENTS) + tuple(GROUPS)]
Flat = tyro.conf.arg(name="")
"""A nested run spec whose fields are the command's own options (--approach, not --run.approach)."""


def check_seed_devices(seeds: int) -> None:
    """The seeds split evenly over this machine's devices (programs.seed_sharding), checked before any compile."""
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
        cluster.join(self.coordinator, self.num_processes, self.process_id)


@dataclasses.dataclass(frozen=True)
class Launch:
    """Where the runs train: here, one after another or several at once, or as a SLURM job array (docs/cluster.md)."""

    launcher: Literal["local", "slurm"] = "local"
    """local: on this machine; slurm: one job array through submitit, waited for, then drawn here as locally."""
    runs_per_device: int = 1
    """Runs at once, each in its own process sharing one device (on a GPU each with 1/N of its memory); on SLURM,
    runs per array task."""
    slurm_partition: Optional[str] = None
    """The partition the array is submitted to (default: the cluster's default partition)."""
    slurm_gpus: int = 0
    """GPUs per array task (0: CPU nodes)."""
    slurm_cpus: int = 2
    """CPU cores per array task."""
    slurm_mem_gb: int = 16
    """Memory per array task (GB)."""
    slurm_time_min: int = 240
    """Each task's time limit; one that reaches it is requeued and resumes from its checkpoint."""
    slurm_account: Optional[str] = None
    """The account the tasks are charged to (default: your default account)."""
    slurm_qos: Optional[str] = None
    """The quality of service the tasks ask for (default: the partition's)."""
    slurm_folder: Optional[Path] = None
    """Where submitit keeps the jobs' files and logs (default: <results-dir>/slurm)."""
    slurm_requeues: int = 3
    """Time-outs a task may resume from before it is given up."""
    slurm_signal_delay_s: int = 600
    """How long before its time limit a task is told to checkpoint and requeue (it acts between chunks)."""

    @property
    def here(self) -> bool:
        """Whether the runs train in this process, one after another (with progress bars and an ETA)."""
        return self.launcher == "local" and self.runs_per_device == 1

    def check(self, distributed: bool = False) -> None:
        """ValueError for options out of range or SLURM not reachable; submits nothing. Where the runs train in
        processes of their own, this one takes device memory only as it needs it (launch.spare_device)."""
        integer("--runs-per-device", self.runs_per_device, 1, 64)
        if distributed and not self.here:
            raise ValueError(f"{'--launcher slurm' if self.launcher == 'slurm' else '--runs-per-device'} spreads whole "
                             "runs: leave out --coordinator/--distributed (those split one run's seeds over hosts)")
        if self.launcher == "local":
            given = [f"--{f.name.replace('_', '-')}" for f in dataclasses.fields(self)
                     if f.name.startswith("slurm_") and getattr(self, f.name) != f.default]
            if given:
                raise ValueError(f"{', '.join(given)} {'needs' if len(given) == 1 else 'need'} --launcher slurm")
            if not self.here:
                launch.spare_device()
            return
        integer("--slurm-gpus", self.slurm_gpus, 0, 16)
        integer("--slurm-cpus", self.slurm_cpus, 1, 1024)
        integer("--slurm-mem-gb", self.slurm_mem_gb, 1, 16384)
        integer("--slurm-time-min", self.slurm_time_min, 1, 60 * 24 * 31)
        integer("--slurm-requeues", self.slurm_requeues, 0, 100)
        integer("--slurm-signal-delay-s", self.slurm_signal_delay_s, 60, 24 * 3600)
        if self.slurm_time_min * 60 < self.slurm_signal_delay_s + 300:
            raise ValueError(f"--slurm-time-min {self.slurm_time_min} leaves under 5 min before the requeue signal "
                             f"{self.slurm_signal_delay_s} s ahead of the limit (--slurm-signal-delay-s): give a task "
                             f"at least {(self.slurm_signal_delay_s + 300 + 59) // 60} min")
        if self.slurm_folder is not None:
            writable_dir(self.slurm_folder, "--slurm-folder")
        why = slurm.available()
        if why:
            raise ValueError(f"--launcher slurm: {why}; on a machine without SLURM use --launcher local")
        launch.spare_device()

    def run(self, jobs: list, shared: Path) -> None:
        """Train `jobs` where these options say; `shared` (the results folder) holds the compile cache."""
        if self.launcher == "local":
            return launch.run(jobs, self.runs_per_device, shared)
        if jobs:
            # Each --slurm-X option is the field X of slurm.Slurm.
            resources = slurm.Slurm(**{f.name: getattr(self, f"slurm_{f.name}") for f in dataclasses.fields(slurm.Slurm)})
            slurm.submit(jobs, self.runs_per_device, resources, shared, lambda line: print(line, flush=True))


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
