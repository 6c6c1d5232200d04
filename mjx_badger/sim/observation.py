"""What the HB40 env observes: the observation's blocks and scales, and the observing half of HB40Env.

Observation (thesis Table 4.1, trunk frame): 54 values for the joint-target approaches,
56 for the CPG approaches:
    [0:12]  joint angle - nominal pose (rad)           order FL, FR, RL, RR x hip, thigh, knee
    [12:24] joint velocity (rad/s)
    [24:36] JT: the applied target - nominal pose (rad, the filtered action)
            CPG, thesis-text: commanded foot positions - nominal ones (m); thesis-code: the scaled action
    [36:39] trunk linear acceleration: thesis-text the IMU accelerometer (with gravity);
            thesis-code the free joint's acceleration (without gravity), both in the trunk frame
    [39:42] trunk angular acceleration: thesis-text the gyro difference over a control period;
            thesis-code the free joint's angular acceleration
    [42:45] trunk linear velocity (m/s)
    [45:48] trunk angular velocity (rad/s)
    [48:51] target velocities [vx, vy, yaw rate]
    [51:54] projected gravity (unit vector)
    [54:56] CPG only: thesis-text the phase as (1 + sin, 1 + cos) / 2; thesis-code the two swing heights
Each block is multiplied by its protocol's scale; `observation_layout` lists them. Under on-robot
conditions the robot observes through its own sensors and velocity estimate (`Observing._sense`).
"""

import jax
import jax.numpy as jnp

from mjx_badger.control import actions
from mjx_badger.estimation import estimators, sensors
from mjx_badger.protocol import protocols
from mjx_badger.protocol.protocols import Protocol
from mjx_badger.robot import description as robot
from mjx_badger.tasks import locomotion as tasks

# Fixed scale factors that bring each block to order one (thesis-text), and the released
# code's divisors (thesis-code, docs/thesis-code.md §4: q / 3.14, qdot / 25, action / 3.14, omega / 10).
TEXT_SCALES = {"joint_angle": 1.0, "joint_velocity": 0.1, "predicted_joint_angle": 1.0, "predicted_feet_position": 5.0,
               "trunk_linear_acceleration": 0.1, "trunk_angular_acceleration": 0.01, "trunk_angular_velocity": 1.0}
CODE_SCALES = {"joint_angle": 1 / 3.14, "joint_velocity": 1 / 25, "predicted_joint_angle": 1 / 3.14,
               "predicted_feet_position": 1 / 3.14, "trunk_linear_acceleration": 1.0,
               "trunk_angular_acceleration": 1.0, "trunk_angular_velocity": 0.1}


def observation_layout(action_space: actions.ActionSpace, protocol: Protocol = protocols.THESIS_CODE) -> tuple:
    """(name, size, scale) of every observation block for an approach's action space."""
    scales = CODE_SCALES if protocol.observation == "thesis-code" else TEXT_SCALES
    predicted = "predicted_joint_angle" if action_space.predicted_name == "joint_angle" else "predicted_feet_position"
    sizes = (("joint_angle", 12), ("joint_velocity", 12), (predicted, 12), ("trunk_linear_acceleration", 3),
             ("trunk_angular_acceleration", 3), ("trunk_linear_velocity", 3), ("trunk_angular_velocity", 3),
             ("target_velocity", 3), ("projected_gravity", 3))
    if action_space.extra_size:
        sizes += (("cpg_progress", action_space.extra_size),)
    return tuple((name, size, scales.get(name, 1.0)) for name, size in sizes)


def roll_pitch(rot):
    """Roll and pitch (rad) of a body-to-world rotation matrix (3, 3), traced (robot.roll_pitch)."""
    return robot.roll_pitch(rot, jnp)


