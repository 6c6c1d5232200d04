"""The experiments: their runs, names, sizes per profile, and the groups `reproduce` takes."""

from mjx_badger.core.paths import REFERENCE
from mjx_badger.experiments import registry
from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES, Run


def test_groups_expand_into_their_experiments_once_each():
    assert registry.GROUPS["simulation"] == ("algo-comparison", "forward", "forward-max", "omni-random", "omni-pdec")
    assert registry.expand(["forward", "simulation"])[:2] == ("forward", "algo-comparison")
    assert len(registry.expand(["simulation", "real", "real", "agents"])) == len(EXPERIMENTS)


def test_the_agents_experiments_put_the_newer_agents_beside_fig_5_2s_four():
    agents, comparison = EXPERIMENTS["agents"], EXPERIMENTS["algo-comparison"]
    assert [r.algo for r in agents.runs] == ["sac", "sac-utd20", "droq", "crossq", "xqc", "simbav2", "bro", "fastsac"]
    assert {r.approach for r in agents.runs} == {"jt-nf"} and {r.approach for r in EXPERIMENTS["agents-cpg"].runs} == {
        "cpg-vf"}
    assert agents.thesis_numbers["crossq"] == comparison.thesis_numbers["crossq"] and agents.x_axis == "minutes"
    # The thesis's four are the comparison's very runs: reproduce copies them rather than training them again.
    assert agents.train_config(agents.runs[3], "quick") == comparison.train_config(comparison.runs[3], "quick")
    assert "agents" not in registry.GROUPS["simulation"] and registry.GROUPS["agents"] == ("agents", "agents-cpg")


def test_a_runs_steps_follow_its_profile_its_caps_and_the_real_worlds_20k_and_table_5_5s_50k():
    algos = EXPERIMENTS["algo-comparison"]
    droq, crossq = (next(r for r in algos.runs if r.algo == a) for a in ("droq", "crossq"))
    assert algos.steps(crossq, "quick") == PROFILES["quick"].steps == 20_000 and algos.steps(droq, "quick") == 10_000
    office = EXPERIMENTS["real-office"]
    assert office.steps(office.runs[0], "full") == 20_000 and office.steps(office.runs[0], "smoke") == 600
    omni = EXPERIMENTS["real-outdoor-omni"]  # Table 5.5: 50k steps (§5.2.3)
    assert omni.steps(omni.runs[0], "quick") == omni.steps(omni.runs[0], "full") == 50_000
    config = office.train_config(office.runs[1], "quick")
    assert config.conditions == "office" and dict(config.task_params) == {"target_velocity": 0.25}


def test_run_names_and_files_say_what_differs_among_an_experiments_runs():
    office = EXPERIMENTS["real-office"]
    assert [office.label(r) for r in office.runs[:2]] == ["jt-lpf sac-utd20", "jt-oef"]
    swept = registry.Experiment("toy", "-", (Run("jt-oef", "crossq", "forward", approach_params=(("min_cutoff", 0.5),)),
                                             Run("jt-oef", "crossq", "forward", approach_params=(("min_cutoff", 2.0),))), {})
    assert [swept.label(r) for r in swept.runs] == ["jt-oef min_cutoff=0.5", "jt-oef min_cutoff=2.0"]
    assert swept.result_name(swept.runs[0]) == "jt-oef_crossq_forward__min_cutoff=0.5.json"
    assert registry.result_name(Run("jt-nf", "sac", "forward"), (("path", "a b/c"),)) == "jt-nf_sac_forward__path=a-b-c.json"


def test_an_experiments_results_are_loaded_by_run_name_and_missing_ones_left_out(tmp_path):
    loaded = registry.load_experiment(EXPERIMENTS["forward"], REFERENCE / "quick" / "thesis-code" / "forward")
    assert set(loaded) == set(registry.THESIS_APPROACHES)
    assert registry.load_experiment(EXPERIMENTS["forward"], tmp_path) == {}
