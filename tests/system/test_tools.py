"""tools/profile_time.py reads a pause log: which SIGSTOPs a run's clock counted; tools/reevaluate.py names why an
evaluation differs from training's."""

import importlib.util
from pathlib import Path

spec = importlib.util.spec_from_file_location("profile_time", Path(__file__).parents[2] / "tools" / "profile_time.py")
profile_time = importlib.util.module_from_spec(spec)
spec.loader.exec_module(profile_time)
spec = importlib.util.spec_from_file_location("reevaluate", Path(__file__).parents[2] / "tools" / "reevaluate.py")
reevaluate = importlib.util.module_from_spec(spec)
spec.loader.exec_module(reevaluate)

LOG = """\
2026-12-03T10:00:00+00:00 START attempt 1
2026-12-03T10:10:00+00:00 STOP (all background training) a benchmark (pids 1
2)
2026-12-03T10:15:00+00:00 CONT (all background training) done (pids 1
2)
2026-12-03T10:20:00+00:00 START real group, beside the full profile
2026-12-03T10:30:00+00:00 STOP (all background training) make test (pids 1 2)
2026-12-03T10:40:00+00:00 CONT real group only (pid 2); the full profile stays paused
2026-12-03T11:00:00+00:00 STOP (all background training) while the runs' process is gone (pids 2)
2026-12-03T11:05:00+00:00 CONT (all background training) done (pids 2)
2026-12-03T11:10:00+00:00 START attempt 1
2026-12-03T11:20:00+00:00 STOP (all background training) profile (pids 3)
2026-12-03T11:22:00+00:00 CONT (all background training) done (pids 3)
2026-12-03T11:30:00+00:00 session ended
""".splitlines()


def at(clock: str) -> float:
    return profile_time.seconds(f"2026-12-03T{clock}:00+00:00")


def test_only_pauses_that_a_cont_of_the_runs_process_ended_count():
    # The 10:30 stop was never continued (the process was killed while stopped); 11:00 paused another process.
    assert profile_time.pause_intervals(LOG) == [(at("10:10"), at("10:15")), (at("11:20"), at("11:22"))]


def test_a_run_is_charged_the_paused_part_of_its_span_and_knows_its_attempts():
    pauses, starts = profile_time.pause_intervals(LOG), profile_time.attempt_starts(LOG)
    assert profile_time.paused_seconds(pauses, at("10:12"), at("11:21")) == 3 * 60 + 60
    assert starts == [at("10:00"), at("11:10")]
    document = {"complete": True, "seeds": [0, 1], "steps": [1000],
                "wall_clock": {"started": "2026-12-03T10:00:00+00:00", "updated": "2026-12-03T10:50:00+00:00",
                               "compile_s": 60.0, "run_s": 2000.0, "checkpoint_s": 40.0}}
    cost = profile_time.run_cost(document, None, pauses, starts)
    assert (cost["wall_s"], cost["cost_s"], cost["paused_s"], cost["cost_s_less_pauses"]) == (3000, 2100, 300, 1800)
    document["wall_clock"]["updated"] = "2026-12-03T11:25:00+00:00"  # resumed by the 11:10 attempt
    cost = profile_time.run_cost(document, None, pauses, starts)
    assert cost["paused_s"] == 420 and cost["cost_s_less_pauses"] is None


# tools/cluster_plan.py: the full profile's runs put longest first onto a cluster's nodes.

plan_spec = importlib.util.spec_from_file_location("cluster_plan", Path(__file__).parents[2] / "tools" / "cluster_plan.py")
cluster_plan = importlib.util.module_from_spec(plan_spec)
plan_spec.loader.exec_module(cluster_plan)


def test_runs_go_longest_first_to_the_node_that_frees_first():
    assert cluster_plan.makespan([5, 4, 3, 3, 3], 2) == 10  # 5 + 3 on one node, 4 + 3 + 3 on the other
    assert cluster_plan.makespan([5, 4, 3, 3, 3], 1) == 18
    assert cluster_plan.makespan([5, 1, 1], 3) == 5


def test_many_nodes_are_bound_by_the_longest_run_and_sharing_a_node_slows_it():
    costs = {"long": 10 * 3600.0, "a": 3600.0, "b": 3600.0}
    rows = {(r["nodes"], r["runs_per_node"]): r for r in cluster_plan.plan(costs, (1, 3), 1.5)}
    assert rows[1, 1]["wall_h"] == 12 and rows[1, 1]["bound"] == "the work over the nodes"
    assert rows[3, 1]["wall_h"] == 10 and rows[3, 1]["bound"] == "the longest run"
    assert rows[3, 2]["wall_h"] == 15 and rows[3, 2]["bound"] == "the longest run"
    assert rows[1, 2]["wall_h"] == 15 and rows[1, 2]["bound"] == "the longest run"  # two slots: long | a + b


def test_a_difference_is_put_on_the_engine_where_mjx_reaches_trainings_figure_and_native_mujoco_falls_short():
    row = {"heading_velocity_along_command": 0.10, "training_eval": 0.37, "training_eval_last": 0.32,
           "native_at_training_length": {"heading_velocity_along_command": 0.16, "falls": 11},
           "mjx_at_training_length": {"heading_velocity_along_command": 0.30, "falls": 1}}
    assert reevaluate.why(row).startswith("the engine: MJX at training's length agrees (0.30 m/s, 1 falls)")
    row["mjx_at_training_length"]["heading_velocity_along_command"] = 0.42  # past it: another draw of the ground
    assert reevaluate.why(row).startswith("the engine: MJX at training's length walks as fast or faster (0.42 m/s")
    row["mjx_at_training_length"]["heading_velocity_along_command"] = 0.20  # short of it too: not the engine
    assert reevaluate.why(row) == "unexplained by the policy's last chunk, the engine or the length"
    row["native_at_training_length"]["heading_velocity_along_command"] = 0.30  # native agrees over the same length
    assert reevaluate.why(row) == "the length: over training's evaluation length native MuJoCo agrees"
    row["heading_velocity_along_command"] = 0.29  # within 20 % of the last chunk's evaluation, not of the final chunks'
    assert reevaluate.why(row).startswith("the policy changed over the final chunks")
    row["heading_velocity_along_command"] = 0.36
    assert reevaluate.why(row) == "agrees"
