"""Algorithm configurations (thesis Table 4.3; CrossQ paper defaults where it is silent)."""

import dataclasses
from typing import Callable, NamedTuple

from mjx_badger.agents.trunks import TRUNKS


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
    from_thesis: bool = True
    """One of the thesis's four, whose runs the protocols reproduce; a newer agent keeps its authors' settings
    under every protocol."""
    # The newer agents' components (docs/agents.md gives each one's source); the defaults are the thesis's agents.
    trunk: str = "mlp"
    """Network body of actor and critic (agents.trunks.TRUNKS)."""
    critic_hidden: tuple | None = None
    """The critic's widths; None: `hidden`."""
    log_std_range: tuple | None = None
    """Log-std bounds; None: [-10, 2] squashed, [-20, 2] clipped."""
    critic_output: str = "scalar"
    """'scalar' Q; 'categorical' over `atoms` in `value_range` (XQC, SimbaV2, FastSAC); 'quantile', `atoms`
    quantiles (BRO)."""
    atoms: int = 101
    value_range: tuple = (-5.0, 5.0)
    ensemble_rule: str = "min"
    """How the critics combine: 'min' (the target from the member with the lower Q, the actor on the lower Q),
    'mean' (both on the ensemble mean: BRO with its pessimism 0), 'own' (each member its own target, the actor on
    the mean: FastSAC)."""
    joint_pass: bool = False
    """With a target network, online and target critics each see [s; s'] in one training-mode pass (XQC)."""
    weight_norm: bool = False
    """After every optimiser step, each dense kernel's incoming weights are put back on the unit sphere."""
    observation_norm: bool = False
    """Observations standardised by their running moments."""
    reward_scaling: str = "none"
    """'none', 'return-std' (XQC) or 'return-std-gmax' (SimbaV2, with `g_max`): agents.normalisers."""
    g_max: float = 5.0
    adam_b2: float = 0.999
    weight_decay: float = 0.0
    """AdamW's decoupled weight decay on actor and critic; 0: Adam."""
    learning_rate_end: float | None = None
    """The learning rate falls linearly to this over the run's updates; None: constant."""
    resets: tuple = ()
    """Steps of the run at which every network and optimiser starts afresh, the replay kept (BRO; with several
    environments per seed, a step is one of each)."""
    optimism: bool = False
    """BRO's optimistic exploration policy (agents.optimism)."""
    alpha_every_update: bool = False
    """The temperature steps with every critic update, on the next states' log-probabilities (FastSAC); else with
    the actor, on its own samples'."""

    def __post_init__(self):
        if self.batch_renorm and self.target_network:
            raise ValueError(f"{self.name}: batch renormalisation is built for the joint pass without a target network")
        if self.batch_renorm and self.dropout_rate > 0:
            raise ValueError(f"{self.name}: dropout and batch renormalisation in one critic are not supported")
        if self.updates_per_step < 1 or self.policy_delay < 1:
            raise ValueError(f"{self.name}: updates_per_step and policy_delay must be >= 1")
        choices = (("trunk", TRUNKS), ("critic_output", ("scalar", "categorical", "quantile")),
                   ("ensemble_rule", ("min", "mean", "own")),
                   ("reward_scaling", ("none", "return-std", "return-std-gmax")))
        for field, valid in choices:
            if getattr(self, field) not in valid:
                raise ValueError(f"{self.name}: {field} {getattr(self, field)!r} is not one of {', '.join(valid)}")
        if self.joint_pass and not self.target_network:
            raise ValueError(f"{self.name}: joint_pass is for a target network (without one the pass is joint)")
        if self.optimism and self.ensemble_size != 2:
            raise ValueError(f"{self.name}: optimism bounds Q by the spread of exactly two critics")
        if self.trunk != "mlp" and (self.batch_renorm or self.dropout_rate or self.layer_norm):
            raise ValueError(f"{self.name}: batch renorm, dropout and layer norm belong to the 'mlp' trunk")

    @property
    def is_crossq(self) -> bool:
        """CrossQ's kind of agent (batch renormalisation in the critic, so no target network): the one the protocols'
        CrossQ settings apply to, whatever name it is registered under."""
        return self.batch_renorm

    def replace(self, **changes) -> "AgentConfig":
        return dataclasses.replace(self, **changes)


