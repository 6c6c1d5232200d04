"""Numbers from results files: how figures and tables name a run."""

from mjx_badger.records.analysis import display_name


def test_a_run_of_another_algorithm_is_named_algorithm_first():
    assert display_name("jt-lpf sac-utd20") == "SAC-UTD20 JT-LPF"  # Table 5.3's first row, as the thesis names it
    assert display_name("jt-lpf") == "JT-LPF" and display_name("jt-lpf cutoff_hz=2") == "JT-LPF cutoff_hz=2"
