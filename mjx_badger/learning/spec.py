"""RunSpec: what one run trains, shared by the vmapped trainer and the on-robot loop, checked when built.

A run is a robot, an approach, an algorithm, a task and a protocol, each with its keyword
parameters as plain `((name, value), ...)` fields, the values a sweep changes (a filter
cutoff, a target speed, a learning rate). Building a spec checks every name against its
registry and every parameter against what its owner takes, and names the valid choices.
"""

import dataclasses

from mjx_badger.agents.config import ALGORITHMS, AgentConfig
from mjx_badger.control import actions
from mjx_badger.core import validation
from mjx_badger.core.options import pairs
from mjx_badger.protocol import conditions as on_robot
from mjx_badger.protocol import protocols
from mjx_badger.protocol.protocols import Protocol
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf
from mjx_badger.tasks import locomotion as tasks

AGENT_FIELDS = tuple(f.name for f in dataclasses.fields(AgentConfig) if f.name != "name")
OPTIONAL_AGENT_FIELDS = tuple(f.name for f in dataclasses.fields(AgentConfig) if "None" in str(f.type))


def protocol_words(field: str) -> tuple:
    """The words a protocol field of words takes: the protocols' own values (and the CPG's other residual modes)."""
    values = [getattr(p, field) for p in protocols.PROTOCOLS.values()]
    if not all(isinstance(v, str) for v in values):
        return ()
    extra = actions.RESIDUAL_MODES if field == "cpg_residual" else ()
    return tuple(dict.fromkeys([*values, *extra]))


@dataclasses.dataclass(frozen=True)
class RunSpec:
    """What a run trains: robot, approach, algorithm, task and protocol, with their parameters."""

    approach: str = "jt-oef"
    """An action space of actions.APPROACHES: 'jt-nf', 'jt-lpf', 'jt-oef', 'cpg-d', 'cpg-vf', 'cpg-rt', ..."""
    algo: str = "crossq"
    """An algorithm of agents.config.ALGORITHMS: the thesis's 'sac', 'sac-utd20', 'droq', 'crossq'; 'xqc', 'simbav2', 'bro', 'fastsac'."""
    task: str = "forward"
    """A task of tasks.locomotion.TASKS: 'forward', 'forward-max', 'omni-random', 'omni-pdec', ..."""
    protocol: str = "thesis-code"
    """'thesis-code' (as the released code ran it) or 'thesis-text' (as the thesis reads); protocols.py."""
    protocol_changes: pairs("--set") = ()
    """One-factor swaps of protocol fields, e.g. action_delay=False (`list` names the fields)."""
    approach_params: pairs("--approach-param") = ()
    """The approach's keyword parameters, e.g. cutoff_hz=2.0 for jt-lpf (`list` shows which each takes)."""
    algo_params: pairs("--algo-param") = ()
    """AgentConfig fields set on the protocol's configuration of `algo`, e.g. learning_rate=0.001."""
    task_params: pairs("--task-param") = ()
    """The task's keyword parameters, e.g. target_velocity=0.3 for forward."""
    robot: str = "hb40"
    """The robot description (robot.description.ROBOTS): 'hb40', the thesis code's, or 'hb40-v1', this suite's first."""
    conditions: str = "sim"
    """'sim' (the simulation chapter), or on-robot 'office' or 'outdoor' (§5.2; conditions.py)."""
    condition_changes: pairs("--condition") = ()
    """One-factor swaps of the conditions' fields, e.g. estimate_in_loop=False or ground.incline_deg=0."""

    def __post_init__(self):
        self.validate()

    def validate(self) -> None:
        """Raise ValueError naming the valid choices for any unknown name or parameter, before anything compiles."""
        for what, value, valid in (("approach", self.approach, actions.APPROACHES),
                                   ("algorithm", self.algo, ALGORITHMS), ("task", self.task, tasks.TASKS),
                                   ("protocol", self.protocol, protocols.PROTOCOLS),
                                   ("robot", self.robot, robot.ROBOTS),
                                   ("conditions", self.conditions, on_robot.CONDITIONS)):
            if value not in valid:
                raise ValueError(f"unknown {what} {value!r}; choose from {', '.join(valid)}")
        for field, value in self.protocol_changes:  # the kind of value each field holds, before it is set
            if field in protocols.FIELDS:
                validation.like_any("protocol field", field, value,
                                    [getattr(p, field) for p in protocols.PROTOCOLS.values()])
                words = protocol_words(field)
                if words and value not in words:
                    raise ValueError(f"protocol field {field} takes {', '.join(words)}, not {value!r}")
        self.protocol_spec  # unknown protocol fields raise here
        ground = self.conditions_spec.ground  # unknown or invalid condition fields raise here
        on_robot.check_friction(ground, ground.impratio_with(self.robot_spec.impratio))
        if ground.terrain != "flat":  # and parts MJX cannot collide with a height field here (a model, no compile)
            mjcf.load_model(self.robot_spec, ground=ground)
        actions.check_params(self.approach, dict(self.approach_params))
        actions.check_robot(self.approach, self.robot_spec, self.protocol_spec)
        tasks.check_params(self.task, dict(self.task_params), self.protocol_spec.rewards)
        unknown = sorted(set(dict(self.algo_params)) - set(AGENT_FIELDS))
        if unknown:
            raise ValueError(f"algorithm parameters {', '.join(unknown)} are not AgentConfig fields; "
                             f"choose from {', '.join(AGENT_FIELDS)}")
        validation.params("approach parameter", self.approach_params)
        validation.params("task parameter", self.task_params)
        agent = self.protocol_spec.agent_config(self.algo)
        for name, value in self.algo_params:  # None where the field may be None (target_entropy), else its kind
            if not (value is None and name in OPTIONAL_AGENT_FIELDS):
                validation.like("algorithm parameter", name, value, getattr(agent, name))

    @property
    def robot_spec(self) -> "robot.RobotSpec":
        """The robot description `robot` names."""
        return robot.ROBOTS[self.robot]

    @property
    def protocol_spec(self) -> Protocol:
        """The protocol with its swaps; on a robot (conditions.robot_controller) JT runs on the robot's own PD
        controller at the algorithm's rate, as the released on-robot scripts do, and episodes last the robot's."""
        spec = protocols.get(self.protocol, self.protocol_changes)
        on_robot = self.conditions_spec
        if on_robot.robot_controller:
            spec = spec.replace(jt_pd_gains=self.robot_spec.pd_gains, jt_control_hz=None)
        if on_robot.episode_seconds is not None:
            spec = spec.replace(episode_seconds=on_robot.episode_seconds)
        return spec

    @property
    def conditions_spec(self) -> on_robot.Conditions:
        """The conditions with their swaps (conditions.get)."""
        return on_robot.get(self.conditions, self.condition_changes)

    @property
    def agent_config(self) -> AgentConfig:
        """The protocol's configuration of `algo` with `algo_params` set."""
        return self.protocol_spec.agent_config(self.algo).replace(**dict(self.algo_params))

    def make_task(self) -> tasks.Task:
        """The task under the protocol's reward forms and curriculum rules, with `task_params`."""
        spec = self.protocol_spec
        return tasks.make_task(self.task, spec.rewards, spec.curriculum, **dict(self.task_params))

    @property
    def name(self) -> str:
        return f"{self.approach}_{self.algo}_{self.task}"
