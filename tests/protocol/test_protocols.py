"""Every protocol field is applied: each test fails if its field were ignored."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.losses import Transition, make_losses
from mjx_badger.agents.networks import Actor, Critic
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
from mjx_badger.protocol import protocols
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.tasks import curriculum
from mjx_badger.tasks import locomotion as tasks

CODE, TEXT = protocols.THESIS_CODE, protocols.THESIS_TEXT


def test_the_two_protocols_differ_in_every_field_and_are_frozen():
    for field in protocols.FIELDS:
        if field not in ("cpg_pd_gains",):  # the one figure both share, kept as a field for swaps
            assert getattr(CODE, field) != getattr(TEXT, field), field
    with pytest.raises(dataclasses.FrozenInstanceError):
        CODE.episode_seconds = 20.0
    with pytest.raises(ValueError, match="unknown protocol field"):
        CODE.replace(no_such_field=1)
    with pytest.raises(ValueError, match="thesis-code, thesis-text"):
        protocols.get("thesis-paper")
    assert protocols.other_value("lowpass", "thesis-code") == "first-order"


def test_the_env_takes_its_reward_forms_curriculum_and_cpg_termination_from_the_protocol():
    cmd, fast = jnp.array([0.5, 0.0, 0.0]), tasks.Motion(jnp.array([1.1, 0.0, 0.0]), jnp.zeros(3), 0.0, 0.0, jnp.zeros(12))
    rewards = {form: float(HB40Env("jt-nf", "forward", EnvConfig(protocol=CODE.replace(rewards=form)))
                     .task.reward(fast, cmd)[0]) for form in ("thesis-code", "thesis-text")}
    assert rewards == pytest.approx({"thesis-code": 4.0, "thesis-text": 9.0}, abs=1e-5)  # as in the test above
    state = curriculum.init()._replace(learned=jnp.array([2, 2], jnp.int32))
    speeds = {}
    for rules in ("thesis-code", "thesis-text"):
        task = HB40Env("cpg-d", "omni-pdec", EnvConfig(protocol=CODE.replace(curriculum=rules))).task
        speeds[rules] = {round(float(jnp.linalg.norm(task.command(state, k)[1][:2])), 4)
                         for k in jax.random.split(jax.random.PRNGKey(3), 20)}
    assert len(speeds["thesis-code"]) > 2 and speeds["thesis-text"] == {0.25}
    for protocol, cpg_ends in ((CODE, False), (TEXT, True), (CODE.replace(cpg_terminates=True), True)):
        assert HB40Env("cpg-d", "forward", EnvConfig(protocol=protocol)).terminates == cpg_ends
        assert HB40Env("jt-nf", "forward", EnvConfig(protocol=protocol)).terminates


def test_the_renorm_warmup_reaches_the_networks():
    """Past its warm-up batch renorm corrects by r and d, so a 1-update warm-up changes the third update."""
    losses = {}
    for warmup in (1, 1000):
        cfg = TrainConfig(algo="crossq", protocol_changes=(("crossq_renorm_warmup", warmup),)).agent_config
        agent = make_agent(cfg.replace(hidden=(8,)), 4, 2)
        update = jax.jit(agent.update)
        state = agent.init(jax.random.PRNGKey(0))
        for i in range(3):
            batch = _batch()
            batch = batch._replace(obs=batch.obs * (1 + 2 * i) + 3 * i, next_obs=batch.next_obs + 3 * i)
            state, metrics = update(state, batch, jax.random.PRNGKey(i), i)
            losses.setdefault(warmup, []).append(float(metrics["critic_loss"]))
    assert losses[1][0] == pytest.approx(losses[1000][0], rel=1e-6)  # the first update is inside both warm-ups
    assert abs(losses[1][2] - losses[1000][2]) > 1e-4 * abs(losses[1000][2])


TINY = dict(approach="jt-nf", algo="crossq", task="forward", total_steps=40, chunk_steps=20, warmup_steps=20,
            eval_steps=5)


def _warm_up(protocol: str, changes: tuple = ()):
    """The warm-up steps of one seed as the chunk scans them (Trainer.step), without the chunk's evaluation: half
    the program to compile. Returns (trainer, carry after them, per-step metrics)."""
    config = TrainConfig(protocol=protocol, protocol_changes=changes, **TINY)
    trainer = make_train(config)
    carry = jax.jit(trainer.init)(jax.random.PRNGKey(0))
    scan = jax.jit(lambda carry: jax.lax.scan(trainer.step, carry, jnp.arange(config.warmup_steps)))
    carry, steps = scan(carry)
    return trainer, carry, steps


def test_truncation_bootstraps_from_the_next_episodes_start_under_the_code():
    """5-step (code, 50 Hz) or 4-step (text, 40 Hz) episodes of random warm-up actions, which do not tip the robot."""
    for name in ("thesis-code", "thesis-text"):
        trainer, carry, steps = _warm_up(name, (("episode_seconds", 0.1), ("action_delay", False)))
        assert float(steps["falls_total"][-1]) == 0.0
        assert float(steps["episode_end"].sum()) >= 4  # the rows below are episode ends
        data = jax.tree.map(np.asarray, carry.buffer.data)
        last = trainer.env.episode_steps - 1  # the first episode's time-out row
        assert data.discount[last] == 1.0
        same = np.allclose(data.next_obs[last], data.obs[last + 1], atol=1e-6)
        assert same == (name == "thesis-code"), name


def test_falls_in_the_warm_up_are_counted_only_under_the_text(monkeypatch):
    """With every step a fall, the 20 warm-up steps count 20 falls under the text and none under the code."""
    monkeypatch.setattr(HB40Env, "_fall_rule", lambda self, data, motion, power_steps: jnp.bool_(True))
    _, _, code = _warm_up("thesis-code")
    _, _, text = _warm_up("thesis-text")
    assert float(code["falls_total"][-1]) == 20.0 and float(code["falls"][-1]) == 0.0
    assert float(text["falls"][-1]) == 20.0


def _batch(obs=4, act=2, n=8):
    keys = jax.random.split(jax.random.PRNGKey(0), 4)
    return Transition(jax.random.normal(keys[0], (n, obs)), jax.random.uniform(keys[1], (n, act), minval=-1),
                      jax.random.normal(keys[2], (n,)), jax.random.normal(keys[3], (n, obs)), jnp.ones(n))


def test_crossq_under_the_code_renormalises_the_actor_and_updates_it_every_step():
    cfg = TrainConfig(algo="crossq").agent_config.replace(hidden=(8,))
    agent = make_agent(cfg, 4, 2)
    state = agent.init(jax.random.PRNGKey(0))
    assert state.actor_stats, "the actor has no batch statistics"
    new, metrics = jax.jit(agent.update)(state, _batch(), jax.random.PRNGKey(1), 1)  # index 1: not a multiple of 3
    assert np.isfinite(float(metrics["actor_loss"]))  # policy delay 1: the actor moved
    moved = jax.tree.leaves(jax.tree.map(lambda a, b: bool(jnp.any(a != b)), new.actor_stats, state.actor_stats))
    assert any(moved), "the actor's batch statistics did not update"
    text = TrainConfig(algo="crossq", protocol="thesis-text").agent_config.replace(hidden=(8,))
    text_agent = make_agent(text, 4, 2)
    _, text_metrics = jax.jit(text_agent.update)(text_agent.init(jax.random.PRNGKey(0)), _batch(),
                                                 jax.random.PRNGKey(1), 1)
    assert np.isnan(float(text_metrics["actor_loss"]))  # policy delay 3: not this update


def test_target_entropy_is_minus_6_under_the_code():
    cfg = TrainConfig(algo="crossq").agent_config.replace(hidden=(8,))

    losses = make_losses(Actor(2), Critic(), cfg, 2)
    # The code's J = -mean(alpha (log pi + H)): with log alpha = 1 and log pi = 0 it is -e H = 6 e.
    assert float(losses.alpha(jnp.float32(1.0), jnp.zeros(3))) == pytest.approx(6.0 * np.e)
    text = TrainConfig(algo="crossq", protocol="thesis-text").agent_config
    assert float(make_losses(Actor(2), Critic(), text, 2).alpha(jnp.float32(1.0), jnp.zeros(3))) == pytest.approx(1.0)


def test_the_codes_temperature_uses_adam_with_b1_0_9_whatever_the_actors():
    cfg = TrainConfig(algo="crossq").agent_config.replace(hidden=(8,))
    assert cfg.adam_b1 == 0.5 and cfg.alpha_adam_b1 == 0.9
    log_alphas = []
    for variant in (cfg, cfg.replace(alpha_adam_b1=None)):  # None: the actor's b1 0.5
        agent = make_agent(variant, 4, 2)
        state, update = agent.init(jax.random.PRNGKey(0)), jax.jit(agent.update)
        for index in range(3):
            state, _ = update(state, _batch(), jax.random.PRNGKey(index), index)
        log_alphas.append(float(state.log_alpha))
    assert log_alphas[0] != pytest.approx(log_alphas[1], abs=1e-7)
    assert TrainConfig(algo="crossq", protocol="thesis-text").agent_config.alpha_adam_b1 is None


def test_an_untrained_actor_explores_with_std_1_under_the_code():
    """RL-X clips the raw log-std (0 for a zero input: std 1) to [-20, 2]; the text's squash maps 0 to std e^-4."""
    obs = jnp.zeros((256, 4))  # zero features: the mean and raw log-std are their zero biases
    for protocol, low, high in (("thesis-code", 0.3, 1.0), ("thesis-text", 0.0, 0.05)):
        for algo in ("crossq", "sac"):
            agent = make_agent(TrainConfig(algo=algo, protocol=protocol).agent_config.replace(hidden=(8,)), 4, 12)
            actions = agent.act(agent.init(jax.random.PRNGKey(0)), obs, jax.random.PRNGKey(1))
            assert low < float(jnp.std(actions)) < high, (protocol, algo, float(jnp.std(actions)))


