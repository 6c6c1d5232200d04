"""A saved policy run on the robot's own computer without JAX: the thesis's test mode, deterministic, at its rate.

`outputs/onnx_export.export` writes the actor as `<name>.onnx` and beside it `<name>.onboard.json`, everything
else the robot needs (schema SCHEMA). `OnboardPolicy(path).step(...)` then does in NumPy what the on-robot
loop's jitted evaluation tick does (realtime/control.evaluate_tick with realtime/estimation.VelocityEstimator):
the Kalman velocity estimate (onboard_estimator.py), the observation of sim/observation.py, the actor through
onnxruntime and the approach's action pipeline of control/actions.py (joint targets through their filter, or the
foot-offsets CPG). It imports numpy, onnxruntime and its sibling only; tests/realtime/test_onboard.py holds its
targets to the JAX tick's.
"""

import json
import math
from pathlib import Path

import numpy as np
import onnxruntime

from mjx_badger.realtime.onboard_estimator import KalmanEstimator, Legs, rotation_matrix

SCHEMA = "mjx_badger.onboard/1"
FILTERS = ("none", "lowpass", "butterworth", "one_euro")
"""The joint-target filters it runs (control/filters.py's)."""
RESIDUALS = (None, "angle-average", "angle-sum")
"""The CPG residual modes it runs: a robot has one PD controller per joint, so not torque-average."""
ANGULAR_ACCELERATION = ("gyro-difference", "zero")
"""How the observation's angular acceleration is measured: thesis-text, and thesis-code's robot env (never set)."""
BLOCKS = ("joint_angle", "joint_velocity", "predicted", "trunk_linear_acceleration", "trunk_angular_acceleration",
          "trunk_linear_velocity", "trunk_angular_velocity", "target_velocity", "projected_gravity", "cpg_progress")
"""sim/observation.observation_layout's blocks in order (predicted_joint_angle or predicted_feet_position)."""


def settings_path(onnx_path: Path) -> Path:
    """The `.onboard.json` beside an exported `.onnx`."""
    return Path(onnx_path).with_suffix(".onboard.json")


def smoothing_factor(cutoff_hz: float, dt: float) -> float:
    """filters.smoothing_factor: alpha = 1 / (1 + tau / dt), tau = 1 / (2 pi f_c)."""
    return 1.0 / (1.0 + 1.0 / (2.0 * math.pi * cutoff_hz * dt))


class Filter:
    """A joint-target filter of control/filters.py, stateful: `reset(x0)` at rest at x0, then `filter(x) -> y`."""

    def __init__(self, name: str, dt: float, params: dict):
        if name not in FILTERS:
            raise ValueError(f"unknown filter {name!r}; the onboard runner has {', '.join(FILTERS)}")
        self.name, self.dt, self.params = name, dt, dict(params)
        if name == "butterworth":  # filters.butterworth_coefficients
            k = math.tan(math.pi * self.params["cutoff_hz"] / (self.params.get("design_hz") or 1.0 / dt))
            norm = 1.0 / (1.0 + math.sqrt(2.0) * k + k * k)
            b0 = k * k * norm
            self.b, self.a = (b0, 2 * b0, b0), (2.0 * (k * k - 1.0) * norm, (1.0 - math.sqrt(2.0) * k + k * k) * norm)

    def reset(self, x0) -> None:
        x0 = np.array(x0, np.float64)
        self.x, self.y, self.dx, self.started = x0, x0, np.zeros_like(x0), False
        if self.name == "butterworth":  # the transposed direct form's steady state at x0 (DC gain 1)
            (_, b1, b2), (a1, a2) = self.b, self.a
            self.z = np.stack([(b1 + b2 - a1 - a2) * x0, (b2 - a2) * x0])

    def __call__(self, x) -> np.ndarray:
        x, p = np.asarray(x, np.float64), self.params
        if self.name == "lowpass":
            alpha = smoothing_factor(p["cutoff_hz"], self.dt)
            self.y = alpha * x + (1 - alpha) * self.y
        elif self.name == "butterworth":
            (b0, b1, b2), (a1, a2) = self.b, self.a
            self.y = b0 * x + self.z[0]
            self.z = np.stack([b1 * x - a1 * self.y + self.z[1], b2 * x - a2 * self.y])
        elif self.name == "one_euro":
            alpha_d = smoothing_factor(p["d_cutoff"], self.dt)
            dx = alpha_d * (x - self.x) / self.dt + (1 - alpha_d) * self.dx
            alpha = smoothing_factor(p["min_cutoff"] + p["beta"] * np.abs(dx), self.dt)
            y = alpha * x + (1 - alpha) * self.y
            if p.get("start_at_first_input") and not self.started:  # the OneEuroFilter package's first output
                y, dx = x, np.zeros_like(dx)
            self.x, self.y, self.dx, self.started = x, y, dx, True
        else:
            self.y = x
        return self.y


