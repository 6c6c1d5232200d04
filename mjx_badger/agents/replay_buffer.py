"""A uniform replay buffer as a pytree, so it can ride in the training loop's scan carry."""

import jax
import jax.numpy as jnp
from flax import struct

from mjx_badger.agents.losses import Transition


class ReplayBuffer(struct.PyTreeNode):
    """Ring buffer of transitions; `data` fields have a leading (capacity,) axis."""

    data: Transition
    position: jnp.ndarray
    size: jnp.ndarray


def init(capacity: int, obs_size: int, action_size: int) -> ReplayBuffer:
    """An empty buffer for `capacity` transitions."""
    data = Transition(
        obs=jnp.zeros((capacity, obs_size)),
        action=jnp.zeros((capacity, action_size)),
        reward=jnp.zeros((capacity,)),
        next_obs=jnp.zeros((capacity, obs_size)),
        discount=jnp.zeros((capacity,)),
    )
    return ReplayBuffer(data=data, position=jnp.int32(0), size=jnp.int32(0))


def add(buffer: ReplayBuffer, transition: Transition) -> ReplayBuffer:
    """Store one transition, overwriting the oldest when full."""
    return add_many(buffer, jax.tree.map(lambda x: jnp.asarray(x)[None], transition))


def sample(buffer: ReplayBuffer, key, batch_size: int) -> Transition:
    """A uniform batch (with replacement) of the stored transitions."""
    index = jax.random.randint(key, (batch_size,), 0, jnp.maximum(buffer.size, 1))
    return jax.tree.map(lambda store: store[index], buffer.data)


def add_many(buffer: ReplayBuffer, transitions: Transition) -> ReplayBuffer:
    """Store a batch of transitions (N, ...) in the next N slots, overwriting the oldest when full."""
    capacity = buffer.data.reward.shape[0]
    count = transitions.reward.shape[0]
    slots = (buffer.position + jnp.arange(count)) % capacity
    data = jax.tree.map(lambda store, x: store.at[slots].set(x), buffer.data, transitions)
    return buffer.replace(data=data, position=(buffer.position + count) % capacity,
                          size=jnp.minimum(buffer.size + count, capacity))
