"""One process alone is its own cluster: it writes, gathers to the host and agrees with itself."""

import jax.numpy as jnp
import numpy as np

from mjx_badger.core import cluster


def test_one_process_writes_and_takes_its_own_decisions():
    assert cluster.writes()
    assert cluster.agreed_max(0.5, 2.0) == (0.5, 2.0)
    assert cluster.agree(True) is True and cluster.agree(False) is False
    cluster.wait_for_peers()  # no barrier to wait at


def test_gather_brings_a_device_tree_to_the_host_whole():
    gathered = cluster.gather({"a": jnp.arange(3), "b": (jnp.ones(2),)})
    assert isinstance(gathered["a"], np.ndarray) and gathered["a"].tolist() == [0, 1, 2]
    assert gathered["b"][0].tolist() == [1.0, 1.0]
