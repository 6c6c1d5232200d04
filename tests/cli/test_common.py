"""What the commands share: a cluster's address checked before anything joins, and a run's seeds and folder."""

import pytest

from mjx_badger.cli.common import Cluster, Runs, check_seed_devices
from mjx_badger.cli.main import main


@pytest.mark.parametrize("cluster, says", [
    (Cluster(num_processes=2), "need --coordinator HOST:PORT"),
    (Cluster(coordinator="host:1234"), "needs --num-processes and --process-id"),
    (Cluster(coordinator="host", num_processes=2, process_id=0), "HOST:PORT with a port in 1..65535"),
    (Cluster(coordinator="host:70000", num_processes=2, process_id=0), "HOST:PORT with a port in 1..65535"),
    (Cluster(coordinator="host:1234", num_processes=2, process_id=2), r"--process-id must be in 0\.\.1, not 2"),
])
def test_an_incomplete_or_malformed_cluster_is_refused_in_one_line(cluster, says):
    with pytest.raises(ValueError, match=says):
        cluster.check()


def test_a_whole_address_and_no_address_pass_and_the_seeds_follow_first_seed(tmp_path):
    Cluster().check()
    Cluster(coordinator="10.0.0.1:1234", num_processes=4, process_id=3).check()
    runs = Runs(seeds=3, first_seed=5, out=tmp_path)
    runs.check_runs()
    assert runs.seed_list == [5, 6, 7]
    check_seed_devices(3)  # one device here: any number of seeds
    with pytest.raises(ValueError, match="--first-seed must be an integer"):
        Runs(seeds=3, first_seed=-1, out=tmp_path).check_runs()


@pytest.mark.parametrize("argv, says", [
    (["--runs-per-device", "0"], "--runs-per-device must be an integer in 1..64, not 0"),
    (["--slurm-partition", "gpu"], "--slurm-partition needs --launcher slurm"),
    (["--slurm-gpus", "1", "--slurm-time-min", "5"], "--slurm-gpus, --slurm-time-min need --launcher slurm"),
    (["--launcher", "slurm", "--slurm-gpus", "-1"], "--slurm-gpus must be an integer in 0..16, not -1"),
    (["--launcher", "slurm", "--coordinator", "a:1", "--num-processes", "2", "--process-id", "0"],
     "--launcher slurm spreads whole runs: leave out --coordinator/--distributed"),
    (["--runs-per-device", "2", "--distributed"], "--runs-per-device spreads whole runs: leave out --coordinator"),
    (["--launcher", "slurm", "--slurm-time-min", "10"], "--slurm-time-min 10 leaves under 5 min before the requeue "
                                                         "signal 600 s ahead of the limit (--slurm-signal-delay-s)"),
    (["--launcher", "slurm"], "--launcher slurm: SLURM's sbatch is not on PATH; on a machine without SLURM use "
                              "--launcher local"),
])
def test_where_the_runs_train_is_refused_in_one_line_before_anything_runs(argv, says, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("PATH", "/nonexistent")  # no sbatch, whatever this machine has
    with pytest.raises(SystemExit) as stop:
        main(["reproduce", "--profile", "smoke", "--results-dir", str(tmp_path / "r"), *argv])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1 and says in err, err
    assert not (tmp_path / "r").exists()