class JointTargets:
    """JT (actions.joint_targets): the nominal pose plus the action scaled to its range, then filtered."""

    def __init__(self, settings: dict, nominal: np.ndarray):
        self.nominal, self.scale = nominal, np.asarray(settings["action"]["scale"], np.float64)
        f = settings["filter"]
        self.filter = Filter(f["name"], settings["control_dt"], f["params"])

    def reset(self) -> None:
        self.filter.reset(self.nominal)
        self.target = self.nominal.copy()

    def step(self, action) -> np.ndarray:
        self.target = self.filter(self.nominal + self.scale * np.clip(action, -1.0, 1.0))
        return self.target

    def observe(self):
        """The predicted block (the applied target - nominal pose) and no extra block."""
        return self.target - self.nominal, np.zeros(0)


class CentralPattern:
    """The foot-offsets CPG (actions.central_pattern, thesis-text): trot heights plus offsets, through the IK."""

    def __init__(self, settings: dict, nominal: np.ndarray, legs: Legs):
        self.c, self.nominal, self.legs, self.dt = settings["cpg"], nominal, legs, settings["control_dt"]
        if self.c["residual"] not in RESIDUALS:
            raise ValueError(f"CPG residual {self.c['residual']!r}; the onboard runner has {RESIDUALS}")
        self.nominal_feet = np.asarray(self.c["nominal_feet"], np.float64)

    def reset(self) -> None:
        self.phase, self.feet = np.float32(0.0), self.nominal_feet.copy()

    def heights(self, phase: float) -> np.ndarray:
        """cpg.foot_heights: each leg's swing height at the CPG phase, two smoothsteps (lift, lower), 0 in stance."""
        own = np.mod(phase + np.asarray(self.c["leg_phase_offsets"]), 1.0)
        t = own / self.c["swing_fraction"]
        smooth = lambda s: -2.0 * s**3 + 3.0 * s**2
        apex = self.c["apex_height"]
        swing = np.where(t < 0.5, apex * smooth(np.clip(2 * t, 0, 1)), apex * (1 - smooth(np.clip(2 * t - 1, 0, 1))))
        return np.where(own < self.c["swing_fraction"], swing, 0.0)

    def step(self, action) -> np.ndarray:
        action = np.clip(np.asarray(action, np.float64), -1.0, 1.0)
        low, high = self.c["frequency_range_hz"]
        frequency = low + (high - low) * 0.5 * (action[12] + 1.0) if self.c["variable_frequency"] else self.c[
            "frequency_hz"]
        # In float32, as the trained pipeline kept it: a float64 phase drifts from it by 1e-5 in 200 steps.
        advanced = np.mod(self.phase + np.float32(frequency * self.dt), np.float32(1.0))
        lift = self.heights(self.phase if self.c["heights_before_advance"] else advanced)
        self.phase = advanced
        self.feet = self.nominal_feet + (action[:12] * self.c["foot_offset_scale"]).reshape(-1, 3)
        self.feet[:, 2] += lift
        angles = self.legs.inverse(self.feet).reshape(-1)
        residual = action[-12:] * np.asarray(self.c["residual_scale"])
        if self.c["residual"] == "angle-average":
            return 0.5 * (angles + self.nominal + residual)
        if self.c["residual"] == "angle-sum":
            return np.clip(angles + residual, self.legs.lower.reshape(-1), self.legs.upper.reshape(-1))
        return angles

    def observe(self):
        """The predicted block (commanded feet - nominal feet) and the phase on a circle (cpg.progress)."""
        angle = 2.0 * math.pi * self.phase
        return (self.feet - self.nominal_feet).reshape(-1), np.array([0.5 * (1 + math.sin(angle)),
                                                                     0.5 * (1 + math.cos(angle))])


