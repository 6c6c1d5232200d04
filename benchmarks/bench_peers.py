"""Our CrossQ beside sbx's CrossQ on the same robot, task and protocol, in one run on this CPU.

Both learn JT-NF forward at 0.5 m/s under the thesis-code protocol for 3 seeds x 20k steps with
the thesis code's CrossQ hyperparameters (learning rate 0.005, batch 128, 256x256 actor and
critic, Adam b1 0.5, batch renorm in actor and critic with momentum 0.99 and a 1000-step warm-up,
actor updated every step, target entropy -6, log-std clipped to [-20, 2], 1000 random steps
first, one update per step). sbx differs in one detail we cannot set: its temperature loss is
log(alpha) * (H - target), where the thesis code scales by alpha (our `alpha_loss_scaled`).
Ours runs its three seeds vmapped on MJX; sbx runs one seed after another on the Gymnasium env
(native MuJoCo, `mjx_badger/HB40-v0`), as its users would.

The same evaluation for both: every 1000 steps, the deterministic policy for 400 steps from a
fresh episode under 0.5 m/s forward, the mean forward velocity until a first fall (ours in its
MJX training env as every run does, sbx's on the native env it trains on); at the end every
final policy of both is evaluated the same way on the native env. Evaluation time is left out
of the throughput figures. Also: where each learner's time goes (env vs gradient update), and
the learner's arithmetic rate (XLA's FLOPs per update x updates/s) beside a plain jitted
matmul at the learner's shapes.

Run: `make bench-peers` (installs the optional `peers` extra: sbx-rl, Stable-Baselines3, torch), which runs
`python -m benchmarks.bench_peers` from the repository root.
Writes benchmarks/results/peers.json and peers.png.
"""

import argparse
import json
import time
from pathlib import Path

import gymnasium
import jax
import jax.numpy as jnp
import numpy as np

import mjx_badger
from benchmarks.common import RESULTS, mjx_env_steps_per_s, timed, update_program
from mjx_badger.experiments.registry import EXPERIMENTS, result_name
from mjx_badger.learning import runner
from mjx_badger.records import policy, results

OUT = RESULTS / "peers.json"
SEEDS, STEPS, EVERY, EVAL_STEPS, WARMUP = 3, 20_000, 1_000, 400, 1_000
COMMAND = (0.5, 0.0, 0.0)
ENV_KWARGS = dict(approach="jt-nf", task="forward", protocol="thesis-code")


def evaluate(act, env) -> tuple[float, int]:
    """Mean forward velocity until a first fall, and falls, of `act` for EVAL_STEPS from a fresh episode."""
    obs, _ = env.reset(options={"command": COMMAND})
    velocities, falls = [], 0
    for _ in range(EVAL_STEPS):
        obs, _, terminated, truncated, info = env.step(act(obs))
        if falls == 0:
            velocities.append(info["desired_velocity"])
        falls += int(terminated)
        if terminated or truncated:
            obs, _ = env.reset(options={"command": COMMAND})
    return float(np.mean(velocities)), falls


def our_run():
    """The quick profile's JT-NF CrossQ forward run under thesis-code (what `reproduce` runs), and its config."""
    experiment = EXPERIMENTS["forward"]
    run = next(r for r in experiment.runs if r.approach == "jt-nf" and r.algo == "crossq")
    return run, experiment.train_config(run, "quick", "thesis-code")


def ours(folder: Path) -> dict:
    """Our trainer on our_run(), seed for seed the reproduce run."""
    run, config = our_run()
    assert (config.total_steps, config.chunk_steps, config.warmup_steps, config.eval_steps) == (
        STEPS, EVERY, WARMUP, EVAL_STEPS)
    path = folder / result_name(run)
    document = runner.run(config, list(range(SEEDS)), path, progress=False, resume=False, tensorboard=False)
    clock = document["wall_clock"]
    curve = np.array(document["metrics"]["eval/forward/desired_velocity"], dtype=float)  # [chunk][seed]
    env = gymnasium.make(mjx_badger.GYM_ENV_ID, **ENV_KWARGS)
    env.reset(seed=100)
    final = [evaluate(policy.load(path.parent / document["policy"], seed=seed), env) for seed in range(SEEDS)]
    return {"steps": document["steps"], "eval_velocity": curve.T.tolist(), "compile_s": clock["compile_s"],
            "run_s": clock["run_s"], "seed_steps_per_s_per_seed": STEPS / clock["run_s"],
            "seed_steps_per_s_total": SEEDS * STEPS / clock["run_s"],
            "updates_per_s_per_seed": (STEPS - WARMUP) / clock["run_s"],
            "final_native_velocity": [v for v, _ in final], "final_native_falls": [f for _, f in final],
            "config": document["config"]["agent"]}


