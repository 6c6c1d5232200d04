"""A saved policy for the robot's own computer: its deterministic actor as ONNX and the settings that run it.

`export(results, seed, out)` writes `out` (.onnx, opset OPSET, float32: observation (batch, O) -> action (batch, A)
in [-1, 1], the tanh of the actor's mean, built with onnx.helper from the saved policy's layers: dense, relu and
the released CrossQ's batch renormalisation with its running statistics) and beside it `<stem>.onboard.json`
(realtime/onboard.SCHEMA): rate, PD gains, nominal pose, observation layout and how its angular acceleration is
measured, action scale, filter or CPG, estimator, leg figures, safety limits and the task's commands.
`realtime/onboard.OnboardPolicy` runs the pair with NumPy and onnxruntime. `check` compares the ONNX actor with
the JAX agent's deterministic action.
"""

import inspect
import json
from pathlib import Path

import jax
import numpy as np
import onnx
import onnxruntime
from onnx import TensorProto, helper, numpy_helper

from mjx_badger.agents.agent import make_agent
from mjx_badger.control import actions, cpg, filters
from mjx_badger.core import safe_io
from mjx_badger.core.validation import INT32_MAX, integer
from mjx_badger.estimation.estimators import KalmanConfig
from mjx_badger.learning.config import TrainConfig, from_results
from mjx_badger.realtime import onboard
from mjx_badger.records import policy, results
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics
from mjx_badger.robot.safety import JOINT_MARGIN_RAD

OPSET = 17
IR_VERSION = 8
"""ONNX IR of opset 17: a robot's older onnxruntime (1.12 and later) reads the file too."""
INPUT, OUTPUT = "observation", "action"
JT_FILTERS = {"jt-nf": "none", "jt-lpf": "lowpass", "jt-oef": "one_euro"}
CPG_RESIDUALS = {"cpg-d": None, "cpg-vf": None, "cpg-rt-avg": "angle-average", "cpg-rt-sum": "angle-sum"}
SUPPORTED = (*JT_FILTERS, *CPG_RESIDUALS)
"""The approaches the onboard runner runs; cpg-rt too where its protocol's residual mode is one of these two."""
MAX_CHECKED = 1_000_000
MAX_DIFFERENCE = 1e-5
"""The largest |ONNX - JAX| action difference an export may show over `check`'s observations (issue 63)."""
RANGES = {"joint_angle": (0.0, 0.2), "joint_velocity": (0.0, 3.0), "predicted_joint_angle": (0.0, 0.2),
          "predicted_feet_position": (0.0, 0.05), "trunk_linear_acceleration": ([0.0, 0.0, 9.81], 2.0),
          "trunk_angular_acceleration": (0.0, 20.0), "trunk_linear_velocity": (0.0, 0.3),
          "trunk_angular_velocity": (0.0, 0.5), "target_velocity": (0.0, 0.25),
          "projected_gravity": ([0.0, 0.0, -1.0], 0.1),
          "cpg_progress": (0.5, 0.3)}
"""(centre, standard deviation) of each observation block's quantity, in its own units (rad, rad/s, m, m/s^2,
rad/s^2, m/s): a walking robot's, joint angles as offsets from the nominal pose, the IMU reading gravity."""


def saved(results_file: Path, seed: int | None) -> tuple[dict, TrainConfig, policy.Policy]:
    """(document, config, actor) of a results file's saved policy, one seed (default its first); ValueError naming
    what is wrong: the file, its policy, the seed (the valid ones), a diverged seed."""
    path = Path(results_file)
    if seed is not None:
        integer("--seed", seed, 0, INT32_MAX)
    if not path.is_file():
        raise ValueError(f"no results file {str(path)!r}")
    document = results.read(path)
    if "policy" not in document:
        why = policy.unsupported(document.get("config", {}).get("agent", {}))
        raise ValueError(f"{path} has no saved policy: {why or 'complete runs since policies are saved have one'}")
    if not (path.parent / document["policy"]).is_file():
        raise ValueError(f"{path}: its saved policy {str(path.parent / document['policy'])!r} is missing")
    actor = policy.load(path.parent / document["policy"], seed)  # names the seeds it holds
    if actor.seed in results.diverged(document):
        raise ValueError(f"seed {actor.seed} of {path.name} diverged at step {results.diverged(document)[actor.seed]};"
                         f" its policy is frozen from before, choose another of {actor.meta['seeds']}")
    return document, from_results(document), actor


