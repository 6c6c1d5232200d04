"""A one-node SLURM on this machine for tests: munged, slurmctld and slurmd in a folder of their own, on 127.0.0.1.

Debian's `slurm-wlm` and `munge` packages (`.ci/run` installs them). The daemons run as this user with a fresh
munge key; `CommunicationParameters=NoCtldInAddrAny,NoInAddrAny` binds them to the node's address, 127.0.0.1,
rather than every interface. No accounting database: `sacct` answers that accounting is disabled, and submitit
then learns that a job has ended from its result file.
"""

import contextlib
import getpass
import os
import shutil
import subprocess
import time
from pathlib import Path

DAEMONS = ("munged", "slurmctld", "slurmd", "sbatch", "scontrol", "scancel", "squeue")
CONTROLLER_PORT, NODE_PORT = 16817, 16818  # away from SLURM's usual 6817/6818, in case a real one runs here

CONF = """ClusterName=mjxbadgertest
SlurmctldHost=localhost(127.0.0.1)
SlurmUser={user}
SlurmdUser={user}
SlurmctldPort={controller}
SlurmdPort={node}
AuthType=auth/munge
AuthInfo=socket={folder}/munge.socket
CredType=cred/munge
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
StateSaveLocation={folder}/state
SlurmdSpoolDir={folder}/spool
SlurmctldPidFile={folder}/slurmctld.pid
SlurmdPidFile={folder}/slurmd.pid
SlurmctldLogFile={folder}/slurmctld.log
SlurmdLogFile={folder}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
ReturnToService=2
JobRequeue=1
NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory_mb} State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""


def unavailable() -> str | None:
    """Why a SLURM cannot start here, or None."""
    missing = [name for name in DAEMONS if not shutil.which(name) and not Path("/usr/sbin", name).exists()]
    if missing:
        return f"SLURM cannot start here: {', '.join(missing)} missing (apt-get install slurm-wlm munge; .ci/run does)"
    if os.geteuid() != 0:
        return "SLURM cannot start here: slurmd launches jobs as their user, which needs root"
    return None


def _binary(name: str) -> str:
    return shutil.which(name) or str(Path("/usr/sbin", name))


@contextlib.contextmanager
def cluster(folder: Path, cpus: int = 2, memory_mb: int = 16_000):
    """A running one-node SLURM; yields the environment its clients need (SLURM_CONF). Stops it on the way out."""
    folder = Path(folder).absolute()
    for sub in ("state", "spool"):
        (folder / sub).mkdir(parents=True, exist_ok=True)
    key = folder / "munge.key"
    key.write_bytes(os.urandom(128))
    key.chmod(0o600)
    conf = folder / "slurm.conf"
    conf.write_text(CONF.format(user=getpass.getuser(), controller=CONTROLLER_PORT, node=NODE_PORT, folder=folder,
                                cpus=cpus, memory_mb=memory_mb))
    env = dict(os.environ, SLURM_CONF=str(conf))
    started = []
    try:
        subprocess.run([_binary("munged"), "--force", f"--socket={folder}/munge.socket", f"--key-file={key}",
                        f"--pid-file={folder}/munged.pid", f"--log-file={folder}/munged.log",
                        f"--seed-file={folder}/munge.seed"], check=True, env=env)
        started.append(folder / "munged.pid")
        subprocess.run([_binary("slurmctld"), "-f", str(conf)], check=True, env=env)
        started.append(folder / "slurmctld.pid")
        subprocess.run([_binary("slurmd"), "-f", str(conf), "-N", "localhost"], check=True, env=env)
        started.append(folder / "slurmd.pid")
        _wait_idle(env, folder)
        yield env
    finally:
        for pid_file in reversed(started):
            with contextlib.suppress(OSError, ValueError):
                os.kill(int(pid_file.read_text()), 15)


def _wait_idle(env: dict, folder: Path, timeout_s: float = 60.0) -> None:
    """Until the node takes jobs; RuntimeError with the controller's last lines if it never does."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        state = subprocess.run(["sinfo", "-h", "-o", "%T"], env=env, capture_output=True, text=True).stdout.strip()
        if state == "idle":
            return
        time.sleep(0.5)
    log = (folder / "slurmctld.log").read_text()[-2000:] if (folder / "slurmctld.log").exists() else ""
    raise RuntimeError(f"the test SLURM's node never became idle:\n{log}")


def restarts(env: dict, job_id: str) -> int:
    """How many times SLURM has requeued `job_id` (scontrol's Restarts)."""
    shown = subprocess.run(["scontrol", "show", "job", job_id], env=env, capture_output=True, text=True).stdout
    return int(shown.split("Restarts=", 1)[1].split()[0]) if "Restarts=" in shown else 0