ADDED_LATER = ("from_thesis", "trunk", "critic_hidden", "log_std_range", "critic_output", "atoms", "value_range",
               "ensemble_rule", "joint_pass", "weight_norm", "observation_norm", "reward_scaling", "g_max", "adam_b2",
               "weight_decay", "learning_rate_end", "resets", "optimism", "alpha_every_update")
"""AgentConfig's fields added with the newer agents; a results file written before them ran their defaults."""


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


def xqc() -> AgentConfig:
    """XQC (Palenicek et al. 2025, CrossQ's successor): batch-normalised blocks on the unit sphere, a categorical
    critic, a target critic fed the joint batch, rewards scaled by the return's spread (RL-X xqc/)."""
    return AgentConfig(
        name="xqc", learning_rate=3e-4, learning_rate_end=3e-5, batch_size=256, updates_per_step=2, policy_delay=3,
        trunk="xqc", hidden=(256,) * 4, critic_hidden=(512,) * 4, critic_output="categorical", joint_pass=True,
        weight_norm=True, reward_scaling="return-std", initial_alpha=0.01, log_std_clip=True,
        log_std_range=(-10.0, 2.0), alpha_loss_scaled=True, from_thesis=False)


def simbav2() -> AgentConfig:
    """SimbaV2 (Lee et al. 2025): hyperspherical networks with learned scalers, a categorical critic, observations
    and rewards normalised (RL-X simbav2/, the authors' head scalers)."""
    return AgentConfig(
        name="simbav2", learning_rate=1e-4, learning_rate_end=5e-5, batch_size=256, updates_per_step=2,
        trunk="simba", hidden=(128,) * 2, critic_hidden=(512,) * 3, critic_output="categorical", weight_norm=True,
        observation_norm=True, reward_scaling="return-std-gmax", initial_alpha=0.01, alpha_loss_scaled=True,
        from_thesis=False)


def bro() -> AgentConfig:
    """BRO (Nauman et al. 2024): wide residual layer-norm networks, quantile critics on their mean, AdamW, ten
    updates per step, a reset at 15k steps and an optimistic exploration policy (RL-X bro/)."""
    return AgentConfig(
        name="bro", learning_rate=3e-4, batch_size=128, updates_per_step=10, trunk="bro", hidden=(256,) * 2,
        critic_hidden=(512,) * 3, critic_output="quantile", atoms=100, ensemble_rule="mean", weight_decay=1e-4,
        alpha_adam_b1=0.5, resets=(15_000,), optimism=True, alpha_loss_scaled=True, from_thesis=False)


def fastsac() -> AgentConfig:
    """FastSAC (2025, SAC for thousands of parallel environments): layer-norm SiLU networks, a categorical critic per
    member averaged for the actor, AdamW, a low starting temperature, standardised observations (RL-X fastsac/).
    One environment per seed here: batch 256 is this suite's assumption where FastSAC draws 8,192 from thousands."""
    return AgentConfig(
        name="fastsac", learning_rate=3e-4, batch_size=256, updates_per_step=8, policy_delay=4, gamma=0.97,
        tau=0.125, trunk="layernorm", hidden=(512, 256, 128), critic_hidden=(768, 384, 192),
        critic_output="categorical", value_range=(-20.0, 20.0), ensemble_rule="own", observation_norm=True,
        adam_b2=0.95, weight_decay=1e-3, initial_alpha=1e-3, target_entropy=0.0, log_std_range=(-5.0, 0.0),
        alpha_every_update=True, alpha_loss_scaled=True, from_thesis=False)


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
    "xqc": Algorithm(xqc, "XQC", "tab:purple"),
    "simbav2": Algorithm(simbav2, "SimbaV2", "tab:green"),
    "bro": Algorithm(bro, "BRO", "tab:brown"),
    "fastsac": Algorithm(fastsac, "FastSAC", "tab:blue"),
}
THESIS_ALGORITHMS = ("sac", "sac-utd20", "droq", "crossq")