def sbx_crossq(seed: int) -> dict:
    """sbx CrossQ for one seed: learning curve, training time by chunk (evaluation excluded), final evaluation."""
    from sbx import CrossQ
    from stable_baselines3.common.callbacks import BaseCallback

    env = gymnasium.make(mjx_badger.GYM_ENV_ID, **ENV_KWARGS)
    eval_env = gymnasium.make(mjx_badger.GYM_ENV_ID, **ENV_KWARGS)
    eval_env.reset(seed=100 + seed)
    model = CrossQ("MlpPolicy", env, learning_rate=0.005, batch_size=128, gamma=0.99, buffer_size=STEPS,
                   learning_starts=WARMUP, train_freq=1, gradient_steps=1, policy_delay=1, ent_coef="auto",
                   target_entropy=-6.0, seed=seed, verbose=0,
                   policy_kwargs=dict(net_arch=dict(pi=[256, 256], qf=[256, 256]), batch_norm=True,
                                      batch_norm_actor=True, batch_norm_momentum=0.99, renorm_warmup_steps=1000,
                                      optimizer_kwargs={"b1": 0.5}))
    act = lambda obs: model.predict(obs, deterministic=True)[0]
    chunks, curve = [], []

    class EveryChunk(BaseCallback):
        def _on_training_start(self):
            self.started = time.perf_counter()

        def _on_step(self):
            if self.num_timesteps % EVERY == 0:
                chunks.append(time.perf_counter() - self.started)
                curve.append(evaluate(act, eval_env)[0])
                self.started = time.perf_counter()
            return True

    model.learn(STEPS, callback=EveryChunk())
    final = evaluate(act, eval_env)
    learning = chunks[1:]  # the first chunk is the random warm-up; the second holds the jit compile
    steady = float(np.median(learning[1:]))
    return {"seed": seed, "chunk_s": chunks, "eval_velocity": curve, "final_native_velocity": final[0],
            "final_native_falls": final[1], "train_s": float(sum(chunks)),
            "compile_s_estimate": learning[0] - steady, "steady_chunk_s": steady}


def native_env_steps_per_s(steps: int = 2000) -> float:
    """Gymnasium env control steps/s under random actions (sbx's env cost per step)."""
    env = gymnasium.make(mjx_badger.GYM_ENV_ID, **ENV_KWARGS)
    env.reset(seed=0)
    env.step(env.action_space.sample())  # compiles the env's jitted pieces
    t0 = time.perf_counter()
    for _ in range(steps):
        if any(env.step(env.action_space.sample())[2:4]):
            env.reset()
    return steps / (time.perf_counter() - t0)


def arithmetic(agent_config) -> dict:
    """The learner's FLOP rate (XLA cost analysis x measured updates/s) beside jitted matmuls at its shapes."""
    # XLA's cost analysis of the lowered program counts a loop's body once (one update here). The compiled
    # CPU program's analysis is no help: it also counts the body once, and drops dots it hands to libraries
    # when the loop is unrolled (31 MFLOP for one update, where the critic's forward pass alone is 84).
    fn, args = update_program(1, updates=1, cfg=agent_config)
    flops = fn.lower(*args).cost_analysis()["flops"]
    updates = 200
    fn, args = update_program(1, updates=updates, cfg=agent_config)
    rate = updates / timed(fn, *args)
    batch = 2 * agent_config.batch_size  # CrossQ's joint forward pass of (s, a) and (s', a')

    def matmul_rate(rows, size, repeats=200):
        x = jax.random.normal(jax.random.PRNGKey(0), (rows, size))
        w = jnp.linalg.qr(jax.random.normal(jax.random.PRNGKey(1), (size, size)))[0]  # orthogonal: y keeps its norm
        chain = jax.jit(lambda x, w: jax.lax.fori_loop(0, repeats, lambda i, y: y @ w, x))
        return 2.0 * rows * size * size * repeats / timed(chain, x, w)

    learner_shape = matmul_rate(batch, agent_config.hidden[0])
    large = matmul_rate(1024, 1024, repeats=20)
    return {"flops_per_update": flops, "updates_per_s": rate, "learner_gflops": flops * rate / 1e9,
            "matmul_gflops_at_learner_shape": learner_shape / 1e9, "matmul_shape": [batch, agent_config.hidden[0]],
            "matmul_gflops_1024": large / 1e9, "fraction_of_learner_shape_matmul": flops * rate / learner_shape,
            "fraction_of_1024_matmul": flops * rate / large}


