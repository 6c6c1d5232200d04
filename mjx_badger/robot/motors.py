"""The motors' PD controllers on a built model: their gains, set per approach and protocol or by the safety stop."""

import mujoco
import numpy as np


def set_pd_gains(model, kp: float, kd: float, split_pd: bool = False):
    """Return the model with every actuator's PD gains set (works for MjModel and mjx.Model).

    `split_pd` says the model was built with two PD actuators per joint (mjcf.mjcf(split_pd=True)): each then gets
    half the gains. ValueError if the model's actuators are not one (or two) per hinge joint.
    """
    per_joint = 2 if split_pd else 1
    actuators, joints = np.asarray(model.actuator_gainprm).shape[0], model.njnt - 1  # njnt counts the free joint
    if actuators != per_joint * joints:
        raise ValueError(f"the model has {actuators} actuators for {joints} joints, not {per_joint} per joint "
                         f"(split_pd={split_pd})")
    share = 1.0 / per_joint
    gain = np.zeros_like(np.asarray(model.actuator_gainprm))
    gain[:, 0] = kp * share
    bias = np.zeros_like(np.asarray(model.actuator_biasprm))
    bias[:, 1] = -kp * share
    bias[:, 2] = -kd * share
    if isinstance(model, mujoco.MjModel):
        model.actuator_gainprm[:] = gain
        model.actuator_biasprm[:] = bias
        return model
    return model.replace(actuator_gainprm=gain, actuator_biasprm=bias)