def actor_model(actor: policy.Policy) -> onnx.ModelProto:
    """The deterministic actor as an ONNX model, one node per operation of the saved layers, then tanh."""
    nodes, weights = [], []
    x = INPUT

    def constant(name, value):
        weights.append(numpy_helper.from_array(np.asarray(value, np.float32), name))
        return name

    def node(op, inputs, out):
        nodes.append(helper.make_node(op, inputs, [out]))
        return out

    for layer in actor.layers:
        name = layer.get("name", f"relu_{len(nodes)}")
        a = lambda key: actor.arrays[f"{name}/{key}"]
        if layer["op"] == "dense":
            x = node("Add", [node("MatMul", [x, constant(f"{name}/kernel", a("kernel"))], f"{name}/matmul"),
                             constant(f"{name}/bias", a("bias"))], f"{name}/out")
        elif layer["op"] == "relu":
            x = node("Relu", [x], f"{name}/out")
        else:  # batch renormalisation with its running statistics, as the JAX actor computes it in float32
            std = np.sqrt(a("var").astype(np.float32) + np.float32(layer["epsilon"]))
            x = node("Sub", [x, constant(f"{name}/mean", a("mean"))], f"{name}/centred")
            x = node("Div", [x, constant(f"{name}/std", std)], f"{name}/normed")
            x = node("Add", [node("Mul", [x, constant(f"{name}/scale", a("scale"))], f"{name}/scaled"),
                             constant(f"{name}/bias", a("bias"))], f"{name}/out")
    node("Tanh", [x], OUTPUT)
    graph = helper.make_graph(
        nodes, "actor", [helper.make_tensor_value_info(INPUT, TensorProto.FLOAT, ["batch", actor.observation_size])],
        [helper.make_tensor_value_info(OUTPUT, TensorProto.FLOAT, ["batch", actor.meta["action_size"]])], weights)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)], producer_name="mjx_badger",
                              ir_version=IR_VERSION)
    helper.set_model_props(model, {"seed": str(actor.seed), "approach": actor.meta["config"]["approach"]})
    onnx.checker.check_model(model)
    return model


def refusal(config: TrainConfig) -> str:
    """'' or why the onboard runner cannot run the approach of `config`."""
    protocol, _ = actions.on_robot(config.approach, config.protocol_spec, config.conditions_spec)
    supported = f"the onboard runner takes {', '.join(SUPPORTED)}"
    if config.approach not in SUPPORTED and config.approach != "cpg-rt":
        return f"approach {config.approach!r} is not ported to the robot's computer; {supported}"
    if actions.is_cpg(config.approach) and protocol.cpg_action != "foot-offsets":
        return (f"{config.approach} under {protocol.name}: the released code's CPG (cpg_action "
                f"{protocol.cpg_action!r}) is not ported; {supported} with foot offsets (thesis-text)")
    sensing = config.conditions_spec.sensing
    if sensing is not None and sensing.kalman.contact_trust:
        return (f"kalman.contact_trust {sensing.kalman.contact_trust:g}: the onboard estimator weighs every foot alike "
                "(the thesis's robot); export a policy trained with contact_trust 0")
    if config.approach == "cpg-rt" and protocol.cpg_residual not in onboard.RESIDUALS:
        return (f"cpg-rt under {protocol.name} combines by {protocol.cpg_residual!r}, two PD controllers per joint "
                f"that a robot does not have; {supported}")
    return ""


def filter_settings(config: TrainConfig) -> dict:
    """The JT approach's filter under its protocol (actions.jt_filter), every parameter resolved."""
    protocol, params = config.protocol_spec, dict(config.approach_params)
    name = JT_FILTERS[config.approach]
    if name == "lowpass" and protocol.lowpass == "butterworth":
        name = "butterworth"
    if name == "one_euro":
        params["start_at_first_input"] = protocol.one_euro_first_output_is_input
    defaults = {k: p.default for k, p in list(inspect.signature(filters.FILTERS[name]).parameters.items())[1:]}
    return {"name": name, "params": {**defaults, **params}}