class OnboardPolicy:
    """An exported policy on the robot: `reset()` at a stand, then `step(...)` once per control period."""

    def __init__(self, onnx_path: Path, threads: int = 1):
        path = settings_path(onnx_path)
        try:
            self.settings = s = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as error:
            raise ValueError(f"{path}: cannot read the policy's onboard settings ({error})") from None
        if not isinstance(s, dict) or s.get("schema") != SCHEMA:
            raise ValueError(f"{path}: not a {SCHEMA} file")
        obs = s["observation"]
        names = [name.replace("predicted_joint_angle", "predicted").replace("predicted_feet_position", "predicted")
                 for name, _, _ in obs["layout"]]
        if names != list(BLOCKS[:len(names)]) or obs["angular_acceleration"] not in ANGULAR_ACCELERATION:
            raise ValueError(f"{path}: an observation this runner does not build ({names}, "
                             f"{obs['angular_acceleration']!r})")
        self.scale = np.concatenate([np.full(size, scale) for _, size, scale in obs["layout"]])
        self.nominal = np.asarray(s["nominal_pose"], np.float64)
        self.legs = Legs(s["kinematics"])
        self.estimator = KalmanEstimator(self.legs, s["estimator"]["acceleration_std"], s["estimator"]["odometry_std"])
        self.pipeline = (CentralPattern(s, self.nominal, self.legs) if s["kind"] == "cpg"
                         else JointTargets(s, self.nominal))
        self.control_hz, self.control_dt, self.kp, self.kd = s["control_hz"], s["control_dt"], *s["pd_gains"]
        options = onnxruntime.SessionOptions()
        # One thread: the network is small, and idle worker threads spinning would compete with the control loop.
        options.intra_op_num_threads = options.inter_op_num_threads = threads
        self.session = onnxruntime.InferenceSession(str(onnx_path), options, providers=["CPUExecutionProvider"])
        self.input = self.session.get_inputs()[0].name
        self.reset()

    def reset(self) -> None:
        """A fresh stand: the estimator sure the robot is still, the action pipeline at the nominal pose."""
        self.estimator.reset()
        self.pipeline.reset()
        self.prev_gyro = None
        self.observation = self.action = self.velocity = None

    def act(self, observation) -> np.ndarray:
        """The deterministic action in [-1, 1] of one observation, through onnxruntime."""
        batch = np.asarray(observation, np.float32).reshape(1, -1)
        return self.session.run(None, {self.input: batch})[0][0]

    def step(self, joint_angle, joint_velocity, joint_torque, acceleration, angular_velocity, orientation_wxyz,
             command_xyz, dt: float | None = None):
        """(joint targets (12,), kp, kd) for one sensor reading (interface.Sensors' fields) and command [vx, vy, yaw];
        `dt` (s) since the last reading is the estimator's (default the control period); the observation's gyro
        difference is taken over the control period, as in training. `joint_torque` is read by no part of it today
        (the all-feet estimator), kept so the call has every reading."""
        del joint_torque
        q, qd = np.asarray(joint_angle, np.float64), np.asarray(joint_velocity, np.float64)
        gyro, accel = np.asarray(angular_velocity, np.float64), np.asarray(acceleration, np.float64)
        rotation = rotation_matrix(orientation_wxyz)
        self.velocity = self.estimator.update(q, qd, accel, gyro, rotation, self.control_dt if dt is None else dt)
        if self.prev_gyro is None:  # the loop's first reading stands in for the one before it
            self.prev_gyro = gyro
        if self.settings["observation"]["angular_acceleration"] == "gyro-difference":
            angular_acceleration = (gyro - self.prev_gyro) / self.control_dt
        else:
            angular_acceleration = np.zeros(3)
        predicted, extra = self.pipeline.observe()
        self.observation = (np.concatenate([q - self.nominal, qd, predicted, accel, angular_acceleration, self.velocity,
                                            gyro, np.asarray(command_xyz, np.float64), rotation.T @ [0.0, 0.0, -1.0],
                                            extra]) * self.scale).astype(np.float32)
        self.action = self.act(self.observation)
        self.prev_gyro = gyro
        return np.array(self.pipeline.step(self.action)), self.kp, self.kd  # a copy: the pipeline keeps its own

    def trip(self, joint_angle, orientation_wxyz) -> str | None:
        """Why the robot must stop now (robot/safety.trips' rule, realtime/safety.check's words), or None."""
        rotation, safety = rotation_matrix(orientation_wxyz), self.settings["safety"]
        roll, pitch = math.atan2(rotation[2, 1], rotation[2, 2]), math.asin(min(max(-rotation[2, 0], -1.0), 1.0))
        for name, angle in (("roll", roll), ("pitch", pitch)):
            if abs(angle) > safety["fall_tilt_rad"]:
                return f"{name} {angle:+.2f} rad"
        angle, margin = np.asarray(joint_angle), safety["joint_margin_rad"]
        outside = (angle < self.legs.lower.reshape(-1) - margin) | (angle > self.legs.upper.reshape(-1) + margin)
        if outside.any():
            joint = int(np.argmax(outside))
            return f"{safety['joint_names'][joint]} at {angle[joint]:+.2f} rad, outside its range"
        return None
