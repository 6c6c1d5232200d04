"""Off-policy agents of the SAC family as configurations of shared pieces."""

from mjx_badger.agents.agent import Agent, AgentState, make_agent
from mjx_badger.agents.config import ALGORITHMS, AgentConfig

__all__ = ["ALGORITHMS", "Agent", "AgentConfig", "AgentState", "make_agent"]
