"""A simulated HB40 behind the `Robot` protocol: native MuJoCo at 200 Hz, paced to wall-clock.

The physics runs in its own thread, like the robot's own controller, and exposes only what
the real robot's sensors give, with the noise of the suite's one sensor model (sensors.py,
read every physics step); its `truth()` (the protocol's optional part) is for logging and
figures, and the loop never learns from it.
"""

import threading
import time

import mujoco
import numpy as np

from mjx_badger.estimation import sensors
from mjx_badger.protocol.conditions import SIM, Conditions
from mjx_badger.realtime import scheduling
from mjx_badger.realtime.interface import Robot, Sensors
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf, motors


class SimulatedHB40(Robot):
    """The HB40 (or another robot spec) in native MuJoCo with its physics thread; implements `interface.Robot`."""

    def __init__(self, noise: sensors.SensorModel | None = sensors.SensorModel(), reset_seconds: float = 2.0, seed: int = 0,
                 spec: robot.RobotSpec = robot.HB40, conditions: Conditions = SIM):
        self.spec = spec
        self.conditions = conditions
        # On the conditions' ground (a flat floor, or the cobblestones on their slope), its friction drawn per reset.
        self.model = mjcf.load_model(spec, ground=conditions.ground if conditions is not SIM else None)
        self.data = mujoco.MjData(self.model)
        self.noise = sensors.EXACT if noise is None else noise
        self.reset_seconds = reset_seconds
        self.physics_dt = float(self.model.opt.timestep)
        self.late_physics_steps = 0
        self.damp_calls = 0
        self._rng = np.random.default_rng(seed)
        self._sensor_state = sensors.init(self.noise)
        self._lock = threading.Lock()
        self._running = threading.Event()
        self._thread: threading.Thread | None = None
        self._gains = self.spec.pd_gains
        self._applied_gains = None
        self._targets = np.asarray(robot.nominal_pose(self.spec), dtype=np.float64)
        self._trunk = self.model.body("trunk").id
        self._accel = mjcf.sensor_slice(self.model, "accelerometer")
        self._gyro = mjcf.sensor_slice(self.model, "gyro")
        self._sensors: Sensors | None = None
        self._stand()

    # The Robot protocol.
    def start(self) -> None:
        if self._thread is not None:
            return
        self._sensor_state = sensors.init(self.noise, rng=self._rng)
        self._running.set()
        self._thread = threading.Thread(target=self._physics_loop, name="hb40-physics", daemon=True)
        self._thread.start()

    def read(self) -> Sensors:
        with self._lock:
            return self._sensors

    def command(self, targets, kp: float, kd: float) -> None:
        with self._lock:
            self._targets = np.asarray(targets, dtype=np.float64).copy()
            self._gains = (float(kp), float(kd))

    def hold(self) -> None:
        self.command(robot.nominal_pose(self.spec), *self.spec.pd_gains)

    def damp(self) -> None:
        with self._lock:
            self._gains = self.spec.damping_gains
            self.damp_calls += 1

    def reset(self) -> None:
        time.sleep(self.reset_seconds)  # the operator walks over and stands the robot up
        with self._lock:
            self._stand()

    def stop(self) -> None:
        self.damp()
        self._running.clear()
        if self._thread is not None:
            self._thread.join()
            self._thread = None

    def truth(self) -> dict:
        """Trunk-frame linear velocity (3,), world position (3,) and height of the simulated trunk."""
        with self._lock:
            rot = self.data.xmat[self._trunk].reshape(3, 3)
            return {"linear_velocity": rot.T @ self.data.qvel[:3], "position": self.data.qpos[:3].copy(),
                    "height": float(self.data.qpos[2])}

    # Simulation only: a hand on the robot for tests.
    @property
    def gains(self) -> tuple[float, float]:
        with self._lock:
            return self._gains

    def tip(self, roll: float) -> None:
        """Roll the trunk to `roll` (rad) in place, as a push would."""
        with self._lock:
            self.data.qpos[3:7] = [np.cos(roll / 2), np.sin(roll / 2), 0.0, 0.0]
            mujoco.mj_forward(self.model, self.data)
            self._sensors = self._measure()

    def _stand(self):
        ground = self.conditions.ground
        if ground.friction != (self.spec.friction,) * 2:  # a new spot of the floor at every reset
            self.model.pair_friction[:, :2] = self._rng.uniform(*ground.friction)
        mujoco.mj_resetData(self.model, self.data)
        if self.conditions.push_newtons:  # the wind, from a new direction each time the robot stands again
            heading = self._rng.uniform(0.0, 2 * np.pi)
            self.data.xfrc_applied[self._trunk, :3] = self.conditions.push_newtons * np.array(
                [np.cos(heading), np.sin(heading), 0.0])
        self.data.qpos[:] = robot.standing_qpos(self.model, self.spec)
        self._targets = np.asarray(robot.nominal_pose(self.spec), dtype=np.float64)
        self._gains = self.spec.pd_gains
        self.data.ctrl[:] = self._targets
        mujoco.mj_forward(self.model, self.data)
        self._sensors = self._measure()

    def _physics_loop(self):
        # The robot's own controller runs on its own hardware; here it must not wait behind the
        # learner either (a no-op where real-time scheduling is not allowed).
        scheduling.raise_to_realtime(scheduling.CONTROL_PRIORITY + 1)
        next_tick = time.perf_counter()
        while self._running.is_set():
            with self._lock:
                if self._gains != self._applied_gains:
                    motors.set_pd_gains(self.model, *self._gains)
                    self._applied_gains = self._gains
                self.data.ctrl[:] = self._targets
                mujoco.mj_step(self.model, self.data)
                self._sensors = self._measure()
            next_tick += self.physics_dt
            delay = next_tick - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            elif delay < -self.physics_dt:
                # More than a step behind: count it and pick up from now rather than race to catch up.
                self.late_physics_steps += 1
                next_tick = time.perf_counter()

    def _measure(self) -> Sensors:
        d = self.data
        truth = sensors.Truth(d.qpos[7:].copy(), d.qvel[6:].copy(), d.actuator_force[:12].copy(),
                              d.sensordata[self._accel].copy(), d.sensordata[self._gyro].copy(),
                              d.xmat[self._trunk].reshape(3, 3).copy(), np.ones(4))
        self._sensor_state, reading = sensors.read(self.noise, self._sensor_state, truth,
                                                   sensors.draw_numpy(self._rng), self.physics_dt, xp=np)
        quaternion = np.zeros(4)
        mujoco.mju_mat2Quat(quaternion, np.ascontiguousarray(reading.rotation).reshape(-1))
        return Sensors(time=float(d.time), joint_angle=reading.joint_angle, joint_velocity=reading.joint_velocity,
                       joint_torque=reading.joint_torque, acceleration=reading.acceleration,
                       angular_velocity=reading.angular_velocity, orientation=quaternion)
