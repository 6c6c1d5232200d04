"""The ETA of `reproduce`: each remaining run's cost from its algorithm, task and steps, at the rates of the runs done."""

import dataclasses
from pathlib import Path

import pytest

from mjx_badger.experiments import eta
from mjx_badger.learning.config import TrainConfig

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("profile", ["quick", "smoke"])
def test_after_the_first_run_the_eta_is_within_25_percent_of_the_time_left(profile):
    """Replayed on what the profile's runs cost on this machine, run after run."""
    cost = eta.measured_costs(profile, ROOT)
    runs = [(plan, (0.0, 0.0) if plan.copy else cost[name]) for name, plan, _ in eta.profile_plan(profile)]
    for k, (left, actual) in enumerate(eta.replay(runs), start=1):
        assert left == pytest.approx(actual, rel=0.25), f"after run {k}"


def test_the_eta_counts_updates_evaluations_and_copies():
    forward = TrainConfig(approach="jt-nf", algo="crossq", task="forward", total_steps=2000, chunk_steps=1000,
                          warmup_steps=1000, eval_steps=100)
    plan = eta.planned(forward, seeds=2)
    assert plan.work == 2 * (2000 + eta.UPDATE_COST * 1000 + 2 * 100)  # steps, updates after warm-up, evaluations
    utd = eta.planned(dataclasses.replace(forward, algo="sac-utd20"), seeds=2)
    assert utd.work == 2 * (2000 + eta.UPDATE_COST * 20 * 1000 + 2 * 100)
    omni = eta.planned(dataclasses.replace(forward, task="omni-random", approach="cpg-d"), seeds=2)
    assert omni.work == 2 * (2000 + eta.UPDATE_COST * 1000 + 2 * 8 * 100) and omni.other_weight > plan.other_weight
    assert eta.seconds_left([plan], []) is None  # nothing measured yet
    done = [eta.Done(plan, train_s=100.0, other_s=30.0)]
    assert eta.seconds_left([plan, plan._replace(copy=True)], done) == pytest.approx(130.0)
    assert eta.seconds_left([utd], done) == pytest.approx(utd.work / plan.work * 100.0 + 30.0)
    # A task not seen yet: the compile and recording of the seen ones, scaled by its evaluation commands.
    assert eta.seconds_left([omni], done) == pytest.approx(omni.work / plan.work * 100.0 + 30.0 * omni.other_weight)


def test_a_newer_agents_updates_weigh_what_they_cost_beside_a_thesis_agents():
    crossq, xqc = (TrainConfig(approach="jt-nf", algo=a, total_steps=2000, warmup_steps=1000) for a in ("crossq", "xqc"))
    # 1000 learning steps: CrossQ one update each, XQC two, each 18.4 of a thesis agent's; the rest is the same.
    extra = eta.planned(xqc, 1).work - eta.planned(crossq, 1).work
    assert extra == pytest.approx(eta.UPDATE_COST * 1000 * (2 * 18.4 - 1))
