"""Figures 2.1 and 2.2 of the thesis redrawn: every estimator against the truth over a walk, and the learned
estimators' error per epoch.

A walk is a trained policy on native MuJoCo with the robot's sensor noise (sensors.SensorModel),
its readings recorded at every control step; every estimator then runs on the same readings
(they are pure functions of them), from a standing start and again after any fall. Per
estimator the table gives the ratio of its mean forward velocity to the true one (below 1:
it underestimates), the mean absolute error of vx and vy, and its drift: the mean error of vx
over the walk's last two seconds.
"""

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.estimation import estimators, sensors
from mjx_badger.estimation.learned import load as load_fitted
from mjx_badger.learning.config import from_results
from mjx_badger.records import analysis, policy, results
from mjx_badger.sim import native

CLASSIC = ("kinematic-kalman", "kinematic-kalman-contact", "integration")
LABELS = {"kinematic-kalman": "(a) kinematics + IMU, all four feet (the thesis's robot)",
          "kinematic-kalman-contact": "(a) kinematics + IMU, feet weighted by estimated contact",
          "integration": "(b) acceleration integration"}
DRIFT_SECONDS = 2.0


def walk(results_path: Path, seconds: float, seed: int = 0) -> dict:
    """A run's best saved seed walking on native MuJoCo under its task's first command, sensors noisy: per control
    step the readings, the true trunk-frame velocity, the env's own estimate and whether a fall reset the robot."""
    document = results.read(results_path)
    policy_seed, _ = analysis.best_seed(results.read(results_path, leave_out_diverged=True))
    actor = policy.load(Path(results_path).parent / document["policy"], policy_seed)
    env = native.evaluation_env(from_results(document), seconds, sensors.Sensing())
    command = list(next(iter(env.task.eval_commands.values())))
    robot = native.NativeEnv(env)
    state = robot.reset(jax.random.PRNGKey(seed), command)
    trunk = robot.model.body("trunk").id
    record = {"reading": [], "truth": [], "estimate": [], "reset": []}
    for _ in range(int(round(seconds / env.control_dt))):
        state = robot.step(actor(np.asarray(state.obs)))
        rotation = robot.data.xmat[trunk].reshape(3, 3)
        record["reading"].append(jax.device_get(state.info["reading"]))
        record["truth"].append(rotation.T @ robot.data.qvel[:3])
        record["estimate"].append(np.asarray(state.info["estimate"]))
        record["reset"].append(bool(state.done))
        if state.done:  # a fall: the robot stands again, the estimators recalibrate
            state = robot.reset(robot.reset_key, command)
    readings = jax.tree.map(lambda *x: np.stack(x), *record["reading"])
    return {"name": f"{document['config']['approach']} {document['config']['algo']}", "results": str(results_path),
            "policy_seed": policy_seed, "command": command, "dt": env.control_dt, "readings": readings,
            "truth": np.array(record["truth"]), "estimate": np.array(record["estimate"]),
            "reset": np.array(record["reset"])}


def replay(estimator: estimators.Estimator, readings, reset, dt: float) -> np.ndarray:
    """(steps, 3) the estimator's velocity over recorded readings, started afresh after every step flagged `reset`."""

    def step(carry, inputs):
        state, fresh = carry
        reading, ends = inputs
        state = jax.tree.map(lambda a, b: jnp.where(fresh, a, b), estimator.init(), state)
        state, velocity = estimator.step(state, reading, dt)
        return (state, ends), velocity

    readings = jax.tree.map(jnp.asarray, readings)
    _, velocity = jax.jit(lambda r, e: jax.lax.scan(step, (estimator.init(), jnp.bool_(False)), (r, e)))(
        readings, jnp.asarray(reset))
    return np.asarray(velocity)


def scores(estimate: np.ndarray, truth: np.ndarray, dt: float) -> dict:
    """Ratio of mean forward velocities, MAE of vx and vy, and the drift (mean vx error over the last seconds)."""
    last = max(1, int(round(DRIFT_SECONDS / dt)))
    error = estimate[:, :2] - truth[:, :2]
    return {"ratio_to_truth": float(np.mean(estimate[:, 0]) / np.mean(truth[:, 0])),
            "mae_vx": float(np.mean(np.abs(error[:, 0]))), "mae_vy": float(np.mean(np.abs(error[:, 1]))),
            "drift_vx": float(np.mean(error[-last:, 0]))}


def compare(walks: list, learned: list) -> dict:
    """Every estimator's velocity and scores on every walk; `learned` fitted estimator files."""
    out = {}
    for w in walks:
        runs = {name: replay(estimators.make(name), w["readings"], w["reset"], w["dt"]) for name in CLASSIC}
        for path in learned:
            fitted = load_fitted(path)
            runs[f"(c) learned: {label(fitted.meta)}"] = replay(fitted.estimator(), w["readings"], w["reset"],
                                                                      w["dt"])
        out[w["name"]] = {"velocity": runs, "scores": {name: scores(v, w["truth"], w["dt"]) for name, v in runs.items()}}
    return out


def fit_curves(learned: list) -> dict:
    """Per fitted estimator its train and validation MAE per epoch, averaged over the velocity components."""
    curves = {}
    for path in learned:
        meta = load_fitted(path).meta
        curves[label(meta)] = {k: [float(np.mean(epoch)) for epoch in v] for k, v in meta["curves"].items()}
    return curves