def cpg_settings(config: TrainConfig) -> dict:
    """The foot-offsets CPG's figures (actions.central_pattern, cpg.py)."""
    protocol, robot_params = actions.on_robot(config.approach, config.protocol_spec, config.conditions_spec)
    params, spec = {**robot_params, **dict(config.approach_params)}, config.robot_spec
    residual = protocol.cpg_residual if config.approach == "cpg-rt" else CPG_RESIDUALS[config.approach]
    return {"variable_frequency": config.approach == "cpg-vf", "residual": residual,
            "frequency_hz": params.get("frequency_hz", actions.CPG_FREQUENCY_HZ),
            "frequency_range_hz": list(actions.CPG_FREQUENCY_RANGE_HZ),
            "heights_before_advance": protocol.cpg_heights_before_advance,
            "apex_height": params.get("apex_m", cpg.APEX_HEIGHT),
            "swing_fraction": cpg.SWING_FRACTION, "leg_phase_offsets": cpg.leg_phase_offsets(spec).tolist(),
            "foot_offset_scale": actions.FOOT_OFFSET_SCALE.tolist(), "residual_scale": actions.RESIDUAL_SCALE.tolist(),
            "nominal_feet": kinematics.nominal_feet(spec).tolist()}


def leg_figures(spec: robot.RobotSpec) -> dict:
    """The leg kinematics' figures of `spec` (kinematics.leg) and its hips, as onboard_estimator.Legs reads them."""
    figures = {k: np.asarray(v).tolist() for k, v in kinematics.leg(spec)._asdict().items()}
    return dict(figures, hip_positions=spec.hip_positions.tolist())


def onboard_settings(results_file: Path, document: dict, config: TrainConfig, actor: policy.Policy,
                     onnx_name: str) -> dict:
    """Everything but the network that the robot's computer needs to run the policy (realtime/onboard.SCHEMA)."""
    protocol, spec, is_cpg = config.protocol_spec, config.robot_spec, actions.is_cpg(config.approach)
    control_hz = float(actor.meta["control_hz"])
    control_dt = round(1.0 / (control_hz * spec.physics_dt)) * spec.physics_dt  # the env's: whole physics steps
    sensing = config.conditions_spec.sensing
    kalman = sensing.kalman if sensing is not None else KalmanConfig()
    commands = {name: list(command) for name, command in config.make_task().eval_commands.items()}
    return {
        "schema": onboard.SCHEMA,
        "onnx": {"file": onnx_name, "opset": OPSET, "input": INPUT, "output": OUTPUT},
        "source": {"results": Path(results_file).name,
                   "policy": document["policy"], "seed": actor.seed, "git_commit": document.get("git_commit")},
        "robot": spec.name, "approach": config.approach, "kind": "cpg" if is_cpg else "jt", "algo": config.algo,
        "protocol": protocol.name, "conditions": config.conditions,
        "task": {"name": config.task, "params": dict(config.task_params), "eval_commands": commands,
                 "command": next(iter(commands.values()))},
        "control_hz": control_hz, "control_dt": control_dt,
        "pd_gains": list(protocol.pd_gains(is_cpg)),
        "nominal_pose": robot.nominal_pose(spec).tolist(),
        "observation": {"layout": actor.meta["observation_layout"], "size": actor.observation_size,
                        "angular_acceleration": "gyro-difference" if protocol.observation == "thesis-text" else "zero"},
        "action": {"size": actor.meta["action_size"],
                   "scale": None if is_cpg else robot.jt_action_scale(spec).tolist()},
        **({"cpg": cpg_settings(config)} if is_cpg else {"filter": filter_settings(config)}),
        "estimator": {"name": "kinematic-kalman", "acceleration_std": kalman.acceleration_std,
                      "odometry_std": kalman.odometry_std, "trained_with": sensing.estimator if sensing else None},
        "kinematics": leg_figures(spec),
        "safety": {"fall_tilt_rad": spec.fall_tilt_rad, "joint_margin_rad": JOINT_MARGIN_RAD,
                   "damping_gains": list(spec.damping_gains), "joint_names": list(spec.joint_names)},
    }


