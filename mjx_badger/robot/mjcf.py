"""The MuJoCo model of a robot spec: its MJCF document on a ground, the loaded model, and where its sensors read.

The text is generated from `description.RobotSpec` alone (edit the spec, not the text); the PD gains the
model is built with are set per approach and protocol afterwards (motors.py).
"""

import math

import mujoco
import numpy as np

from mjx_badger.robot import terrain
from mjx_badger.robot.description import HB40, RobotSpec, joint_limits
from mjx_badger.robot.terrain import Ground


def _rot_y(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def knee_offset(spec: RobotSpec, left: float) -> np.ndarray:
    """Knee position (3,) in the thigh frame at thigh angle 0."""
    phi = math.radians(spec.thigh_zero_behind_vertical_deg)
    return np.array([-spec.thigh_length * math.sin(phi), left * spec.knee_outboard, -spec.thigh_length * math.cos(phi)])


def foot_offset(spec: RobotSpec, left: float) -> np.ndarray:
    """Foot-sphere centre (3,) in the calf frame at knee angle 0: back along the thigh, turned down by the zero fold."""
    phi = math.radians(spec.thigh_zero_behind_vertical_deg)
    back = np.array([math.sin(phi), 0.0, math.cos(phi)])
    along = _rot_y(math.radians(spec.knee_zero_interior_deg)) @ back
    return spec.calf_length * along + np.array([0.0, left * spec.foot_outboard, 0.0])


def _vec(v) -> str:
    return " ".join(f"{float(x):.6g}" for x in v)


def _link_quat(direction) -> str:
    """Quaternion turning z onto `direction`, for a link's inertial frame."""
    z = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    quat = np.zeros(4)
    mujoco.mju_quatZ2Vec(quat, z)
    return _vec(quat)


def _leg(spec: RobotSpec, index: int) -> str:
    leg, front, left = spec.legs[index], spec.front_sign[index], spec.left_sign[index]
    knee = knee_offset(spec, left)
    foot = foot_offset(spec, left)
    lower, upper = joint_limits(spec)
    motor = spec.thigh_motor_half_length
    return f"""
      <body name="{leg}_hip" pos="{_vec([front * spec.hip_x, left * spec.hip_y, 0])}">
        <joint name="{leg}_hip" axis="{front:g} 0 0" range="{lower[index, 0]:g} {upper[index, 0]:g}"/>
        <inertial pos="{_vec([front * 0.03, left * 0.006, 0])}" mass="{spec.hip_mass}" diaginertia="{_vec(spec.hip_inertia)}"/>
        <geom name="{leg}_hip" class="visual" type="cylinder" size="0.04 0.03" pos="{_vec([front * 0.03, left * 0.006, 0])}" euler="0 1.5708 0"/>
        <body name="{leg}_thigh" pos="{_vec([front * spec.thigh_offset_x, left * spec.thigh_offset_y, 0])}">
          <joint name="{leg}_thigh" axis="0 {left:g} 0" range="{lower[index, 1]:g} {upper[index, 1]:g}"/>
          <inertial pos="{_vec(knee / 2)}" quat="{_link_quat(knee)}" mass="{spec.thigh_mass}" diaginertia="{_vec(spec.thigh_inertia)}"/>
          <geom name="{leg}_thigh" class="collision" type="cylinder" size="{spec.thigh_motor_radius} {motor}" euler="1.5708 0 0"/>
          <geom name="{leg}_thigh_link" class="visual" type="capsule" fromto="0 0 0 {_vec(knee)}" size="0.018"/>
          <body name="{leg}_calf" pos="{_vec(knee)}">
            <joint name="{leg}_knee" axis="0 {left:g} 0" range="{lower[index, 2]:g} {upper[index, 2]:g}"/>
            <inertial pos="{_vec(foot / 2)}" quat="{_link_quat(foot)}" mass="{spec.calf_mass}" diaginertia="{_vec(spec.calf_inertia)}"/>
            <geom name="{leg}_calf" class="collision" type="capsule" fromto="0 0 0 {_vec(foot)}" size="{spec.calf_radius}"/>
            <geom name="{leg}_foot" class="collision" type="sphere" pos="{_vec(foot)}" size="{spec.foot_radius}"/>
          </body>
        </body>
      </body>"""


def collision_geoms(spec: RobotSpec = HB40) -> tuple:
    """Geoms that touch the floor: of `spec.floor_contacts`, the trunk and per leg the thigh motor, calf and foot."""
    trunk = ("trunk",) if "trunk" in spec.floor_contacts else ()
    return trunk + tuple(f"{leg}_{part}" for leg in spec.legs for part in ("thigh", "calf", "foot")
                         if part in spec.floor_contacts)


def mjcf(spec: RobotSpec = HB40, split_pd: bool = False, ground=None) -> str:
    """The MJCF document of the robot on its ground (terrain.Ground; None: a flat, level floor).

    With `split_pd` every joint gets a second position actuator (ctrl 12-23); both then run at
    half the gains and half the torque limit, so their summed torque is the average of two full
    PD controllers, each clipped: the torque-averaging residual CPG of thesis §4.3.
    """
    ground = Ground() if ground is None else ground
    pd_share = 0.5 if split_pd else 1.0
    limit = spec.torque_limit * pd_share
    actuators = [f'<position name="{name}" joint="{name}"/>' for name in spec.joint_names]
    if split_pd:
        actuators += [f'<position name="{name}_residual" joint="{name}"/>' for name in spec.joint_names]
    touching = collision_geoms(spec)
    if ground.terrain != "flat":
        touching = tuple(g for g in touching if g.split("_")[-1] in ground.contacts)
    pairs = [f'<pair geom1="floor" geom2="{geom}"/>' for geom in touching]
    asset, floor = terrain.floor_xml(ground)
    legs = "".join(_leg(spec, i) for i in range(len(spec.legs)))
    solref = _vec(spec.contact_solref)
    solimp = f"{spec.contact_solimp} {spec.contact_solimp} 0.001 0.5 2"
    return f"""<!-- {spec.name}: generated by mjx_badger.robot.mjcf from RobotSpec; edit the spec, not this text. -->
<mujoco model="{spec.name}">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{spec.physics_dt}" cone="pyramidal" impratio="{ground.impratio_with(spec.impratio):g}"
          iterations="{spec.solver_iterations}" ls_iterations="{spec.solver_ls_iterations}">
    <flag eulerdamp="disable"/>
  </option>
  <default>
    <geom contype="0" conaffinity="0" friction="{spec.friction} 0.005 0.0001"/>
    <joint type="hinge" damping="{spec.joint_damping}" armature="{spec.joint_armature}" frictionloss="{spec.joint_frictionloss}"/>
    <!-- PD at the physics rate: force = kp (target - q) - kv qdot, clipped to the motor limit;
         the gains are set per approach and protocol at run time (motors.set_pd_gains). -->
    <position kp="{60 * pd_share:g}" kv="{3 * pd_share:g}" forcerange="{-limit:g} {limit:g}"/>
    <pair condim="3" friction="{spec.friction} {spec.friction} 0.005 0.0001 0.0001" solref="{solref}" solimp="{solimp}"/>
    <default class="visual"><geom mass="0" rgba="0.3 0.3 0.3 1"/></default>
    <default class="collision"><geom mass="0" rgba="0.5 0.5 0.5 1"/></default>
  </default>{asset and chr(10) + '  ' + asset}
  <worldbody>
    {floor}
    <light pos="0 0 3" dir="0 0 -1" directional="true"/>
    <body name="trunk" pos="0 0 {spec.home_height}">
      <freejoint name="root"/>
      <inertial pos="0 0 0" mass="{spec.trunk_mass}" diaginertia="{_vec(spec.trunk_inertia)}"/>
      <geom name="trunk" class="collision" type="box" size="{_vec(spec.trunk_half_size)}" rgba="0.2 0.2 0.2 1"/>
      <site name="imu" pos="0 0 0"/>{legs}
    </body>
  </worldbody>
  <!-- Only floor contacts: MJX pays for every candidate pair on every physics step. -->
  <contact>
    {chr(10).join('    ' + p for p in pairs).strip()}
  </contact>
  <actuator>
    {chr(10).join('    ' + a for a in actuators).strip()}
  </actuator>
  <sensor>
    <accelerometer name="accelerometer" site="imu"/>
    <gyro name="gyro" site="imu"/>
    <framequat name="orientation" objtype="site" objname="imu"/>
  </sensor>
</mujoco>
"""


def load_model(spec: RobotSpec = HB40, split_pd: bool = False, ground=None) -> mujoco.MjModel:
    """Native MuJoCo model of the robot on its ground (see `mjcf`); ValueError for a part MJX cannot collide with it."""
    model = mujoco.MjModel.from_xml_string(mjcf(spec, split_pd, ground))
    if ground is not None:
        terrain.check_collisions(model)
        terrain.set_heights(model, ground)
    return model


def sensor_slice(model: mujoco.MjModel, name: str) -> slice:
    """Where the sensor `name` sits in `sensordata`."""
    sensor = model.sensor(name)
    return slice(int(sensor.adr[0]), int(sensor.adr[0] + sensor.dim[0]))