def plot(report: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    steps = np.array(report["ours"]["steps"]) / 1000
    for label, curves, color in (("mjx_badger CrossQ (MJX, 3 seeds vmapped)", report["ours"]["eval_velocity"], "C0"),
                                 ("sbx CrossQ (native MuJoCo, Gymnasium)", [r["eval_velocity"] for r in report["sbx"]],
                                  "C1")):
        curves = np.array(curves, dtype=float)
        ax.plot(steps[:curves.shape[1]], np.nanmean(curves, 0), color=color, label=label)
        ax.fill_between(steps[:curves.shape[1]], np.nanmin(curves, 0), np.nanmax(curves, 0), color=color, alpha=0.2)
    ax.axhline(0.5, color="grey", lw=0.8, ls="--")
    ax.set(xlabel="environment steps (k)", ylabel="evaluation forward velocity (m/s)",
           title="JT-NF forward 0.5 m/s, thesis-code protocol (mean, min-max of 3 seeds)")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def summarize(report: dict) -> dict:
    """The peer table's figures from the measurements: seeds-steps/s for 3 seeds x 20k steps, updates/s, compile."""
    ours, sbx = report["ours"], report["sbx"]
    sbx_train_s = float(np.sum([r["train_s"] for r in sbx]))  # one seed after another
    sbx_warmup_s = float(np.sum([r["chunk_s"][0] for r in sbx]))
    # Our chunks also run the evaluation (400 steps per 1000, every seed, in MJX); sbx's time leaves it out.
    # Its cost, at the measured MJX rate for 3 seeds, is taken out of ours for the like-for-like figure.
    eval_s = len(ours["steps"]) * EVAL_STEPS * SEEDS / report["where_time_goes"]["ours_mjx_env_steps_per_s_batch_3"]
    table = {
        "ours": {"seed_steps_per_s": SEEDS * STEPS / ours["run_s"],
                 "seed_steps_per_s_without_eval": SEEDS * STEPS / (ours["run_s"] - eval_s),
                 "eval_s_estimate": eval_s,
                 "updates_per_s": SEEDS * (STEPS - WARMUP) / ours["run_s"],
                 "compile_s": ours["compile_s"],
                 "final_velocity_mean": float(np.mean(ours["final_native_velocity"])),
                 "final_falls": ours["final_native_falls"]},
        "sbx": {"seed_steps_per_s": SEEDS * STEPS / sbx_train_s,
                "updates_per_s": SEEDS * (STEPS - WARMUP) / (sbx_train_s - sbx_warmup_s),
                "compile_s": float(np.mean([r["compile_s_estimate"] for r in sbx])),
                "final_velocity_mean": float(np.mean([r["final_native_velocity"] for r in sbx])),
                "final_falls": [r["final_native_falls"] for r in sbx]},
    }
    table["throughput_ratio"] = table["ours"]["seed_steps_per_s"] / table["sbx"]["seed_steps_per_s"]
    table["throughput_ratio_without_eval"] = (table["ours"]["seed_steps_per_s_without_eval"]
                                              / table["sbx"]["seed_steps_per_s"])
    return table


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--work", type=Path, default=Path("results/peers"), help="folder for our run's files")
    parser.add_argument("--resummarize", action="store_true",
                        help="recompute the table and plot from the measurements in --out, running nothing")
    args = parser.parse_args()
    if args.resummarize:
        report = json.loads(args.out.read_text())
    else:
        # The persistent compilation cache is deliberately not enabled, so compile times are real.
        report = {"machine": results.hardware(), "versions": results.versions(), "git_commit": results.git_commit()}
        report["ours"] = ours(args.work)
        print(f"ours: {SEEDS * STEPS / report['ours']['run_s']:.1f} seed-steps/s, "
              f"final {report['ours']['final_native_velocity']}", flush=True)
        report["sbx"] = [sbx_crossq(seed) for seed in range(SEEDS)]
        for run in report["sbx"]:
            print(f"sbx seed {run['seed']}: {STEPS / run['train_s']:.1f} steps/s, "
                  f"final {run['final_native_velocity']:.2f}", flush=True)
        report["where_time_goes"] = {"ours_mjx_env_steps_per_s_batch_3": mjx_env_steps_per_s(SEEDS),
                                     "native_gym_env_steps_per_s": native_env_steps_per_s()}
        report["arithmetic"] = arithmetic(our_run()[1].agent_config)
    for stale in ("sbx_summary", "ratio_per_seed_throughput"):
        report.pop(stale, None)
    report["table"] = summarize(report)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1))
    plot(report, args.out.with_suffix(".png"))
    print(json.dumps({k: report[k] for k in ("table", "where_time_goes", "arithmetic")}, indent=1))


if __name__ == "__main__":
    main()
