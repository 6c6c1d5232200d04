"""Algorithm configurations (thesis Table 4.3; CrossQ paper defaults where it is silent)."""

import dataclasses
from typing import Callable, NamedTuple


@dataclasses.dataclass(frozen=True)
class AgentConfig:
    """Every choice of an agent of the SAC family, one named field each."""

    name: str
    learning_rate: float
    """Adam step size for actor, critic and temperature (Table 4.3)."""
    batch_size: int
    hidden: tuple = (256, 256)
    """Actor and critic hidden layers (Table 4.3: 256, 256)."""
    ensemble_size: int = 2
    gamma: float = 0.99
    target_entropy_per_action: float = -0.5
    """Target entropy = this x |A| (Table 4.3: -dim(A)/2) ..."""
    target_entropy: float | None = None
    """... unless this fixes it whatever |A| is (the released CrossQ scripts: -6)."""
    initial_alpha: float = 1.0
    adam_b1: float = 0.9
    log_std_clip: bool = False
    """Clip the actor's log-std to [-20, 2] (RL-X, the released code: std ~1 untrained); else squash it into [-10, 2]."""
    alpha_loss_scaled: bool = False
    """Temperature loss alpha (H - target), gradient alpha (H - target) on log alpha (RL-X); else log alpha (H - target)."""
    alpha_adam_b1: float | None = None
    """Adam b1 of the temperature; None: `adam_b1` (RL-X: optax's default 0.9 whatever the actor's)."""
    updates_per_step: int = 1
    """Gradient updates per environment step (the replay or UTD ratio)."""
    policy_delay: int = 1
    """Actor and temperature are updated on every n-th critic update ..."""
    actor_updates_per_step: int | None = None
    """... and at most this many times per environment step (None: no cap; RL-X's UTD and DroQ: 1)."""
    target_network: bool = True
    tau: float = 0.005
    """Polyak factor of the target critic; unused without a target network."""
    batch_renorm: bool = False
    """Batch renormalisation in the critic, fed the joint [s; s'] batch (CrossQ)."""
    renorm_momentum: float = 0.99
    renorm_warmup_steps: int = 100_000
    """Updates of plain batch normalisation before renormalisation starts."""
    actor_batch_renorm: bool = False
    """Batch renormalisation in the actor too, after its input and every hidden layer (the released CrossQ)."""
    dropout_rate: float = 0.0
    layer_norm: bool = False
    control_hz: float = 40.0
    """Control frequency the thesis ran this algorithm at (Table 4.3 'inference frequency')."""

    def __post_init__(self):
        if self.batch_renorm and self.target_network:
            raise ValueError(f"{self.name}: batch renormalisation is built for the joint pass without a target network")
        if self.batch_renorm and self.dropout_rate > 0:
            raise ValueError(f"{self.name}: dropout and batch renormalisation in one critic are not supported")
        if self.updates_per_step < 1 or self.policy_delay < 1:
            raise ValueError(f"{self.name}: updates_per_step and policy_delay must be >= 1")

    @property
    def is_crossq(self) -> bool:
        """CrossQ's kind of agent (batch renormalisation in the critic, so no target network): the one the protocols'
        CrossQ settings apply to, whatever name it is registered under."""
        return self.batch_renorm

    def replace(self, **changes) -> "AgentConfig":
        return dataclasses.replace(self, **changes)


def sac() -> AgentConfig:
    """SAC (Haarnoja et al.) as Table 4.3 ran it: target critics with Polyak averaging, 20 Hz."""
    return AgentConfig(name="sac", learning_rate=0.003, batch_size=256, control_hz=20.0)


def sac_utd20() -> AgentConfig:
    """SAC with 20 gradient updates per environment step (Table 4.3 'SAC UTD 20')."""
    return sac().replace(name="sac-utd20", updates_per_step=20)


def droq() -> AgentConfig:
    """DroQ (Hiraoka et al.): SAC's critic with dropout and layer norm, 20 updates per step."""
    return sac().replace(name="droq", learning_rate=0.001, updates_per_step=20, dropout_rate=0.01, layer_norm=True)


def crossq() -> AgentConfig:
    """CrossQ (Bhatt/Palenicek et al.): no target network, batch renorm, joint forward pass."""
    return AgentConfig(
        name="crossq",
        learning_rate=0.005,
        batch_size=128,
        target_network=False,
        batch_renorm=True,
        policy_delay=3,
        adam_b1=0.5,
        control_hz=40.0,
    )


class Algorithm(NamedTuple):
    """A registered algorithm: its configuration factory and how figures show it; calling it builds the config."""

    config: Callable
    label: str
    color: str

    def __call__(self) -> AgentConfig:
        return self.config()


ALGORITHMS = {
    "sac": Algorithm(sac, "SAC", "tab:gray"),
    "sac-utd20": Algorithm(sac_utd20, "SAC-UTD20", "tab:olive"),
    "droq": Algorithm(droq, "DroQ", "tab:cyan"),
    "crossq": Algorithm(crossq, "CrossQ", "tab:red"),
}
