"""What the agents' tests share: a random batch of transitions and a CrossQ agent of the HB40's sizes."""

import jax
import jax.numpy as jnp
import pytest

from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.agents.losses import Transition

OBS, ACT, BATCH = 54, 12, 128
"""The JT approaches' observation and action sizes, and a batch."""


def random_batch(key) -> Transition:
    k = jax.random.split(key, 4)
    return Transition(
        obs=jax.random.normal(k[0], (BATCH, OBS)),
        action=jax.random.uniform(k[1], (BATCH, ACT), minval=-1, maxval=1),
        reward=jax.random.uniform(k[2], (BATCH,)) * 10,
        next_obs=jax.random.normal(k[3], (BATCH, OBS)),
        discount=jnp.ones(BATCH),
    )


@pytest.fixture(scope="module")
def crossq():
    return make_agent(ALGORITHMS["crossq"](), OBS, ACT)
