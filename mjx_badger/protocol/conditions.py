"""On-robot conditions: the thesis's real-world experiments (§5.2) as frozen settings of the simulated robot.

`sim` is the simulation chapter's world and every experiment's default. `office` and `outdoor`
are what learning on the HB40 met: the reward and the observation see the onboard velocity
estimate, not the truth (§2.6.1: a Kalman filter over all four legs, which underestimates); the
sensors are noisy; a safety monitor stops the motors on a tilt or a joint out of range, the
episode ends as a fall, and an operator stands the robot up again, which costs wall time; and
the ground is a smooth office floor or outdoor cobblestones on a slope. Each field is one
factor, so `attribute` can swap one at a time (attribution.py).
"""

import dataclasses

from mjx_badger.core import validation
from mjx_badger.estimation import estimators
from mjx_badger.estimation.estimators import KalmanConfig
from mjx_badger.estimation.sensors import EXACT, Sensing
from mjx_badger.robot.terrain import Ground


@dataclasses.dataclass(frozen=True)
class Conditions:
    """What the robot learns under: its senses, its safety monitor, its ground."""

    name: str
    sensing: Sensing | None = None
    """Noisy sensors and an onboard velocity estimator (None: the simulator's truth, no estimate)."""
    estimate_in_loop: bool = False
    """The observation's trunk-velocity block and the reward's velocity are the estimate (§5.2: the robot had only it)."""
    safety_stop: bool = False
    """The robot stops itself, damping its motors (§5.2: P 0, D 3; the released code's collapse: D 5), counts a fall
    and ends the episode, in place of the protocol's termination rule. The rule is the protocol's robot's:
    thesis-code the released robot env's (heading pitched 30 deg, 4 rad/s, or 1.5 rad of roll or pitch),
    thesis-text the on-robot loop's monitor (the fall tilt, or a joint out of range)."""
    episode_seconds: float | None = None
    """Episode length on the robot (the released robot env: 20 s); None: the protocol's."""
    reset_seconds: float = 0.0
    """Wall time an operator needs to stand the robot up after a fall, added to the run's duration (assumed)."""
    ground: Ground = Ground()
    push_newtons: float = 0.0
    """Wind: a horizontal push of this size on the trunk, new direction each episode (0: none)."""
    robot_controller: bool = False
    """The joint-target approaches run on the robot's own PD controller (Kp 60, Kd 3) at their algorithm's rate
    (CrossQ 40 Hz, SAC-UTD20 20 Hz, §5.2), as the released on-robot scripts run them, in place of the simulation
    code's 25 / 1 at 50 Hz (thesis-code only; thesis-text is already so)."""
    cpg_swing_height_m: float | None = None
    """The CPG's swing apex (m); None: the simulation's 0.15 (§4.3). The robot swung 0.2 m (§5.2.1, CPG-D; the released
    robot CPG's beat generator), the agent's z-offset of up to 0.1 m on top as in simulation (the action's bound)."""
    cpg_frequency_hz: float | None = None
    """CPG-D's and CPG-RT's gait frequency (Hz); None: the simulation's 2. The released robot connection starts its
    CPG at 1.75 (honey_badger_ros/ros_connection/ros_connection.py); the thesis gives no figure for the robot."""
    robot_cpg_residual: bool = False
    """CPG-RT mixes the CPG's joint angles with its residuals in joint angles, as on the robot, in place of the
    simulation's torques: thesis-text their average (§4.3 item 2, §6.3), thesis-code the released robot CPG's sum."""
    stop_on_sensed: bool = True
    """The safety stop judges from what the robot senses (the IMU's noisy attitude and rates, the encoders), as the
    released monitor read its bridge data (ros_connection.py); False: from the simulator's truth. Either way a stop
    at which the truth shows no fall (tilt past the fall tilt, trunk below the fall height) counts as a stop before
    a fall, and one the same rule on the truth would not make as premature (§5.2.1, §6.4)."""

    def validate(self) -> None:
        self.ground.validate()
        if self.sensing is not None and self.sensing.estimator not in estimators.names():
            raise ValueError(f"unknown estimator {self.sensing.estimator!r}; choose from {', '.join(estimators.names())}")
        if self.estimate_in_loop and self.sensing is None:
            raise ValueError(f"conditions {self.name!r}: the estimate in the loop needs sensing")
        if self.reset_seconds < 0 or self.push_newtons < 0:
            raise ValueError(f"conditions {self.name!r}: reset_seconds and push_newtons must not be negative")
        if self.cpg_swing_height_m is not None and not 0.0 < self.cpg_swing_height_m <= 0.25:
            raise ValueError(f"conditions {self.name!r}: cpg_swing_height_m {self.cpg_swing_height_m:g} is not in "
                             f"(0, 0.25] m (a leg reaches about 0.3 m below its hip)")
        if self.cpg_frequency_hz is not None and not 0.5 <= self.cpg_frequency_hz <= 4.0:
            raise ValueError(f"conditions {self.name!r}: cpg_frequency_hz {self.cpg_frequency_hz:g} is not in "
                             f"[0.5, 4] Hz")

    def replace(self, **changes) -> "Conditions":
        """A copy with fields changed (a one-factor swap); `ground.<field>` names a ground field, `sensing` takes
        None, 'exact' (exact sensors, the default estimator) or an estimator's name (the default sensors with it)."""
        ground = {k.split(".", 1)[1]: v for k, v in changes.items() if k.startswith("ground.")}
        kalman = {k.split(".", 1)[1]: v for k, v in changes.items() if k.startswith("kalman.")}
        rest = {k: v for k, v in changes.items() if not k.startswith(("ground.", "kalman."))}
        fields = {f.name for f in dataclasses.fields(self)} - {"name", "ground"}
        kalman_fields = [f.name for f in dataclasses.fields(KalmanConfig)]
        unknown = (sorted(set(rest) - fields)
                   + [f"ground.{k}" for k in sorted(set(ground) - {f.name for f in dataclasses.fields(Ground)})]
                   + [f"kalman.{k}" for k in sorted(set(kalman) - set(kalman_fields))])
        if unknown:
            raise ValueError(f"unknown condition fields {', '.join(unknown)}; choose from {', '.join(sorted(fields))}, "
                             f"ground.{', ground.'.join(f.name for f in dataclasses.fields(Ground))}, "
                             f"kalman.{', kalman.'.join(kalman_fields)}")
        for key, value in kalman.items():  # the estimator's noise levels: the estimate's quality (docs/real-world.md)
            validation.number(f"condition field kalman.{key}", value, *KALMAN_RANGES[key])
        if isinstance(ground.get("friction"), (int, float)) and not isinstance(ground["friction"], bool):
            ground["friction"] = (float(ground["friction"]),) * 2
        # The kind of value each field holds (any of the defined conditions' kinds), before it is set.
        for key, value in rest.items():
            if key != "sensing":
                validation.like_any("condition field", key, value, [getattr(c, key) for c in CONDITIONS.values()])
            elif value is not None and not isinstance(value, (str, Sensing)):
                raise ValueError(f"condition field sensing takes None, 'exact' or an estimator's name, not {value!r}")
        for key, value in ground.items():
            validation.like_any("condition field", f"ground.{key}", value,
                                [getattr(c.ground, key) for c in CONDITIONS.values()])
        if rest.get("sensing") == "exact":
            rest["sensing"] = Sensing(sensors=EXACT)
        elif isinstance(rest.get("sensing"), str):
            rest["sensing"] = Sensing(estimator=rest["sensing"])
        out = dataclasses.replace(self, ground=dataclasses.replace(self.ground, **ground), **rest)
        if kalman:
            if out.sensing is None:
                raise ValueError(f"conditions {self.name!r}: kalman.* sets the estimator's noise, and these conditions "
                                 "sense nothing")
            out = dataclasses.replace(out, sensing=dataclasses.replace(
                out.sensing, kalman=dataclasses.replace(out.sensing.kalman, **kalman)))
        out.validate()
        return out


