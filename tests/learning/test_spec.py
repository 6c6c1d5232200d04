"""RunSpec: one checked description of a run, shared by the trainer and the on-robot loop."""

import dataclasses

import pytest

from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.spec import RunSpec
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.tasks import locomotion as tasks


@pytest.mark.parametrize("changes, message", [
    ({"approach": "jt-xyz"}, "unknown approach 'jt-xyz'; choose from jt-nf, jt-lpf"),
    ({"algo": "ppo"}, "unknown algorithm 'ppo'; choose from sac, sac-utd20, droq, crossq, xqc, simbav2, bro, fastsac"),
    ({"task": "jump"}, "unknown task 'jump'; choose from forward"),
    ({"protocol": "thesis-paper"}, "unknown protocol 'thesis-paper'"),
    ({"approach_params": (("cutoff_hz", 1.0),)}, "approach 'jt-oef' takes min_cutoff, beta, d_cutoff, not cutoff_hz"),
    ({"task_params": (("speed", 0.3),)}, "task 'forward' takes target_velocity, velocity_weight, .*, not speed"),
    ({"algo_params": (("learning_rat", 0.1),)}, "learning_rat are not AgentConfig fields; choose from learning_rate"),
    ({"protocol_changes": (("gains", 1),)}, "unknown protocol field"),
])
def test_a_bad_spec_fails_when_built_and_names_the_choices(changes, message):
    for kind in (RunSpec, TrainConfig):
        with pytest.raises(ValueError, match=message.replace("(", r"\(")):
            kind(**changes)
    with pytest.raises(ValueError, match="must be shorter than the run"):
        TrainConfig(total_steps=100, warmup_steps=100, chunk_steps=50)
    with pytest.raises(ValueError, match="chunk_steps \\(1000\\) must not exceed total_steps \\(100\\)"):
        TrainConfig(total_steps=100, warmup_steps=10)
    with pytest.raises(ValueError, match="eval_steps must be a positive number of steps, not 0"):
        TrainConfig(eval_steps=0)


def test_swept_values_are_plain_fields_that_reach_what_they_set():
    spec = TrainConfig(algo_params=(("learning_rate", 0.001),), task_params=(("target_velocity", 0.3),))
    assert spec.agent_config.learning_rate == 0.001
    assert TrainConfig().agent_config.learning_rate == 0.005  # the protocol's CrossQ otherwise
    command = spec.make_task().command((), None)[1]
    assert float(command[0]) == pytest.approx(0.3)
    assert tasks.task_params("omni-pdec") == ("speed", "velocity_weight", "yaw_weight", "roll_pitch_weight",
                                              "energy_weight")
    assert TrainConfig(task_params=(("energy_weight", 0.0),)).make_task().weights["energy"] == 0.0


def test_the_trainer_and_the_on_robot_loop_share_the_spec():
    robot_run = RealtimeConfig(approach="jt-lpf", approach_params=(("cutoff_hz", 2.0),), algo_params=(("batch_size", 64),))
    assert isinstance(robot_run, RunSpec) and robot_run.agent_config.batch_size == 64
    # Only the protocol's default differs (a robot observes as the text says); the rest of the spec is one.
    base = {f.name: f for f in dataclasses.fields(RunSpec)}
    for kind, overridden in ((RealtimeConfig, {"protocol"}), (TrainConfig, set())):
        changed = {f.name for f in dataclasses.fields(kind) if f.name in base
                   and (f.default, f.default_factory) != (base[f.name].default, base[f.name].default_factory)}
        assert changed == overridden, kind
    # The same spec fields build the same agent and task in both.
    fields = dict(approach="jt-lpf", algo="sac", algo_params=(("batch_size", 64),), task_params=(("target_velocity", 0.3),))
    trainer_run = TrainConfig(protocol="thesis-text", **fields)
    robot_run = RealtimeConfig(**fields)
    assert robot_run.agent_config == trainer_run.agent_config
    assert robot_run.make_task().weights == trainer_run.make_task().weights
    with pytest.raises(ValueError, match="thesis-text protocol"):
        RealtimeConfig(protocol="thesis-code")
