"""What the commands share: a cluster's address checked before anything joins, and a run's seeds and folder."""

import pytest

from mjx_badger.cli.common import Cluster, Runs, check_seed_devices


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