KALMAN_RANGES = {"acceleration_std": (1e-3, 100.0), "odometry_std": (1e-3, 100.0), "contact_trust": (0.0, 1.0)}
"""What `kalman.<field>` takes: noise levels (m/s^2, m/s) and the contact trust, a share."""

ADDED_LATER = {"cpg_swing_height_m": None, "cpg_frequency_hz": None, "robot_cpg_residual": False,
               "stop_on_sensed": True, "kalman.contact_trust": 0.0}
"""Fields added after results were first written, with the value every run had before: a file without one ran so."""


SIM = Conditions("sim")
"""The simulation chapter: true velocity, exact sensors, the protocol's termination rule, a flat floor."""

OFFICE = Conditions(
    "office",
    sensing=Sensing(),
    estimate_in_loop=True,
    safety_stop=True,
    reset_seconds=20.0,
    episode_seconds=20.0,
    ground=Ground(friction=(1.0, 1.0)),
    robot_controller=True,
    cpg_swing_height_m=0.2,
    cpg_frequency_hz=1.75,
    robot_cpg_residual=True,
)
"""§5.2.1: an office's smooth floor (friction 1.0, below the model's 1.1: assumed, and the lowest at which MJX's solver
holds with the model's impratio 100, see MIN_FRICTION), the estimate in the loop, the robot's own stop, and about 20 s
to carry the robot back and stand it up (assumed)."""

