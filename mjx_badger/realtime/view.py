"""The operator's terminal and console feed: the run's live numbers, a line on stderr and a snapshot for the console."""

import sys
import time

import numpy as np

from mjx_badger.realtime.report import column

PUBLISH_EVERY_S = 0.2
"""The console's snapshots: five a second is live enough to watch and costs the control thread nothing much."""


def say(enabled: bool, text: str) -> None:
    if enabled:
        print(text, file=sys.stderr, flush=True)


class View:
    """The live numbers: steps, velocities, falls, reward, timing, learner rate, ETA; on stderr and to the operator."""

    def __init__(self, enabled, config, progress, learner, timing, operator=None, bot=None, every_s: float = 0.5):
        self.enabled, self.config, self.progress = enabled, config, progress
        self.learner, self.timing, self.operator, self.bot = learner, timing, operator, bot
        self.every_s = every_s if sys.stderr.isatty() else 10.0
        self.last = self.last_published = 0.0
        self.start = time.perf_counter()
        self.start_step = progress.step
        self.since = (self.start, learner.updates)  # the learner's rate is shown over the last interval
        self.updates_per_s = 0.0

    def numbers(self, now: float) -> dict:
        """The live numbers as plain values (None where there is none yet)."""
        if now - self.since[0] >= 1.0:
            self.updates_per_s = (self.learner.updates - self.since[1]) / (now - self.since[0])
            self.since = (now, self.learner.updates)
        p = self.progress
        recent = p.trace[max(p.step - int(self.config.hz), 0):p.step]
        periods = np.asarray(self.timing["periods"][-2000:]) * 1000
        rate = (p.step - self.start_step) / max(now - self.start, 1e-9)
        mean = lambda name: float(np.mean(column(recent, name))) if len(recent) else None  # noqa: E731
        percentile = lambda q: float(np.percentile(periods, q)) if len(periods) else None  # noqa: E731
        return {"step": p.step, "steps": self.config.steps, "falls": p.falls, "episodes": p.episodes,
                "gaps": p.gaps, "estimated_vx": mean("estimated_vx"), "true_vx": _finite(mean("true_vx")),
                "reward": mean("reward"), "period_p50_ms": percentile(50), "period_p99_ms": percentile(99),
                "late": self.timing["late"], "updates_per_s": self.updates_per_s,
                "eta_s": (self.config.steps - p.step) / rate if rate > 0 else None}  # resets included: they recur

    def show(self):
        now = time.perf_counter()
        if self.operator is not None and now - self.last_published >= PUBLISH_EVERY_S:
            self.last_published = now
            self.operator.publish(dict(self.numbers(now), **self._robot()))
        if not self.enabled or now - self.last < self.every_s:
            return
        self.last = now
        n = self.numbers(now)
        show = lambda value, form: "–" if value is None else format(value, form)  # noqa: E731
        eta = n["eta_s"] or 0.0
        line = (f"step {n['step']}/{n['steps']} | v est {show(n['estimated_vx'], '+.2f')} "
                f"true {show(n['true_vx'], '+.2f')} m/s | falls {n['falls']} | reward {show(n['reward'], '.2f')} | "
                f"period p50 {show(n['period_p50_ms'], '.1f')} p99 {show(n['period_p99_ms'], '.1f')} ms, "
                f"late {n['late']} | {n['updates_per_s']:.0f} upd/s | ETA {int(eta // 60)}:{int(eta % 60):02d}")
        if sys.stderr.isatty():
            print("\r\033[K" + line, end="", file=sys.stderr, flush=True)
        else:
            print(line, file=sys.stderr, flush=True)

    def _robot(self) -> dict:
        """What the console shows of the robot itself: its link, whether it is damped, its true velocity."""
        bot = self.bot
        link = getattr(bot, "address", None) or "in-process"
        robot = getattr(bot, "robot", None)
        if isinstance(robot, dict):
            damped = robot.get("mode") == "damped"
        else:
            gains = getattr(bot, "gains", None)
            damped = gains is not None and gains[0] == 0.0
        truth = bot.truth() if bot is not None else None
        velocity = truth["linear_velocity"] if truth is not None else (None, None, None)
        return {"link": link, "damped": bool(damped), "robot_vx": _finite(velocity[0]),
                "robot_vy": _finite(velocity[1])}

    def note(self, text):
        if self.enabled:
            print(("\r\033[K" if sys.stderr.isatty() else "") + text, file=sys.stderr, flush=True)

    def close(self):
        if self.enabled and sys.stderr.isatty():
            print(file=sys.stderr)


def _finite(value):
    return float(value) if value is not None and np.isfinite(value) else None
