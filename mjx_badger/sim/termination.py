"""When an HB40 episode ends: the protocols' fall rules, the robot's own safety stop, and its time limit.

The terminating half of HB40Env: a fall is judged on a finite state only (a physics blow-up ends the
episode too, but is counted in `blowups`, not as a fall); under on-robot conditions the robot's own
stop replaces the protocol's rule.
"""

import jax.numpy as jnp
import numpy as np

from mjx_badger.robot import safety, terrain
from mjx_badger.sim.observation import roll_pitch

# thesis-text termination (our reading): the robot's own fall rule (RobotSpec.fall_tilt_rad, fall_height).
# thesis-code termination (docs/thesis-code.md §6).
CODE_FALL_TILT_RAD = np.deg2rad(30.0)
CODE_FALL_ANGULAR_SPEED = 4.0
CODE_POWER_LIMIT_W = 1500.0
CODE_POWER_STEPS = 3
# The released robot env's monitor damps the motors at this roll or pitch (docs/thesis-code.md §12).
ROBOT_COLLAPSE_RAD = 1.5


class Terminating:
    """HB40Env's termination: the protocol's fall rule or the robot's safety stop, and the episode's time limit."""

    def _power_steps(self, info: dict, data, torque):
        """Consecutive steps the motors' power has been past the released code's limit (its fall rule counts them)."""
        return jnp.where(jnp.sum(jnp.abs(torque * data.qvel[6:])) > CODE_POWER_LIMIT_W, info["power_steps"] + 1, 0)

    def _terminate(self, info: dict, data, motion, senses: dict, power_steps, finite):
        """(fallen, terminated, truncated): the fall rule on a finite state (a blow-up is counted in `blowups`, not
        as a (would-be) fall), whether the episode ends on it or a blow-up, and whether its time is up."""
        if self.conditions.safety_stop:  # the robot's own stop on its own readings, in place of the protocol's rule
            sensed = senses["reading"] if senses and self.conditions.stop_on_sensed else None
            fallen = self._safety_stop(sensed, data) & finite
            terminated = fallen | ~finite
        else:
            fallen = self._fall_rule(data, motion, power_steps) & finite
            terminated = (fallen if self.terminates else jnp.bool_(False)) | ~finite
        truncated = (info["step"] + 1 >= self.episode_steps) & ~terminated
        return fallen, terminated, truncated

    def stop_counts(self, info=None, data=None, fallen=None) -> dict:
        """The running counts of `stop_kinds` in an episode's info under the robot's own stop (none without it): zeros
        with no arguments (a reset), else `info`'s counts with this step's stop `fallen` added."""
        if not self.conditions.safety_stop:
            return {}
        if info is None:
            return {"stops_before_fall": jnp.int32(0), "premature_stops": jnp.int32(0)}
        before, premature = self.stop_kinds(data, fallen)
        return {"stops_before_fall": info["stops_before_fall"] + before.astype(jnp.int32),
                "premature_stops": info["premature_stops"] + premature.astype(jnp.int32)}

    def stop_kinds(self, data, fallen):
        """(before a fall, premature) of a safety stop `fallen`: the truth shows no fall yet (no tilt past the fall tilt,
        the trunk above the fall height: the tilt-height rule), and the same rule on the truth would not have stopped."""
        down = self._tilted_or_low(data, *roll_pitch(data.xmat[self._trunk]))
        return fallen & ~down, fallen & ~self._safety_stop(None, data)

    def _tilted_or_low(self, data, roll, pitch):
        """The tilt-height rule: roll or pitch past the robot's fall tilt, or the trunk below its fall height."""
        floor = terrain.height_at(self.ground, data.qpos[0]) if self.ground.incline_deg else 0.0
        tilt = self.spec.fall_tilt_rad
        return (jnp.abs(roll) > tilt) | (jnp.abs(pitch) > tilt) | (data.qpos[2] - floor < self.spec.fall_height)

    def _safety_stop(self, reading, data):
        """Whether the robot stops itself: under thesis-code the released robot env's rule (its heading pitched 30 deg
        or more, or turning faster than 4 rad/s, or the monitor's collapse at 1.5 rad of roll or pitch), under
        thesis-text the on-robot loop's monitor (a tilt past the fall tilt or a joint out of range, §5.2)."""
        rotation = reading.rotation if reading is not None else data.xmat[self._trunk]
        angle = reading.joint_angle if reading is not None else data.qpos[7:]
        if self.protocol.termination != "thesis-code":
            return safety.trips(rotation, angle, self.spec, jnp)
        gyro = reading.angular_velocity if reading is not None else data.sensordata[self._gyro]
        roll, pitch = roll_pitch(rotation)
        heading_pitch = jnp.arcsin(jnp.clip(rotation[2, 0], -1.0, 1.0))
        return ((jnp.abs(heading_pitch) >= CODE_FALL_TILT_RAD) | (jnp.linalg.norm(gyro) > CODE_FALL_ANGULAR_SPEED)
                | (jnp.abs(roll) >= ROBOT_COLLAPSE_RAD) | (jnp.abs(pitch) >= ROBOT_COLLAPSE_RAD))

    def _fall_rule(self, data, motion, power_steps):
        """Whether the protocol's termination rule fires on this step."""
        if self.protocol.termination == "tilt-height":
            return self._tilted_or_low(data, motion.roll, motion.pitch)
        rot = data.xmat[self._trunk]
        floor = terrain.height_at(self.ground, data.qpos[0]) if self.ground.incline_deg else 0.0
        # The trunk box's lowest corner at the floor: the trunk-floor contact (a box on a plane).
        trunk_bottom = data.xpos[self._trunk, 2] - floor - jnp.sum(jnp.abs(rot[2]) * self._trunk_half)
        return ((jnp.abs(motion.roll) >= CODE_FALL_TILT_RAD) | (jnp.abs(motion.pitch) >= CODE_FALL_TILT_RAD)
                | (jnp.linalg.norm(data.qvel[3:6]) > CODE_FALL_ANGULAR_SPEED) | (trunk_bottom <= 0.0)
                | (power_steps >= CODE_POWER_STEPS))