OUTDOOR = Conditions(
    "outdoor",
    sensing=Sensing(),
    estimate_in_loop=True,
    safety_stop=True,
    reset_seconds=20.0,
    episode_seconds=20.0,
    ground=Ground(terrain="cobblestones", friction=(1.0, 1.3), incline_deg=3.0, impratio=10.0),
    robot_controller=True,
    cpg_swing_height_m=0.2,
    cpg_frequency_hz=1.75,
    robot_cpg_residual=True,
)
"""§5.2.2-5.2.3: uneven cobblestones with a 3 degree incline, friction varying between spots (1.0-1.3, assumed: rough
stones, wet or dry), otherwise as the office. The contact solver runs at impratio 10 on the stones: at the model's 100
MJX blows up there (8 in 8000 random JT-NF steps, none on flat ground; a first JT-OEF run over and over), at 30 and
below it did not (docs/real-world/cobblestone_stability.json)."""

CONDITIONS = {c.name: c for c in (SIM, OFFICE, OUTDOOR)}

MIN_FRICTION = 1.0
"""Below this floor friction MJX's contact solver blows up on the HB40 with its model's impratio of 100 (non-finite
states: 269, 79, 23, 5 and 2 in 3200 random steps at 0.5, 0.6, 0.7, 0.8 and 0.9; none from 1.0, and none at any
friction with impratio 1; docs/real-world/friction_stability.json)."""


def check_friction(ground: Ground, impratio: float) -> None:
    """ValueError for a floor friction the solver cannot hold with a robot of this impratio, before anything compiles."""
    if impratio > 1.0 and ground.friction[0] < MIN_FRICTION:
        raise ValueError(f"ground friction {ground.friction[0]:g} is below {MIN_FRICTION:g}, where MJX's contact solver "
                         f"blows up with the robot's impratio {impratio:g} (docs/real-world/friction_stability.json); "
                         f"choose a friction of at least {MIN_FRICTION:g}")


def get(name: str, changes: tuple = ()) -> Conditions:
    """The conditions called `name` with `changes` ((field, value), ...); ValueError naming the choices."""
    if name not in CONDITIONS:
        raise ValueError(f"unknown conditions {name!r}; choose from {', '.join(CONDITIONS)}")
    return CONDITIONS[name].replace(**dict(changes)) if changes else CONDITIONS[name]
