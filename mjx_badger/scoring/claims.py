"""The thesis's simulation findings as claims (verdicts.py), and `score`, which checks them: fifteen about
learning here, five about how the policies move in behaviour_claims.py.

Each claim's measure reads the results of one protocol at one profile and gives our numbers in
words and whether the finding holds; the scoreboards that show them are scoreboard.py's.
"""

from pathlib import Path

import numpy as np

from mjx_badger.records import analysis
from mjx_badger.scoring import behaviour_claims
from mjx_badger.scoring.verdicts import Claim, Results, Verdict

JT = ("jt-nf", "jt-oef", "jt-lpf")
CPG = ("cpg-d", "cpg-vf", "cpg-rt")


def _steps(s: dict) -> str:
    return "never" if s["steps_to_target"] is None else f"{s['steps_to_target'] / 1000:.0f}k"


def _reached(s: dict, limit: float = np.inf) -> bool:
    return s["steps_to_target"] is not None and s["steps_to_target"] <= limit


ALGOS = ("sac", "sac-utd20", "droq", "crossq")


def _first_to_target(r: Results):
    s = {a: r.summary("algo-comparison", a) for a in ALGOS}
    minutes = {a: s[a]["minutes_to_target"] for a in ALGOS}
    words = ", ".join(f"{analysis.display_name(a)} " + (f"not in {s[a]['minutes']:.1f}" if m is None else f"{m:.1f}")
                      for a, m in minutes.items()) + " simulated min"
    ours = minutes["crossq"]
    if ours is None:
        return words, False
    others = [a for a in ALGOS if a != "crossq"]
    if any(minutes[a] is not None and minutes[a] <= ours for a in others):
        return words, False
    # A run that stopped short of CrossQ's time without reaching the target might still have beaten it.
    undecided = [analysis.display_name(a) for a in others if minutes[a] is None and s[a]["minutes"] < ours]
    if undecided:
        return words + f" ({', '.join(undecided)} stopped before {ours:.1f} min)", None
    return words, True


def _falls_at(document: dict, minutes: float) -> float:
    """Cumulative falls, mean over seeds, at the last chunk within `minutes` of simulated time."""
    index = int(np.searchsorted(np.asarray(document["sim_minutes"]), minutes + 1e-9)) - 1
    return float(np.mean(analysis.series(document, "train/falls")[max(index, 0)]))


def _crossq_falls(r: Results):
    crossq, droq = (r.document("algo-comparison", a) for a in ("crossq", "droq"))
    minutes = min(crossq["sim_minutes"][-1], droq["sim_minutes"][-1])  # the UTD runs are shorter
    ours, theirs = _falls_at(crossq, minutes), _falls_at(droq, minutes)
    return f"CrossQ {ours:.1f}, DroQ {theirs:.1f} in the first {minutes:.1f} simulated min", ours < theirs


def _jt_convergence(r: Results):
    s = {a: r.summary("forward", a) for a in JT}
    words = ", ".join(f"{analysis.display_name(a)} {_steps(s[a])}" for a in ("jt-nf", "jt-oef", "jt-lpf"))
    fast = _reached(s["jt-nf"], 10_000) and _reached(s["jt-oef"], 10_000)
    lpf = _reached(s["jt-lpf"]) and s["jt-lpf"]["steps_to_target"] >= max(
        s["jt-nf"]["steps_to_target"] or 0, s["jt-oef"]["steps_to_target"] or 0)
    return words, fast and lpf


def _jt_falls(r: Results):
    thesis = {"jt-nf": 13, "jt-oef": 7, "jt-lpf": 7}
    falls = {a: r.summary("forward", a)["falls_mean"] for a in JT}
    words = ", ".join(f"{analysis.display_name(a)} {falls[a]:.1f}" for a in JT)
    ordered = falls["jt-nf"] > falls["jt-oef"] and falls["jt-nf"] > falls["jt-lpf"]
    magnitude = all(thesis[a] / 3 <= falls[a] <= thesis[a] * 3 for a in JT)
    return words, ordered and magnitude


def _cpg_never_falls(r: Results):
    falls = {a: r.summary("forward", a)["falls_mean"] for a in CPG}
    would = {a: r.would_falls("forward", a) for a in CPG}
    words = ", ".join(f"{analysis.display_name(a)} {falls[a]:.1f}" for a in CPG)
    if any(np.isfinite(v) for v in would.values()):
        words += " (JT rule would have fired: " + ", ".join(f"{would[a]:.1f}" for a in CPG) + ")"
    return words, all(f == 0 for f in falls.values())


