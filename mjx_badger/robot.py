"""HB40 model and physical constants (DESIGN.md, thesis §4.1)."""

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

MODEL_PATH = Path(__file__).parent / "assets" / "hb40.xml"

LEGS = ("FL", "FR", "RL", "RR")
JOINTS_PER_LEG = ("hip", "thigh", "knee")
JOINT_NAMES = tuple(f"{leg}_{joint}" for leg in LEGS for joint in JOINTS_PER_LEG)
NUM_JOINTS = len(JOINT_NAMES)
FOOT_GEOMS = tuple(f"{leg}_foot" for leg in LEGS)

# Left legs abduct outward with a positive hip angle, right legs with a negative one.
_SIDE_SIGN = np.array([1.0, -1.0, 1.0, -1.0])
# Thesis §4.1 nominal pose [hip, thigh, knee] = [0.1, 0.6, -1.2], hip mirrored per side.
NOMINAL_POSE = np.concatenate([[0.1 * s, 0.6, -1.2] for s in _SIDE_SIGN]).astype(np.float32)
# Thesis §4.1: joint-target actions stay within +-[0.2, 0.4, 0.4] of the nominal pose.
JT_ACTION_SCALE = np.tile([0.2, 0.4, 0.4], 4).astype(np.float32)

PHYSICS_DT = 0.005
# A public HB40 model uses Kp 20, Kd 0.5; with this model the robot collapses under them
# within 2 s (knee sag 0.13 rad, trunk pitches over), so the stand needs stiffer gains.
KP, KD = 60.0, 1.5
DAMPING_KP, DAMPING_KD = 0.0, 3.0
TORQUE_LIMIT = 16.0
# Trunk height with the legs in the nominal pose (feet at 0.02 m sphere radius).
STANDING_HEIGHT = 0.02 + 0.4 * np.cos(0.6) * np.cos(0.1)


def load_model(split_pd: bool = False) -> mujoco.MjModel:
    """Native MuJoCo model of the HB40.

    With `split_pd` every joint gets a second PD actuator and both run at half gains and half
    torque limit: their summed torque is the average of two full PD controllers, each clipped
    at +-16 N m, which is how the residual CPG combines its two targets in simulation
    (thesis §4.3). Actuators 0-11 take the first targets, 12-23 the second.
    """
    if not split_pd:
        return mujoco.MjModel.from_xml_path(str(MODEL_PATH))
    root = ET.parse(MODEL_PATH).getroot()
    actuators = root.find("actuator")
    originals = list(actuators)
    half = {"kp": f"{KP / 2:g}", "kv": f"{KD / 2:g}", "forcerange": f"{-TORQUE_LIMIT / 2:g} {TORQUE_LIMIT / 2:g}"}
    for element in originals:
        element.attrib.update(half)
    for element in originals:
        actuators.append(ET.Element("position", dict(element.attrib, name=element.get("name") + "_residual")))
    return mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))


def standing_qpos(model: mujoco.MjModel) -> np.ndarray:
    """qpos with the trunk level at standing height and the legs in the nominal pose."""
    qpos = np.zeros(model.nq)
    qpos[:3] = [0.0, 0.0, STANDING_HEIGHT]
    qpos[3] = 1.0
    qpos[7:] = NOMINAL_POSE
    return qpos


def set_pd_gains(model, kp: float, kd: float):
    """Return the model with every actuator's PD gains set (works for MjModel and mjx.Model)."""
    gain = np.zeros_like(np.asarray(model.actuator_gainprm))
    gain[:, 0] = kp
    bias = np.zeros_like(np.asarray(model.actuator_biasprm))
    bias[:, 1] = -kp
    bias[:, 2] = -kd
    if isinstance(model, mujoco.MjModel):
        model.actuator_gainprm[:] = gain
        model.actuator_biasprm[:] = bias
        return model
    return model.replace(actuator_gainprm=gain, actuator_biasprm=bias)


def sensor_slice(model: mujoco.MjModel, name: str) -> slice:
    """Where the sensor `name` sits in `sensordata`."""
    sensor = model.sensor(name)
    return slice(int(sensor.adr[0]), int(sensor.adr[0] + sensor.dim[0]))
