"""An agent: init, act and update from its configuration; CrossQ's actor moves once per policy delay; the newer
agents' components hold after an update."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.agents import agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.learning.config import TrainConfig
from tests.agents.conftest import ACT, OBS, random_batch


def test_actor_updates_only_every_policy_delay(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    batch = random_batch(jax.random.PRNGKey(1))
    update = jax.jit(crossq.update)
    moved = []
    for i in range(6):
        new, metrics = update(state, batch, jax.random.PRNGKey(i), i)
        changed = jax.tree.leaves(jax.tree.map(lambda a, b: bool(jnp.any(a != b)), new.actor_params,
                                               state.actor_params))
        moved.append(any(changed))
        assert np.isnan(metrics["actor_loss"]) != moved[-1]
        state = new
    assert moved == [True, False, False, True, False, False]


def test_an_agent_counts_its_updates_and_crossq_has_no_target_network(crossq):
    state = crossq.init(jax.random.PRNGKey(0))
    assert isinstance(state, agent.AgentState) and int(state.updates) == 0 and state.target_params is None
    state, _ = jax.jit(crossq.update)(state, random_batch(jax.random.PRNGKey(1)), jax.random.PRNGKey(2), 0)
    assert int(state.updates) == 1  # the program the policy-delay test compiled: nothing new compiles
    assert ALGORITHMS["sac"]().target_network and not ALGORITHMS["crossq"]().target_network


NEWER = ("xqc", "simbav2", "bro", "fastsac")


def tiny(name):
    """A newer agent at toy widths: the same components and programs' shapes of logic, quick to compile and run."""
    cfg = ALGORITHMS[name]()
    return cfg.replace(hidden=(16,) * len(cfg.hidden), critic_hidden=(16,) * len(cfg.critic_hidden), atoms=11)


def test_the_learning_rate_falls_linearly_over_the_run():
    xqc, simba = ALGORITHMS["xqc"](), ALGORITHMS["simbav2"]()
    assert abs(float(agent.learning_rate(xqc, 50, 100)) - 1.65e-4) < 1e-9  # 3e-4 halfway to 3e-5
    assert abs(float(agent.learning_rate(simba, 1_000_000, 2_000_000)) - 7.5e-5) < 1e-9
    assert abs(float(agent.learning_rate(simba, 5_000_000, 2_000_000)) - 5e-5) < 1e-9  # and stays at its end


@pytest.mark.parametrize("name", NEWER)
def test_a_newer_agent_learns_and_keeps_what_its_components_promise(name):
    cfg = tiny(name)
    learner = agent.make_agent(cfg, OBS, ACT, total_updates=10)
    state = jax.jit(learner.init)(jax.random.PRNGKey(0))
    obs = jax.random.normal(jax.random.PRNGKey(3), (OBS,)) * 5 + 2
    observed = learner.observe(state, obs, 2.0, 0.0)
    if cfg.observation_norm or cfg.reward_scaling != "none":
        assert float(observed.normaliser["obs"].count) > 0.9 and float(observed.normaliser["reward"].largest) == 2.0
    else:
        assert observed is state
    update = jax.jit(learner.update)
    new, metrics = update(observed, random_batch(jax.random.PRNGKey(1)), jax.random.PRNGKey(2), 0)
    assert all(np.isfinite(float(v)) for v in metrics.values()), metrics  # update 0 is every agent's actor update
    moved = lambda a, b: any(jax.tree.leaves(jax.tree.map(lambda x, y: bool(jnp.any(x != y)), a, b)))
    assert moved(new.critic_params, state.critic_params) and moved(new.actor_params, state.actor_params)
    if cfg.weight_norm:  # every dense kernel is back on the unit sphere after the step
        for params in (new.critic_params, new.actor_params):
            for path, leaf in jax.tree_util.tree_leaves_with_path(params):
                if path[-1].key == "kernel":
                    np.testing.assert_allclose(jnp.linalg.norm(leaf, axis=-2), 1.0, rtol=1e-5)
    if cfg.optimism:  # the optimistic actor and its adjustments moved with the main actor
        assert moved(new.optimism.params, state.optimism.params) and float(new.optimism.beta) != float(
            state.optimism.beta)
        action = learner.act(new, obs, jax.random.PRNGKey(4))
        assert action.shape == (ACT,) and float(jnp.abs(action).max()) <= 1.0
    if cfg.policy_delay > 1:  # an update without the actor's: the temperature moves only if it steps every update
        second, _ = update(new, random_batch(jax.random.PRNGKey(5)), jax.random.PRNGKey(6), 1)
        assert not moved(second.actor_params, new.actor_params)
        assert (float(second.log_alpha) != float(new.log_alpha)) == cfg.alpha_every_update
    if cfg.resets:  # a reset is the first initialisation again, the update count kept
        again = learner.reset(new, jax.random.PRNGKey(0))
        assert int(again.updates) == 1 and not moved(again.critic_params, state.critic_params)


def test_the_newer_agents_are_their_authors_settings_under_every_protocol():
    expected = {  # lr, batch, updates per step, policy delay, body, critic output, ensemble rule (docs/agents.md)
        "xqc": (3e-4, 256, 2, 3, "xqc", "categorical", "min"),
        "simbav2": (1e-4, 256, 2, 1, "simba", "categorical", "min"),
        "bro": (3e-4, 128, 10, 1, "bro", "quantile", "mean"),
        "fastsac": (3e-4, 256, 8, 4, "layernorm", "categorical", "own"),
    }
    for name, values in expected.items():
        cfg = ALGORITHMS[name]()
        assert (cfg.learning_rate, cfg.batch_size, cfg.updates_per_step, cfg.policy_delay, cfg.trunk,
                cfg.critic_output, cfg.ensemble_rule) == values
        assert not cfg.from_thesis and not cfg.is_crossq
        for protocol in ("thesis-code", "thesis-text"):
            assert TrainConfig(algo=name, protocol=protocol).agent_config == cfg
    bro = ALGORITHMS["bro"]()
    assert bro.resets == (15_000,) and bro.optimism and bro.atoms == 100 and bro.weight_decay == 1e-4
    assert ALGORITHMS["xqc"]().joint_pass and ALGORITHMS["xqc"]().reward_scaling == "return-std"
    assert ALGORITHMS["simbav2"]().reward_scaling == "return-std-gmax" and ALGORITHMS["simbav2"]().observation_norm
    assert ALGORITHMS["fastsac"]().value_range == (-20.0, 20.0) and ALGORITHMS["fastsac"]().target_entropy == 0.0