class Observing:
    """HB40Env's observation: from the simulator's truth, or from the robot's own readings and estimate."""

    def _sense(self, info: dict, data, acceleration, key) -> dict:
        """The sensors' reading of this step and the estimator's velocity from it (trunk frame).

        The accelerometer is read as its mean over the control period (an IMU's low-pass at the read rate);
        the contacts the reading carries are estimated from its motor torques."""
        if acceleration is None:
            acceleration = data.sensordata[self._accel]
        truth = sensors.truth(data, self._trunk, acceleration, data.sensordata[self._gyro], data.qfrc_actuator[6:])
        sensor_state, reading = sensors.read(self.sensing.sensors, info["sensor_state"], truth,
                                             sensors.draw(jax.random.fold_in(key, 1)), self.control_dt)
        reading = reading._replace(contacts=estimators.estimated_contacts(reading.joint_angle, reading.joint_torque,
                                                                          reading.rotation, self.spec))
        estimator_state, estimate = self._estimator.step(info["estimator_state"], reading, self.control_dt)
        return {"sensor_state": sensor_state, "estimator_state": estimator_state, "estimate": estimate,
                "reading": reading}

    def _observe(self, data, action_state, command, prev_gyro, torque, senses=None):
        """Observation vector and the raw trunk motion the reward needs (the truth; with the estimate in the loop
        the observation is what the robot measures: `_observe_measured`)."""
        rot = data.xmat[self._trunk]  # body-to-world
        linear_velocity = rot.T @ data.qvel[:3]
        gyro = data.sensordata[self._gyro]
        gravity = rot.T @ jnp.array([0.0, 0.0, -1.0])
        roll, pitch = roll_pitch(rot)
        if self.protocol.observation == "thesis-code":
            acceleration, angular_velocity = rot.T @ data.qacc[:3], data.qvel[3:6]
            angular_acceleration = data.qacc[3:6]
        else:
            acceleration, angular_velocity = data.sensordata[self._accel], gyro
            angular_acceleration = (gyro - prev_gyro) / self.control_dt
        obs = self._assemble(data.qpos[7:], data.qvel[6:], action_state, acceleration, angular_acceleration,
                             linear_velocity, angular_velocity, command, gravity)
        applied = torque if self.protocol.rewards == "thesis-code" else data.qfrc_actuator[6:]
        motion = tasks.Motion(linear_velocity, angular_velocity, roll, pitch, applied)
        if senses and self.conditions.estimate_in_loop:
            obs = self._observe_measured(senses, action_state, command, prev_gyro)
        return obs, motion

    def _observe_measured(self, senses, action_state, command, prev_gyro):
        """The observation from the robot's own readings and velocity estimate: encoders, the IMU's specific force
        (gravity included, as the robot's IMU gives it), gyro and attitude; the angular acceleration is the gyro's
        change (thesis-text) or zero (thesis-code: the released robot env leaves it unset)."""
        reading = senses["reading"]
        gravity = reading.rotation.T @ jnp.array([0.0, 0.0, -1.0])
        if self.protocol.observation == "thesis-code":  # the released robot env never fills angular acceleration
            angular_acceleration = jnp.zeros(3)
        else:
            angular_acceleration = (reading.angular_velocity - prev_gyro) / self.control_dt
        return self._assemble(reading.joint_angle, reading.joint_velocity, action_state, reading.acceleration,
                              angular_acceleration, senses["estimate"], reading.angular_velocity, command, gravity)

    def observation(self, joint_angle, joint_velocity, action_state, acceleration, angular_velocity,
                    prev_angular_velocity, linear_velocity, command, gravity):
        """The thesis-text observation from measured quantities, as the on-robot loop builds it."""
        angular_acceleration = (angular_velocity - prev_angular_velocity) / self.control_dt
        return self._assemble(joint_angle, joint_velocity, action_state, acceleration, angular_acceleration,
                              linear_velocity, angular_velocity, command, gravity)

    def _assemble(self, joint_angle, joint_velocity, action_state, acceleration, angular_acceleration,
                  linear_velocity, angular_velocity, command, gravity):
        """The scaled observation vector in the order of `observation_layout`, from its quantities."""
        predicted, extra = self.action_space.observe(action_state)
        return jnp.concatenate([joint_angle - self._nominal, joint_velocity, predicted, acceleration,
                                angular_acceleration, linear_velocity, angular_velocity, command, gravity,
                                extra]) * self._obs_scale
