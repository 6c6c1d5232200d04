"""The operator's terminal: a live line of the run's progress on stderr, and one-off notes."""

import sys
import time

import numpy as np

from mjx_badger.realtime.report import column


def say(enabled: bool, text: str) -> None:
    if enabled:
        print(text, file=sys.stderr, flush=True)


class View:
    """The live terminal line: steps, velocities, falls, reward, timing, learner rate, ETA."""

    def __init__(self, enabled, config, progress, learner, timing, every_s: float = 0.5):
        self.enabled, self.config, self.progress = enabled, config, progress
        self.learner, self.timing = learner, timing
        self.every_s = every_s if sys.stderr.isatty() else 10.0
        self.last = 0.0
        self.start = time.perf_counter()
        self.start_step = progress.step
        self.since = (self.start, learner.updates)  # the learner's rate is shown over the last interval

    def show(self):
        now = time.perf_counter()
        if not self.enabled or now - self.last < self.every_s:
            return
        self.last = now
        updates_per_s = (self.learner.updates - self.since[1]) / max(now - self.since[0], 1e-9)
        self.since = (now, self.learner.updates)
        p = self.progress
        recent = p.trace[max(p.step - int(self.config.hz), 0):p.step]
        periods = np.asarray(self.timing["periods"][-2000:]) * 1000
        rate = (p.step - self.start_step) / max(now - self.start, 1e-9)
        eta = (self.config.steps - p.step) / max(rate, 1e-9)  # resets included: they will recur
        line = (f"step {p.step}/{self.config.steps} | v est {column(recent, 'estimated_vx').mean():+.2f} "
                f"true {column(recent, 'true_vx').mean():+.2f} m/s | falls {p.falls} | "
                f"reward {column(recent, 'reward').mean():.2f} | period p50 {np.percentile(periods, 50):.1f} "
                f"p99 {np.percentile(periods, 99):.1f} ms, late {self.timing['late']}"
                f" | {updates_per_s:.0f} upd/s | ETA {int(eta // 60)}:{int(eta % 60):02d}")
        if sys.stderr.isatty():
            print("\r\033[K" + line, end="", file=sys.stderr, flush=True)
        else:
            print(line, file=sys.stderr, flush=True)

    def note(self, text):
        if self.enabled:
            print(("\r\033[K" if sys.stderr.isatty() else "") + text, file=sys.stderr, flush=True)

    def close(self):
        if self.enabled and sys.stderr.isatty():
            print(file=sys.stderr)
