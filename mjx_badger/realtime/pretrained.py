"""The on-robot loop started from an agent trained in MJX: `realtime --init-from RESULTS --init-seed K`.

The run's whole final agent (actor, critic, targets, temperature, optimiser states; the
`.agents` folder beside its results file) is loaded for one seed, and learning goes on from it
on the robot. The MJX run must have observed as the robot does (thesis-text) with the same
approach, algorithm, network sizes and robot.
"""

import jax

from mjx_badger.learning import checkpoints
from mjx_badger.records import results


def check(config) -> None:
    """Raise ValueError naming what makes `config.init_from` unusable for `config`."""
    from pathlib import Path

    path = Path(config.init_from)
    if not path.exists():
        raise ValueError(f"--init-from: no results file {str(path)!r}")
    document = results.read(path)
    trained = document["config"]
    for field, wanted in (("protocol", "thesis-text"), ("approach", config.approach), ("algo", config.algo),
                          ("robot", config.robot)):
        if trained.get(field, "hb40") != wanted:
            raise ValueError(f"--init-from {path.name}: its {field} is {trained.get(field)!r}, this run's {wanted!r}")
    if list(trained["agent"]["hidden"]) != list(config.agent_config.hidden):
        raise ValueError(f"--init-from {path.name}: its networks are {trained['agent']['hidden']}, "
                         f"this run's {list(config.agent_config.hidden)}")
    if "agents" not in document or not (path.parent / document["agents"]).is_dir():
        raise ValueError(f"--init-from {path.name}: no saved agents beside it (runs keep them since they are saved)")
    if config.init_seed not in document["seeds"]:
        raise ValueError(f"--init-from {path.name} holds seeds {document['seeds']}, not {config.init_seed}")
    if config.init_seed in results.diverged(document):
        raise ValueError(f"--init-from {path.name}: seed {config.init_seed} diverged in training; choose another")


def load(config, agent):
    """The AgentState of seed `config.init_seed` of the run `config.init_from`."""
    document = results.read(config.init_from)
    seeds = document["seeds"]
    like = jax.vmap(agent.init)(jax.random.split(jax.random.PRNGKey(0), len(seeds)))
    agents = checkpoints.load_agents(config.init_from, like)
    return jax.tree.map(lambda x: x[seeds.index(config.init_seed)], agents)