def _cpg_vf_fastest(r: Results):
    s = {a: r.summary("forward", a) for a in CPG}
    words = ", ".join(f"{analysis.display_name(a)} {_steps(s[a])}" for a in CPG)
    vf = s["cpg-vf"]["steps_to_target"]
    others = [s[a]["steps_to_target"] for a in ("cpg-d", "cpg-rt")]
    return words, vf is not None and all(o is None or vf <= o for o in others)


def _gait(experiment: str, names: tuple):
    def measure(r: Results):
        hz = {a: r.summary(experiment, a)["gait_hz"] for a in names}
        words = ", ".join(f"{analysis.display_name(a)} {'-' if hz[a] is None else f'{hz[a]:.1f} Hz'}" for a in names)
        values = [hz[a] for a in names]
        return words, all(v is not None for v in values) and all(a > b for a, b in zip(values, values[1:]))

    return measure


def _best_and_mean(r: Results, approaches: tuple) -> tuple:
    """({approach: best seed's final evaluation speed}, {approach: the seeds' mean}, words) on forward-max: the thesis
    gives JT-NF's best (2.2) beside its average (1.90) and the CPGs' averages (§5.1.3), so both are scored."""
    best = {a: r.summary("forward-max", a)["final_eval_velocity_max"] for a in approaches}
    mean = {a: r.summary("forward-max", a)["final_eval_velocity"] for a in approaches}
    words = ", ".join(f"{analysis.display_name(a)} {best[a]:.2f} / {mean[a]:.2f}" for a in approaches)
    return best, mean, words + " (best seed / mean)"


def _max_velocity(r: Results):
    best, mean, words = _best_and_mean(r, JT)
    return words, all(v["jt-nf"] > v["jt-oef"] > v["jt-lpf"] for v in (best, mean))


def _cpg_vf_max(r: Results):
    best, mean, words = _best_and_mean(r, CPG)
    jt_best, jt_mean, _ = _best_and_mean(r, JT)
    words += f"; slowest JT {min(jt_best.values()):.2f} / {min(jt_mean.values()):.2f}"
    return words, all(v["cpg-vf"] >= max(v[a] for a in CPG) and v["cpg-vf"] < min(jt[a] for a in JT)
                      for v, jt in ((best, jt_best), (mean, jt_mean)))


def _lpf_falls_most(r: Results):
    falls = {a: r.summary("forward-max", a)["falls_mean"] for a in JT}
    return ", ".join(f"{analysis.display_name(a)} {falls[a]:.1f}" for a in JT), falls["jt-lpf"] > max(falls["jt-nf"], falls["jt-oef"])


def _along(r: Results, experiment: str, name: str) -> float:
    return float(np.mean([r.final_mean(experiment, name, f"eval/{d}_full/desired_velocity")
                          for d in analysis.DIRECTIONS]))


def _jt_stands(r: Results):
    speeds = {a: _along(r, "omni-random", a) for a in JT}
    words = ", ".join(f"{analysis.display_name(a)} {speeds[a]:.2f} m/s" for a in JT) + " along the command (mean of 4 directions)"
    return words, all(s < 0.15 for s in speeds.values())


def _cpg_vf_best_omni(r: Results):
    mae = {a: r.final_mean("omni-random", a, "eval/desired_mae") for a in JT + CPG}
    yaw = r.final_mean("omni-random", "cpg-vf", "eval/yaw_mae")
    words = ", ".join(f"{analysis.display_name(a)} {mae[a]:.2f}" for a in CPG) + f" desired MAE; CPG-VF yaw MAE {yaw:.2f} rad/s"
    return words, mae["cpg-vf"] <= min(mae.values()) and yaw <= 0.2


def _curriculum_beats_random(r: Results):
    pairs = {a: (r.final_mean("omni-pdec", a, "eval/desired_mae"), r.final_mean("omni-random", a, "eval/desired_mae"))
             for a in CPG}
    words = ", ".join(f"{analysis.display_name(a)} {p:.2f} vs {q:.2f}" for a, (p, q) in pairs.items()) + " desired MAE (PDEC vs random)"
    return words, all(p < q for p, q in pairs.values())


def _curriculum_error(r: Results):
    mae = {a: r.final_mean("omni-pdec", a, "eval/desired_mae") for a in CPG}
    return ", ".join(f"{analysis.display_name(a)} {mae[a]:.2f}" for a in CPG), all(m <= 0.1 for m in mae.values())


