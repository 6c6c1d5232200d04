"""The on-robot training run: the control loop on the calling thread, the learner beside it, stop and resume."""

import gc
import json
import signal
import threading
import time
from pathlib import Path

import jax

from mjx_badger.core import locks
from mjx_badger.realtime import control, pretrained, report, scheduling, session_checkpoint
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.control import Progress, build
from mjx_badger.realtime.estimation import KalmanConfig, VelocityEstimator, estimator_name
from mjx_badger.realtime.host_replay import HostReplay
from mjx_badger.realtime.interface import LinkLost, Robot
from mjx_badger.realtime.learner import Learner, replay_ratio_cap
from mjx_badger.realtime.operating import Between
from mjx_badger.realtime.operator import Operator
from mjx_badger.realtime.view import View, say
from mjx_badger.records import results


def run(config: RealtimeConfig, bot: Robot, out_dir: Path = Path("results/realtime"), resume: bool = True,
        view: bool = True, kalman: KalmanConfig = KalmanConfig(), lock_memory: bool = True,
        operator: Operator | None = None, test_policy=None, checkpoint_every_s: float = 60.0,
        stop: threading.Event | None = None) -> dict:
    """Train on `bot` for `config.steps` control steps (or until Ctrl-C); returns the results document.

    The learner updates the agent concurrently, at most `config.utd` times per learning step.
    Ctrl-C or SIGTERM damps the robot, then saves policy, optimiser state and replay buffer; the next
    run with the same settings resumes from them. `lock_memory=False` leaves the pages to the kernel
    (to measure what locking them buys). A second run into the same results file is refused (locks.py).
    `operator` (operator.py) is the console's: without one the run learns from the start. `test_policy` is an
    onboard.OnboardPolicy for the operator's test mode on a robot without a link. Every `checkpoint_every_s` a
    checkpoint is written between episodes, so a killed training process resumes from it. Setting `stop` ends the
    run as Ctrl-C does.
    """
    operator = operator or Operator("learning")
    with locks.hold(report.document_path(out_dir, config), "this on-robot run"):
        return _run(config, bot, out_dir, resume, view, kalman, lock_memory, operator, test_policy,
                    checkpoint_every_s, stop or threading.Event())


def _run(config: RealtimeConfig, bot: Robot, out_dir: Path, resume: bool, view: bool, kalman: KalmanConfig,
         lock_memory: bool, operator: Operator, test_policy, checkpoint_every_s: float,
         stop: threading.Event) -> dict:
    env, task, agent, tick, evaluate_tick, update = build(config)
    out_dir = Path(out_dir)
    saved = session_checkpoint.path(out_dir, config)
    key = jax.random.PRNGKey(config.seed)
    key, agent_key, learner_key = jax.random.split(key, 3)
    agent_state = pretrained.load(config, agent) if config.init_from else agent.init(agent_key)
    task_state = task.init()
    buffer = HostReplay(config.steps, env.observation_size, env.action_size)
    progress = Progress(config.steps)
    learner_updates = 0
    if resume and session_checkpoint.exists(saved):
        agent_state, task_state, key, learner_updates = session_checkpoint.load(
            saved, config, agent_state, task_state, key, buffer, progress)
        finished = report.document_path(out_dir, config)
        if progress.step >= config.steps and finished.exists():
            say(view, f"{config.name} is complete ({progress.step} steps): {finished}; --restart trains again")
            return json.loads(finished.read_text())
        say(view, f"resuming {config.name} at step {progress.step} ({progress.falls} falls so far)")

    compile_start = time.perf_counter()
    control.compile_all(env, tick, evaluate_tick, update, agent_state, task_state, config.agent_config.batch_size)
    compile_s = time.perf_counter() - compile_start
    # What is built by now (JAX, flax, MuJoCo: ~200k objects) lives as long as the run. Freeze it
    # out of the collector's reach: a full collection over it holds the GIL ~100 ms on this CPU,
    # four control periods.
    gc.collect()
    gc.freeze()

    cfg = config.agent_config
    feeds = cfg.observation_norm or cfg.reward_scaling != "none" or cfg.resets  # the newer agents' extras
    learner = Learner(update, agent_state, buffer, cfg.batch_size, learner_key, replay_ratio_cap(config, progress),
                      learner_updates, agent=agent if feeds else None, step=lambda: progress.step)
    learner.prepare()
    started = results.now()
    with scheduling.control_thread(lock_memory) as (realtime, locked):
        timing = report.timing_log(realtime, locked, scheduling.major_page_faults())
        previous_handlers = {signum: signal.signal(signum, lambda *_: stop.set())
                             for signum in (signal.SIGINT, signal.SIGTERM)} if _main_thread() else {}
        between = Between(started=operator.state == "learning", test_policy=test_policy)
        if between.started:
            bot.start()
        learner.start()
        scheduling.nice_compute_threads()
        session = control.Session(config, bot, env, tick, learner, buffer, progress, VelocityEstimator(kalman, env.spec, estimator_name(config)),
                                  timing, View(view, config, progress, learner, timing, operator, bot), stop, operator)
        saved_at = time.perf_counter()
        try:
            fresh = True
            while progress.step < config.steps and not stop.is_set():
                if operator.state != "learning":
                    between.handle(session, operator.state)
                    fresh = True
                    continue
                between.entering_learning(session)
                key, command_key = jax.random.split(key)
                task_state, command = task.command(task_state, command_key)
                fresh = control.episode(session, task_state, command, key, fresh)
                task_state, key = progress.task_state, progress.key
                if time.perf_counter() - saved_at > checkpoint_every_s:
                    # Between episodes, the robot standing: a save beside a walking robot would hold the GIL for
                    # tens of milliseconds, longer than a robot's watchdog waits for the next command.
                    if not fresh:
                        bot.hold()
                        fresh = True
                    session_checkpoint.save(saved, config, learner.state, task_state, key, learner.updates, buffer,
                                            progress)
                    saved_at = time.perf_counter()
        finally:
            bot.damp()  # safety first: motors soft before anything is saved
            between.stop_driving(bot)
            operator.become("finished")
            learner.stop()
            timing["major_page_faults"] = scheduling.major_page_faults() - timing["major_page_faults"]
            gc.unfreeze()
            for signum, handler in previous_handlers.items():
                signal.signal(signum, handler)
            session.view.close()
        try:
            complete = progress.step >= config.steps
            evaluation = control.evaluate(session, evaluate_tick, learner.state, task, key) if (
                complete and config.eval_seconds > 0) else None
        except LinkLost as error:  # the results and checkpoint are saved all the same
            say(view, f"no evaluation run: {error}")
            evaluation = None
        finally:
            bot.stop()
    session_checkpoint.save(saved, config, learner.state, task_state, key, learner.updates, buffer, progress)
    document = report.document(config, progress, timing, learner.updates, compile_s, started, complete, evaluation,
                               report.link_summary(bot))
    report.save(out_dir, config, document, progress)
    say(view, f"{'finished' if complete else 'stopped'} at step {progress.step}: {report.document_path(out_dir, config)}"
              + ("" if complete else f"; run again to resume from {saved}"))
    return document


def _main_thread() -> bool:
    """Whether the caller may install the Ctrl-C handler (Python allows it on the main thread only)."""
    return threading.current_thread() is threading.main_thread()