def export(results_file: Path, seed: int | None, out: Path) -> Path:
    """Write the saved policy of `seed` (default the run's first) as `out` (.onnx) and its `.onboard.json` beside
    it; `out`. ValueError, before anything is written, for a file, seed or approach the robot cannot run."""
    out = Path(out)
    if out.suffix != ".onnx":
        raise ValueError(f"{str(out)!r}: the exported policy's file ends in .onnx")
    document, config, actor = saved(results_file, seed)
    why = refusal(config)
    if why:
        raise ValueError(why)
    settings = onboard_settings(results_file, document, config, actor, out.name)
    model = actor_model(actor)
    out.parent.mkdir(parents=True, exist_ok=True)
    safe_io.write_bytes(out, model.SerializeToString())
    safe_io.write_text(onboard.settings_path(out), json.dumps(settings, indent=1))
    return out


def observations(actor: policy.Policy, n: int, seed: int = 0) -> np.ndarray:
    """(n, O) float32 observations in the range the actor meets: each block a normal draw of its quantity (RANGES),
    times its scale; an actor that renormalises its input (the released CrossQ's) draws from its running statistics
    instead, the inputs it was trained on (a constant input of variance ~0 is amplified 30-fold there, so a wider
    draw tests inputs it never saw)."""
    rng = np.random.default_rng(seed)
    if actor.layers[0]["op"] == "renorm":
        mean, var = (actor.arrays[f"{actor.layers[0]['name']}/{k}"] for k in ("mean", "var"))
        return (mean + np.sqrt(var) * rng.normal(size=(n, mean.size))).astype(np.float32)
    blocks = []
    for name, size, scale in actor.meta["observation_layout"]:
        centre, spread = RANGES.get(name, (0.0, 1.0 / scale))
        blocks.append((np.asarray(centre) + spread * rng.normal(size=(n, size))) * scale)
    return np.concatenate(blocks, axis=1).astype(np.float32)


def agent_state(agent, actor: policy.Policy):
    """An AgentState of `agent` holding the saved actor; every other array zeros (traced for its shapes, nothing
    run): the deterministic action reads none of them, the log-std head included."""
    state = jax.tree.map(lambda s: np.zeros(s.shape, s.dtype), jax.eval_shape(agent.init, jax.random.PRNGKey(0)))
    for key, value in actor.arrays.items():
        layer, name = key.split("/")
        (state.actor_stats if name in ("mean", "var") else state.actor_params["params"])[layer][name] = value
    return state


def jax_actor(config: TrainConfig, actor: policy.Policy):
    """observation (n, O) -> the JAX agent's deterministic action, its actor the saved one."""
    agent = make_agent(config.agent_config, actor.observation_size, actor.meta["action_size"])
    state = agent_state(agent, actor)
    return lambda obs: np.asarray(agent.act(state, obs, None, deterministic=True))


def check(results_file: Path, seed: int | None, onnx_path: Path, n: int = 1000) -> float:
    """The largest |ONNX - JAX| over every action dimension of `n` observations (`observations`), onnxruntime on
    the CPU against the JAX agent with the saved actor."""
    integer("n", n, 1, MAX_CHECKED)
    _, config, actor = saved(results_file, seed)
    if not Path(onnx_path).is_file():
        raise ValueError(f"no ONNX file {str(onnx_path)!r} (export writes it)")
    session = onnxruntime.InferenceSession(str(onnx_path), providers=["CPUExecutionProvider"])
    takes = session.get_inputs()[0].shape[-1]
    if takes != actor.observation_size:
        raise ValueError(f"{onnx_path} takes observations of size {takes}, the saved policy {actor.observation_size}")
    obs = observations(actor, n)
    onnx_action = session.run(None, {session.get_inputs()[0].name: obs})[0]
    return float(np.max(np.abs(onnx_action - jax_actor(config, actor)(obs))))