CLAIMS = (
    Claim("crossq-first", "CrossQ reaches 0.5 m/s first", "Fig 5.2, §5.1.1", "CrossQ ~2 min, DroQ ~7 min",
          "CrossQ's simulated minutes to 90 % of 0.5 m/s below every other algorithm's; undecided while "
          "another run stops short of CrossQ's time without reaching the target",
          _first_to_target),
    Claim("crossq-falls", "CrossQ falls less than DroQ", "Fig 5.2, §5.1.1", "CrossQ ~14, DroQ ~32",
          "mean falls CrossQ < DroQ over the same simulated time (the shorter run's)", _crossq_falls),
    Claim("jt-convergence", "JT-NF and JT-OEF converge in ~5k steps, JT-LPF in ~10k", "Fig 5.3, §5.1.2",
          "NF ~5k, OEF ~5k, LPF ~10k", "NF and OEF within 10k steps; LPF gets there, no earlier than both",
          _jt_convergence),
    Claim("jt-falls", "JT forward falls 13 / 7 / 7 (NF / OEF / LPF)", "Fig 5.3, §5.1.2", "NF ~13, OEF ~7, LPF ~7",
          "NF falls most, and each within 3x of the thesis's count", _jt_falls),
    Claim("cpg-never-falls", "CPG approaches never fall", "Fig 5.3, §5.1.2", "0 for CPG-D, CPG-VF, CPG-RT",
          "0 counted falls for every CPG approach (the JT rule's would-be falls shown beside)", _cpg_never_falls),
    Claim("cpg-vf-fastest", "CPG-VF learns fastest of the CPG approaches", "Fig 5.3, §5.1.2",
          "VF ~5k, D ~10k, RT >10k", "CPG-VF reaches 90 % of 0.5 m/s no later than CPG-D and CPG-RT", _cpg_vf_fastest),
    Claim("jt-gait-order", "JT gait frequency NF > OEF > LPF", "Fig 5.4, §5.1.2", "NF ~6, OEF ~4, LPF ~2.5 Hz",
          "gait frequencies strictly in that order", _gait("forward", ("jt-nf", "jt-oef", "jt-lpf"))),
    Claim("cpg-gait-order", "CPG-VF steps faster than CPG-D", "Fig 5.4, §5.1.2", "VF ~2.5, D 2 Hz",
          "gait frequency CPG-VF > CPG-D", _gait("forward", ("cpg-vf", "cpg-d"))),
    Claim("jt-max-velocity", "Maximal velocity JT-NF > JT-OEF > JT-LPF", "Fig 5.6, Tables 6.1/6.2",
          "NF 2.2 (average 1.90), OEF 1.3, LPF 1.15 m/s",
          "final evaluation velocity strictly in that order, of the best seeds and of the seeds' means",
          _max_velocity),
    Claim("cpg-vf-max", "CPG-VF is the fastest CPG, slower than every JT", "Fig 5.6, Tables 6.1/6.2",
          "VF 0.75, D 0.55, RT 0.55 (averages); JT >= 1.15 m/s",
          "CPG-VF >= CPG-D, CPG-RT and < every JT, of the best seeds and of the seeds' means",
          _cpg_vf_max),
    Claim("lpf-falls-most", "JT-LPF falls most at maximal velocity", "Fig 5.6, §5.1.3", "LPF ~30, NF ~9, OEF ~9",
          "mean falls JT-LPF > JT-NF and JT-OEF", _lpf_falls_most),
    Claim("omni-jt-stands", "Under random directions the JT approaches stand still", "Figs 5.9-5.11, §5.1.4",
          "JT stands still", "every JT approach below 0.15 m/s along a 0.5 m/s command", _jt_stands),
    Claim("omni-cpg-vf-best", "Under random directions CPG-VF is best, yaw within +-0.2 rad/s",
          "Figs 5.9-5.11, §5.1.4", "CPG-VF best; yaw +-0.2 rad/s",
          "CPG-VF has the lowest desired-velocity MAE of all six and yaw MAE <= 0.2 rad/s", _cpg_vf_best_omni),
    Claim("pdec-beats-random", "The curriculum beats random commands for every CPG approach", "Figs 5.12-5.14, §5.1.5",
          "better for CPG-D, CPG-VF, CPG-RT", "desired-velocity MAE under PDEC below random's for all three",
          _curriculum_beats_random),
    Claim("pdec-error", "Under the curriculum the desired-velocity error stays ~0.05 m/s", "Fig 5.13, §5.1.5",
          "~0.05 m/s", "desired-velocity MAE <= 0.1 m/s for all three CPG approaches", _curriculum_error),
) + behaviour_claims.CLAIMS


CLAIMS_BY_ID = {claim.id: claim for claim in CLAIMS}


def score(profile_folder: Path, protocol: str, claims: tuple = CLAIMS) -> list[Verdict]:
    """Every claim (default: the simulation findings) checked against `profile_folder/<protocol>/`."""
    results = Results(Path(profile_folder) / protocol)
    return [claim.check(results) for claim in claims]