def test_only_the_released_crossq_bootstraps_a_time_out_from_the_next_episode():
    assert CODE.bootstraps_from_next_episode("crossq")
    assert not any(CODE.bootstraps_from_next_episode(a) for a in ("sac", "sac-utd20", "droq"))
    assert not TEXT.bootstraps_from_next_episode("crossq")


def test_renorm_warmup_is_the_codes_1000_updates():
    assert TrainConfig(algo="crossq").agent_config.renorm_warmup_steps == 1000
    assert TrainConfig(algo="crossq", protocol="thesis-text").agent_config.renorm_warmup_steps == 100_000


def test_many_update_algorithms_move_the_actor_once_per_step_under_the_code():
    cfg = TrainConfig(algo="droq").agent_config.replace(hidden=(8,), updates_per_step=4)
    agent = make_agent(cfg, 4, 2)
    state = agent.init(jax.random.PRNGKey(0))
    update = jax.jit(agent.update)
    moved = []
    for index in range(8):
        state, metrics = update(state, _batch(), jax.random.PRNGKey(index), index)
        moved.append(bool(np.isfinite(float(metrics["actor_loss"]))))
    assert moved == [False, False, False, True] * 2  # the last of each step's critic updates
    text = TrainConfig(algo="droq", protocol="thesis-text").agent_config
    assert text.actor_updates_per_step is None


