"""The off-policy agents of the SAC family as configurations of shared pieces: networks, losses, the agent's
init/act/update (agent), the algorithm registry (config: SAC, SAC-UTD20, DroQ, CrossQ) and the replay buffer. An
agent sees only observation and action sizes. It may import core only; robot and tasks beside it are independent of it."""