def label(meta: dict) -> str:
    """A fitted estimator's name in figures and tables: its inputs, and its data's action noise where there was some."""
    noise = meta["dataset"].get("action_noise") or 0.0
    return f"{meta['inputs']['name']} inputs" + (f", data with noisy actions ({noise:g})" if noise else "")


def draw(policies, learned, seconds: float, seed: int, out: Path) -> dict:
    """Walk every policy, compare every estimator, draw both figures and write the table; returns the report."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    walks = [walk(path, seconds, seed) for path in policies]
    compared = compare(walks, learned)
    fig, axes = plt.subplots(len(walks), 2, figsize=(15, 3.6 * len(walks)), constrained_layout=True, squeeze=False,
                             sharey="row")
    for row, w in zip(axes, walks):
        time = w["dt"] * np.arange(1, len(w["truth"]) + 1)
        for ax, kind in zip(row, ("classic", "learned")):
            ax.plot(time, w["truth"][:, 0], color="black", lw=1.6, label="ground truth")
            for name, velocity in compared[w["name"]]["velocity"].items():
                if (name in CLASSIC) == (kind == "classic"):
                    ax.plot(time, velocity[:, 0], lw=1.0, label=LABELS.get(name, name))
            for t in time[w["reset"]]:
                ax.axvline(t, color="red", lw=0.6, alpha=0.5)
            what = "(a) and (b)" if kind == "classic" else "(c), learned on another policy's walking"
            ax.set_title(f"{w['name']} at {w['command'][0]:g} m/s, sensor noise: {what}", fontsize=10)
            ax.set_xlabel("time (s)")
            ax.grid(alpha=0.3)
        row[0].set_ylabel("forward velocity (m/s)")
    for ax in axes[0]:
        ax.legend(fontsize=7, loc="lower right")
    fig.savefig(out / "estimators_walk.png", dpi=110)
    plt.close(fig)
    files = [str(out / "estimators_walk.png")]
    curves = fit_curves(learned)
    if curves:
        fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
        for name, curve in curves.items():
            epochs = np.arange(1, len(curve["train_mae"]) + 1)
            line, = ax.plot(epochs, curve["validation_mae"], label=f"{name}: validation")
            ax.plot(epochs, curve["train_mae"], color=line.get_color(), ls="--", label=f"{name}: training")
        ax.axhline(0.2, color="gray", ls=":", label="thesis: saturates at 0.2")
        ax.axhline(0.05, color="green", ls=":", label="thesis: adequate below 0.05")
        ax.set_xlabel("epoch")
        ax.set_ylabel("MAE (m/s), mean of vx and vy")
        ax.set_yscale("log")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3, which="both")
        fig.savefig(out / "estimators_fit.png", dpi=110)
        plt.close(fig)
        files.append(str(out / "estimators_fit.png"))
    report = {"seconds": seconds, "seed": seed, "sensors": "sensors.SensorModel() defaults",
              "walks": {w["name"]: {"results": w["results"], "policy_seed": w["policy_seed"], "command": w["command"],
                                    "falls": int(w["reset"].sum()), "true_mean_vx": float(np.mean(w["truth"][:, 0])),
                                    "scores": compared[w["name"]]["scores"],
                                    "env_estimate_equals_replay": bool(np.allclose(
                                        w["estimate"], compared[w["name"]]["velocity"]["kinematic-kalman"], atol=1e-5))}
                        for w in walks},
              "fit": {name: {"final_train_mae": c["train_mae"][-1], "final_validation_mae": c["validation_mae"][-1],
                             "best_validation_mae": min(c["validation_mae"]), "epochs": len(c["train_mae"])}
                      for name, c in curves.items()}}
    (out / "estimators.json").write_text(json.dumps(report, indent=1))
    (out / "estimators.md").write_text(table(report) + "\n")
    report["files"] = files + [str(out / "estimators.json"), str(out / "estimators.md")]
    return report


def table(report: dict) -> str:
    """The Figure 2.1 table (and the learned estimators' final errors) as Markdown."""
    lines = [f"Over {report['seconds']:g} s on native MuJoCo with sensor noise:", "",
             "| walk | estimator | mean estimate / truth (vx) | MAE vx (m/s) | MAE vy (m/s) | drift vx, last 2 s (m/s) |",
             "|---|---|---|---|---|---|"]
    for name, w in report["walks"].items():
        for estimator, s in w["scores"].items():
            lines.append(f"| {name} (true mean vx {w['true_mean_vx']:.2f} m/s, {w['falls']} falls) | "
                         f"{LABELS.get(estimator, estimator)} | {s['ratio_to_truth']:.2f} | {s['mae_vx']:.3f} | "
                         f"{s['mae_vy']:.3f} | {s['drift_vx']:+.3f} |")
    if report["fit"]:
        lines += ["", "| learned estimator | train MAE | validation MAE (last epoch) | best validation MAE | "
                      "thesis |", "|---|---|---|---|---|"]
        for name, f in report["fit"].items():
            lines.append(f"| {name} | {f['final_train_mae']:.3f} | {f['final_validation_mae']:.3f} | "
                         f"{f['best_validation_mae']:.3f} | saturates at 0.2; adequate below 0.05 |")
    return "\n".join(lines)
