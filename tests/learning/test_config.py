"""TrainConfig: the control rate comes from the protocol, for each approach and algorithm."""

from mjx_badger.learning.config import TrainConfig


def test_train_config_takes_the_control_rate_from_the_protocol():
    # thesis-text: each algorithm at its Table 4.3 rate; thesis-code: JT at 50 Hz, CPG at 40 Hz, any algorithm.
    text = dict(protocol="thesis-text")
    assert TrainConfig(algo="crossq", **text).env_config.control_hz == 40.0
    assert TrainConfig(algo="droq", **text).env_config.control_hz == 20.0
    assert TrainConfig(algo="droq").env_config.control_hz == 50.0
    assert TrainConfig(algo="sac", approach="cpg-d").env_config.control_hz == 40.0
