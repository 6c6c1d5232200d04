"""The thesis's findings about how the policies move, as claims: the gaits of Figs 5.4 and 5.7 named from the feet's
phases (sim/gait.py), the velocity dips of Fig 5.5, and DroQ's yaw and torque penalties (§5.1.1)."""

import numpy as np

from mjx_badger.records import analysis
from mjx_badger.scoring.verdicts import Claim, Results

ASYMMETRIC = ("gallop", "bound", "pronk")
"""Gaits whose pairs land together or nearly so: what the thesis's "gallop" covers when read from phases."""
MARGIN_SHARE = 0.05
"""Fig 5.5's "consistent safety margin": below the target for at most this share of the second."""


def _gaits(experiment: str, expected: dict):
    """Measure: each approach's most common gait over seeds against the thesis's (`expected`: approach -> names)."""
    def measure(r: Results):
        s = {a: r.summary(experiment, a) for a in expected}
        words = ", ".join(f"{analysis.display_name(a)} " + ("no gait record" if s[a]["gait"] is None else
                          " ".join(f"{name} {n}" for name, n in s[a]["gait_counts"].items()))
                          for a in expected)
        if any(s[a]["gait"] is None for a in expected):
            return words, None
        return words + " (of the seeds)", all(s[a]["gait"] in expected[a] for a in expected)

    return measure


def _dips(r: Results, approaches: tuple) -> dict | None:
    """approach -> (share of the last second below 0.5 m/s, deepest dip), seeds' means, forward experiment; None
    where a run has no gait record."""
    documents = {a: r.document("forward", a) for a in approaches}
    if not all(d.get("gait") for d in documents.values()):
        return None
    return {a: tuple(float(np.mean(v)) for v in analysis.below_target(d, 0.5)) for a, d in documents.items()}


def _margin(r: Results):
    dips = _dips(r, ("jt-lpf", "cpg-vf"))
    if dips is None:
        return "no gait record", None
    words = ", ".join(f"{analysis.display_name(a)} {share:.0%} of the second below" for a, (share, _) in dips.items())
    return words, all(share <= MARGIN_SHARE for share, _ in dips.values())


def _cpg_dips(r: Results):
    dips = _dips(r, ("cpg-d", "cpg-vf", "cpg-rt"))
    if dips is None:
        return "no gait record", None
    words = ", ".join(f"{analysis.display_name(a)} dips {deep:.2f} m/s, {share:.0%} below" for a, (share, deep)
                      in dips.items())
    deepest = all(dips["cpg-d"][1] > dips[a][1] for a in ("cpg-vf", "cpg-rt"))
    longest = all(dips["cpg-rt"][0] > dips[a][0] for a in ("cpg-d", "cpg-vf"))
    return words, deepest and longest


ALGOS = ("sac", "sac-utd20", "droq", "crossq")
PENALTIES = ("reward/yaw", "reward/energy")


def _penalty_until(document: dict, metric: str, minutes: float) -> float:
    """Mean per-step penalty (magnitude) over the chunks within `minutes` of simulated time, seeds' mean."""
    last = max(int(np.searchsorted(np.asarray(document["sim_minutes"]), minutes + 1e-9)), 1)
    return float(np.nanmean(np.abs(analysis.series(document, metric)[:last])))


def _droq_penalties(r: Results):
    documents = {a: r.document("algo-comparison", a) for a in ALGOS}
    if not all(m in d["metrics"] for d in documents.values() for m in PENALTIES):
        return "no reward terms recorded", None
    minutes = min(d["sim_minutes"][-1] for d in documents.values())  # the same simulated time for all four
    paid = {m: {a: _penalty_until(d, m, minutes) for a, d in documents.items()} for m in PENALTIES}
    words = "; ".join(f"{m.split('/')[1]} " + ", ".join(f"{analysis.display_name(a)} {v:.3f}" for a, v in p.items())
                      for m, p in paid.items()) + f" per step, first {minutes:.1f} simulated min"
    return words, all(p["droq"] < min(v for a, v in p.items() if a != "droq") for p in paid.values())


CLAIMS = (
    Claim("forward-trot", "After forward training JT-LPF, JT-OEF and the CPGs trot", "Fig 5.4, §5.1.2",
          "LPF trot, OEF trot, CPG-D/VF/RT the CPG's trot", "the seeds' most common gait is a trot for all five",
          _gaits("forward", {a: ("trot",) for a in ("jt-lpf", "jt-oef", "cpg-d", "cpg-vf", "cpg-rt")})),
    Claim("max-gallop", "At maximal velocity JT-OEF and JT-LPF gallop, JT-NF and the CPGs trot", "Fig 5.7, §5.1.3",
          "NF trot ~4 Hz, OEF and LPF gallop, CPGs trot",
          "most common gait: asymmetric (gallop, bound or pronk) for OEF and LPF, a trot for NF and the CPGs",
          _gaits("forward-max", {"jt-nf": ("trot",), "jt-oef": ASYMMETRIC, "jt-lpf": ASYMMETRIC,
                                 "cpg-d": ("trot",), "cpg-vf": ("trot",), "cpg-rt": ("trot",)})),
    Claim("target-margin", "JT-LPF and CPG-VF keep a margin above the target", "Fig 5.5, §5.1.2",
          "no significant drops below 0.5 m/s", f"below 0.5 m/s for at most {MARGIN_SHARE:.0%} of the last second "
          "after training (seeds' mean), both", _margin),
    Claim("cpg-dips", "CPG-D dips deepest, CPG-RT stays below the target longest", "Fig 5.5, §5.1.2",
          "CPG-D pronounced dips, CPG-RT longer below", "of the CPGs: CPG-D's deepest dip the largest, CPG-RT's "
          "share of the second below 0.5 m/s the largest", _cpg_dips),
    Claim("droq-penalties", "DroQ pays the least yaw and torque penalty", "Fig 5.2, §5.1.1",
          "DroQ better on yaw and torque penalties", "DroQ's mean per-step yaw and energy penalties below every "
          "other algorithm's over the same simulated time", _droq_penalties),
)
