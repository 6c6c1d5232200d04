"""The robot's own velocity estimate without JAX: its leg kinematics and the §2.6.1 Kalman filter in NumPy.

A port of robot/kinematics.py (forward, inverse) and estimation/estimators.kinematic_kalman from the
figures an exported policy's `.onboard.json` carries (`outputs/onnx_export.py` writes them from the robot
spec), so that the robot's computer needs NumPy alone; tests/realtime/test_onboard_estimator.py holds it to
the JAX originals. It imports nothing of the package: the robot runs it beside `onboard.py` without JAX.
"""

import numpy as np

GRAVITY = np.array([0.0, 0.0, -9.81])
"""m/s^2, the world's; estimators.GRAVITY."""


def rotation_matrix(quaternion) -> np.ndarray:
    """Trunk-to-world rotation (3, 3) from a quaternion w, x, y, z (normalised here), as interface.rotation_matrix."""
    w, x, y, z = np.asarray(quaternion, dtype=np.float64) / np.linalg.norm(quaternion)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


class Legs:
    """The leg kinematics of kinematics.py from its figures (kinematics.leg's fields and the hip positions)."""

    def __init__(self, figures: dict):
        f = lambda name: np.asarray(figures[name], np.float64)
        self.phi0, self.kappa0, self.l1, self.l2 = (float(figures[k]) for k in ("phi0", "kappa0", "l1", "l2"))
        self.thigh_x, self.lateral = float(figures["thigh_x"]), float(figures["lateral"])
        self.front, self.left = f("front"), f("left")
        self.lower, self.upper = f("lower"), f("upper")
        self.hips = f("hip_positions")

    def forward(self, angles, velocities=None):
        """Foot positions (legs, 3) in the hip frames and, given joint velocities, their velocities (legs, 3)."""
        q = np.reshape(np.asarray(angles, np.float64), (-1, 3))
        dq = np.zeros_like(q) if velocities is None else np.reshape(np.asarray(velocities, np.float64), (-1, 3))
        alpha = self.phi0 + self.left * q[:, 1]
        gamma = alpha + self.kappa0 + self.left * q[:, 2]
        d_alpha = self.left * dq[:, 1]
        d_gamma = d_alpha + self.left * dq[:, 2]
        x = self.front * self.thigh_x - self.l1 * np.sin(alpha) + self.l2 * np.sin(gamma)
        z = -self.l1 * np.cos(alpha) + self.l2 * np.cos(gamma)
        dx = -self.l1 * np.cos(alpha) * d_alpha + self.l2 * np.cos(gamma) * d_gamma
        dz = self.l1 * np.sin(alpha) * d_alpha - self.l2 * np.sin(gamma) * d_gamma
        y = self.left * self.lateral
        hip, d_hip = self.front * q[:, 0], self.front * dq[:, 0]  # the rear hips turn about -x
        c, s = np.cos(hip), np.sin(hip)
        feet = np.stack([x, c * y - s * z, s * y + c * z], axis=-1)
        feet_velocity = np.stack([dx, -s * d_hip * y - c * d_hip * z - s * dz, c * d_hip * y - s * d_hip * z + c * dz],
                                 axis=-1)
        return feet, feet_velocity

    def inverse(self, feet) -> np.ndarray:
        """Joint angles (legs, 3) reaching foot positions (legs, 3), knee bent backward, clipped to the joint ranges."""
        p = np.reshape(np.asarray(feet, np.float64), (-1, 3))
        px, py, pz = p[:, 0], p[:, 1], p[:, 2]
        side = self.left * self.lateral
        height = np.sqrt(np.maximum(py**2 + pz**2 - side**2, 1e-8))
        psi = np.arctan2(pz, py) - np.arctan2(-height, side)
        psi = np.arctan2(np.sin(psi), np.cos(psi))
        xs = px - self.front * self.thigh_x
        reach = np.sqrt(xs**2 + height**2)
        l1, l2 = self.l1, self.l2
        interior = np.arccos(np.clip((l1**2 + l2**2 - reach**2) / (2 * l1 * l2), -1.0, 1.0))
        at_thigh = np.arccos(np.clip((l1**2 + reach**2 - l2**2) / (2 * l1 * np.maximum(reach, 1e-6)), -1.0, 1.0))
        a = np.arctan2(-xs, height) + at_thigh - self.phi0
        b = interior - self.kappa0
        return np.clip(np.stack([self.front * psi, self.left * a, self.left * b], axis=-1), self.lower, self.upper)

    def odometry(self, joint_angle, joint_velocity, angular_velocity) -> np.ndarray:
        """(legs, 3) trunk-frame trunk velocity each foot implies if it stands still: -(dp/dt + omega x p)."""
        feet, feet_velocity = self.forward(joint_angle, joint_velocity)
        return -(feet_velocity + np.cross(np.asarray(angular_velocity, np.float64), self.hips + feet))


class KalmanEstimator:
    """kinematic-kalman (§2.6.1): IMU prediction in the world frame, leg-odometry correction over the feet."""

    def __init__(self, legs: Legs, acceleration_std: float = 0.5, odometry_std: float = 0.1):
        self.legs = legs
        self.acceleration_std, self.odometry_std = float(acceleration_std), float(odometry_std)
        self.reset()

    def reset(self) -> None:
        """Standing still, and sure of it (a reset recalibrates)."""
        self.velocity = np.zeros(3)
        self.covariance = np.eye(3) * 1e-4

    def update(self, joint_angle, joint_velocity, acceleration, angular_velocity, rotation, dt: float,
               contacts=None) -> np.ndarray:
        """Predict over `dt` from the specific force `acceleration`, correct with the feet weighted by `contacts`
        (all four if None); the trunk-frame velocity (3,)."""
        rotation = np.asarray(rotation, np.float64)
        velocity = self.velocity + (rotation @ np.asarray(acceleration, np.float64) + GRAVITY) * dt
        covariance = self.covariance + np.eye(3) * (self.acceleration_std * dt) ** 2
        weights = np.ones(len(self.legs.front)) if contacts is None else np.asarray(contacts, np.float64)
        total = float(np.sum(weights))
        if total > 0:  # no foot on the ground: nothing to correct with
            odometry = self.legs.odometry(joint_angle, joint_velocity, angular_velocity)
            measured = rotation @ (weights @ odometry / max(total, 1e-6))
            noise = np.eye(3) * self.odometry_std**2 / max(total, 1e-6)
            gain = covariance @ np.linalg.inv(covariance + noise)
            velocity = velocity + gain @ (measured - velocity)
            covariance = (np.eye(3) - gain) @ covariance
        self.velocity, self.covariance = velocity, covariance
        return rotation.T @ velocity
