"""The replay buffer: a ring that overwrites its oldest transition, sampled uniformly from what it holds."""

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import replay_buffer
from mjx_badger.agents.losses import Transition


def _transition(k: float) -> Transition:
    return Transition(obs=jnp.full(2, k), action=jnp.full(1, -k), reward=jnp.float32(k), next_obs=jnp.full(2, k + 1),
                      discount=jnp.float32(1.0))


def test_a_full_ring_overwrites_its_oldest_transition():
    buffer = replay_buffer.init(3, obs_size=2, action_size=1)
    assert int(buffer.size) == 0 and buffer.data.obs.shape == (3, 2)
    for k in range(1, 6):  # 1, 2, 3 fill it; 4 and 5 replace 1 and 2
        buffer = replay_buffer.add(buffer, _transition(float(k)))
    assert int(buffer.size) == 3 and int(buffer.position) == 2
    np.testing.assert_array_equal(buffer.data.reward, [4.0, 5.0, 3.0])
    np.testing.assert_array_equal(buffer.data.next_obs[:, 0], [5.0, 6.0, 4.0])


def test_a_batch_comes_only_from_the_filled_part():
    buffer = replay_buffer.init(100, obs_size=2, action_size=1)
    for k in range(1, 4):
        buffer = replay_buffer.add(buffer, _transition(float(k)))
    batch = replay_buffer.sample(buffer, jax.random.PRNGKey(0), 256)
    assert batch.obs.shape == (256, 2) and set(np.unique(batch.reward).tolist()) == {1.0, 2.0, 3.0}
    np.testing.assert_array_equal(batch.action[:, 0], -batch.reward)  # each row one whole transition


def test_several_environments_steps_land_in_consecutive_slots_and_wrap():
    buffer = replay_buffer.init(5, obs_size=2, action_size=1)
    many = lambda ks: jax.tree.map(lambda *x: jnp.stack(x), *[_transition(float(k)) for k in ks])
    buffer = replay_buffer.add_many(buffer, many([1, 2, 3]))
    buffer = replay_buffer.add_many(buffer, many([4, 5, 6]))  # 6 replaces 1, the oldest
    assert int(buffer.size) == 5 and int(buffer.position) == 1
    np.testing.assert_array_equal(buffer.data.reward, [6.0, 2.0, 3.0, 4.0, 5.0])
