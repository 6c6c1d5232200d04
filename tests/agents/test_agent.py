"""An agent: init, act and update from its configuration; CrossQ's actor moves once per policy delay."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import agent
from mjx_badger.agents.config import ALGORITHMS
from tests.agents.conftest import random_batch


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
