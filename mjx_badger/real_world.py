"""The real-world experiments' numbers (thesis Tables 5.3-5.5, 6.1, 6.2) from results files learned under
on-robot conditions: evaluation speed (true, and as the robot estimated it), yaw control in the thesis's
categories, falls, and the run's duration with its resets.

Yaw control: the thesis judged it by eye from video, in four categories of heading drift. We
measure the heading the robot turned through over its final evaluation run, |mean yaw rate| x
the run's seconds, in degrees, and put it in the same bins: very good < 10, good 10-30, medium
30-60, poor > 60. Falls are every safety stop from step 0, warm-up included, as a robot counts
them. Duration: the simulated seconds of the 20k steps plus each fall's reset time
(Conditions.reset_seconds).
"""

import math

import numpy as np

from mjx_badger.analysis import display_name, final, series
from mjx_badger.conditions import get as get_conditions

YAW_BINS = ((10.0, "very good"), (30.0, "good"), (60.0, "medium"), (math.inf, "poor"))
"""Heading drift (degrees) below which each category holds (thesis §5.2)."""


def yaw_category(degrees: float) -> str:
    return next(name for limit, name in YAW_BINS if degrees < limit)


def summary(document: dict) -> dict:
    """A real-world run's row: seeds x steps, true and estimated evaluation speed, heading drift, falls, minutes."""
    config = document["config"]
    metrics = document["metrics"]
    eval_seconds = config["eval_steps"] / config["env"]["control_hz"]
    true_speed = final(document, "eval/desired_velocity")
    estimated = (final(document, "eval/estimated_desired_velocity")
                 if "eval/estimated_desired_velocity" in metrics else np.full_like(true_speed, np.nan))
    drift = np.degrees(np.abs(final(document, "eval/yaw_rate")) * eval_seconds)
    falls = series(document, "train/falls_total")[-1]
    reset = get_conditions(config.get("conditions", "sim"), tuple(map(tuple, config.get("condition_changes", ())))
                           ).reset_seconds
    minutes = (document["sim_minutes"][-1] * 60 + falls * reset) / 60
    return {"seeds": len(document["seeds"]), "steps": document["steps"][-1], "complete": document["complete"],
            "velocity": float(np.nanmean(true_speed)), "velocity_range": (float(np.nanmin(true_speed)),
                                                                          float(np.nanmax(true_speed))),
            "estimated_velocity": float(np.nanmean(estimated)),
            "yaw_drift_deg": float(np.nanmean(drift)), "yaw": yaw_category(float(np.nanmean(drift))),
            "falls": float(np.mean(falls)), "falls_range": (float(falls.min()), float(falls.max())),
            "minutes": float(np.mean(minutes)), "eval_seconds": eval_seconds}


def _thesis_velocity(numbers: dict) -> str:
    if "velocity" not in numbers:
        return "left out"
    return "N/A (no headway)" if numbers["velocity"] is None else f"{numbers['velocity']:g}"


def table(experiment, documents: dict, x_axis: str = "steps") -> str:
    """Markdown: per approach, ours beside the thesis's (ours: mean over seeds, [min-max])."""
    lines = ["| approach | seeds x steps | eval speed m/s (thesis) | ours, true [min-max] | ours, as estimated "
             "| yaw control (thesis) | ours: heading drift, category | falls (thesis) | ours [min-max] "
             "| minutes on the robot (thesis) | ours, resets included |", "|---" * 11 + "|"]
    for label, document in documents.items():
        s = summary(document)
        thesis = experiment.thesis_numbers.get(label, {})
        size = f"{s['seeds']} x {s['steps']:,}{'' if s['complete'] else ' (incomplete)'}"
        low, high = s["velocity_range"]
        lines.append(
            f"| {display_name(label)} | {size} | {_thesis_velocity(thesis)} | {s['velocity']:.2f} [{low:.2f}-{high:.2f}] "
            f"| {s['estimated_velocity']:.2f} | {thesis.get('yaw') or 'N/A'} | {s['yaw_drift_deg']:.0f} deg, {s['yaw']} "
            f"| {thesis.get('falls', '-')} | {s['falls']:.0f} [{s['falls_range'][0]:.0f}-{s['falls_range'][1]:.0f}] "
            f"| {thesis.get('minutes', '-')} | {s['minutes']:.0f} |")
    return "\n".join(lines) + "\n"


TABLE_6 = {  # Tables 6.1/6.2, forward velocity (m/s): simulation (maximal) | office | outdoor (at the 0.25 target)
    "jt-nf": (2.2, None, None), "jt-oef": (1.3, 0.85, 0.25), "jt-lpf": (1.15, 0.4, 0.23),
    "cpg-d": (0.55, 0.3, 0.3), "cpg-vf": (0.75, 0.3, 0.0), "cpg-rt": (0.55, None, None),
}


def table_6(simulation: dict, office: dict, outdoor: dict) -> str:
    """Tables 6.1/6.2 completed: per approach the forward velocity in simulation (forward-max, final evaluation),
    in the office and outdoors (true evaluation speed), ours beside the thesis's ('-': left out on the robot)."""
    lines = ["| approach | simulation, max (thesis) | ours | office (thesis) | ours | outdoor (thesis) | ours |",
             "|---|---|---|---|---|---|---|"]
    cell = lambda value: "-" if value is None else f"{value:g}"
    for approach, (sim, off, out) in TABLE_6.items():
        ours_sim = (f"{np.nanmean(final(simulation[approach], 'eval/desired_velocity')):.2f}"
                    if approach in simulation else "not run")
        ours = [f"{summary(group[approach])['velocity']:.2f}" if approach in group else "not run"
                for group in (office, outdoor)]
        lines.append(f"| {display_name(approach)} | {cell(sim)} | {ours_sim} | {cell(off)} | {ours[0]} | {cell(out)} "
                     f"| {ours[1]} |")
    return "\n".join(lines) + "\n"


LOOP_FOLDER = ("realtime", "outdoor")
"""Where, beside a results folder's profiles, `realtime --conditions outdoor` runs are looked for: results/realtime/outdoor."""


def loop_summary(document: dict) -> dict:
    """An on-robot loop run's row (realtime results file): falls, final evaluation's true and estimated speed and how
    it ended, minutes with each fall's reset at the conditions' reset time (as the vmapped rows count them), updates
    per learning step."""
    config = document["config"]
    reset = get_conditions(config["conditions"], tuple(map(tuple, config.get("condition_changes", ())))).reset_seconds
    evaluation = document.get("evaluation") or {}
    nan = float("nan")
    true = evaluation.get("true_velocity")
    return {"steps": document["steps"], "complete": document["complete"], "falls": float(document["falls"]),
            "velocity": nan if true is None else float(true), "estimated_velocity": evaluation.get("estimated_velocity", nan),
            "minutes": document["train_minutes"] + document["falls"] * reset / 60,
            "updates_per_step": document["updates_per_learning_step"], "protocol": config["protocol"],
            "evaluation": _evaluation_words(evaluation)}


def _evaluation_words(evaluation: dict) -> str:
    """How the loop's one evaluation ended: a speed read over a tumble is not a walk's."""
    if "seconds" not in evaluation:
        return "-"
    return f"fell after {evaluation['seconds']:.2f} s" if evaluation.get("fell") else f"{evaluation['seconds']:.0f} s"


def loop_table(loop: dict, vmapped: dict) -> str:
    """Markdown: per approach, the on-robot loop's single run beside the vmapped runs of the same conditions."""
    lines = ["| approach | loop: steps, protocol | falls | evaluation | true speed m/s | as estimated | minutes "
             "| updates per step | vmapped: seeds x steps, protocol | falls [min-max] | true speed | as estimated "
             "| minutes |", "|---" * 13 + "|"]
    for label, document in loop.items():
        one = loop_summary(document)
        head = (f"| {display_name(label)} | {one['steps']:,}{'' if one['complete'] else ' (incomplete)'}, "
                f"{one['protocol']} | {one['falls']:.0f} | {one['evaluation']} | {one['velocity']:.2f} | {one['estimated_velocity']:.2f} "
                f"| {one['minutes']:.0f} | {one['updates_per_step']:.2f} ")
        if label not in vmapped:
            lines.append(head + "| not run | | | | |")
            continue
        s = summary(vmapped[label])
        lines.append(head + f"| {s['seeds']} x {s['steps']:,}, {vmapped[label]['config']['protocol']} "
                     f"| {s['falls']:.0f} [{s['falls_range'][0]:.0f}-{s['falls_range'][1]:.0f}] | {s['velocity']:.2f} "
                     f"| {s['estimated_velocity']:.2f} | {s['minutes']:.0f} |")
    return "\n".join(lines) + "\n"


def figure(experiment, documents: dict, out, label: str):
    """Training curves of the true and the estimated forward velocity (as the robot saw it), and falls."""
    from mjx_badger import plots

    plt = plots.plt
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.3), constrained_layout=True)
    for name, document in documents.items():
        steps = np.asarray(document["steps"])
        color = plots.display_color(name.split()[0])
        style = "-" if "sac" not in name else ":"
        true = np.nanmean(series(document, "train/forward_velocity"), axis=1)
        axes[0].plot(steps, true, style, color=color, label=display_name(name))
        if "train/estimated_forward_velocity" in document["metrics"]:
            estimated = np.nanmean(series(document, "train/estimated_forward_velocity"), axis=1)
            axes[1].plot(steps, estimated, style, color=color, label=display_name(name))
        axes[2].plot(steps, np.mean(series(document, "train/falls_total"), axis=1), style, color=color,
                     label=display_name(name))
    for ax, title in zip(axes, ("true forward velocity (training)", "as the robot estimated it (reward, observation)",
                                "falls (safety stops), mean over seeds")):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("steps")
        ax.grid(alpha=0.3)
    for ax in axes[:2]:
        ax.axhline(experiment.target_velocity, color="k", ls="--", lw=1)
        ax.set_ylabel("m/s")
    axes[2].axhline(100, color="tab:red", ls=":", lw=1, label="100 falls")
    axes[0].legend(fontsize=7)
    axes[2].legend(fontsize=7)
    fig.suptitle(f"{experiment.name} ({experiment.thesis_figure}), {experiment.conditions} conditions; {label}",
                 fontsize=11)
    return plots._save(fig, out)


def _office_outdoor(r, experiment: str, names) -> dict:
    return {name: summary(r.document(experiment, name)) for name in names}


def _excluded_fall(r):
    rows = {(where, a): summary(r.document(f"real-{where}", a)) for where in ("office", "outdoor")
            for a in ("jt-nf", "cpg-rt")}
    words = "; ".join(f"{where}: JT-NF {rows[(where, 'jt-nf')]['falls']:.0f}, CPG-RT {rows[(where, 'cpg-rt')]['falls']:.0f}"
                      for where in ("office", "outdoor")) + " falls in 20k steps"
    return words, all(rows[("office", a)]["falls"] > 100 for a in ("jt-nf", "cpg-rt"))


def _office_speeds(r):
    s = _office_outdoor(r, "real-office", ("jt-oef", "jt-lpf", "cpg-d", "cpg-vf"))
    words = ", ".join(f"{display_name(a)} {v['velocity']:.2f}" for a, v in s.items()) + " m/s (true, evaluation)"
    fastest = max(s, key=lambda a: s[a]["velocity"])
    return words, fastest == "jt-oef" and all(0.15 <= s[a]["velocity"] <= 0.45 for a in ("cpg-d", "cpg-vf"))


def _outdoor_jt_slow(r):
    office = _office_outdoor(r, "real-office", ("jt-oef", "jt-lpf"))
    outdoor = _office_outdoor(r, "real-outdoor", ("jt-oef", "jt-lpf"))
    words = ", ".join(f"{display_name(a)} {office[a]['velocity']:.2f} -> {outdoor[a]['velocity']:.2f}"
                      for a in office) + " m/s (office -> outdoor)"
    return words, all(outdoor[a]["velocity"] < office[a]["velocity"] and 0.1 <= outdoor[a]["velocity"] <= 0.4
                      for a in office)


def _outdoor_cpg(r):
    s = _office_outdoor(r, "real-outdoor", ("jt-oef", "jt-lpf", "cpg-d", "cpg-vf"))
    vf, d = s["cpg-vf"], s["cpg-d"]
    words = (f"CPG-VF {vf['velocity']:.2f} m/s, {vf['falls']:.0f} falls, yaw {vf['yaw']}; "
             f"CPG-D {d['velocity']:.2f} m/s, {d['falls']:.0f} falls, yaw {d['yaw']}")
    most_falls = max(s, key=lambda a: s[a]["falls"]) == "cpg-vf"
    return words, (vf["velocity"] < 0.1 and most_falls and vf["yaw"] == "poor" and d["velocity"] >= 0.2
                   and d["yaw"] in ("very good", "good"))


def _faster_than_believed(r):
    s = summary(r.document("real-office", "jt-oef"))
    words = f"office JT-OEF walks {s['velocity']:.2f} m/s and estimates {s['estimated_velocity']:.2f} m/s"
    # It must walk too: a policy that stands still and believes it stands stiller proves nothing.
    return words, s["velocity"] >= 0.2 and s["velocity"] > 1.5 * max(s["estimated_velocity"], 0.0)


def real_claims() -> tuple:
    """The real-world findings (§5.2) as claims, scored like the simulation ones (claims.py)."""
    from mjx_badger.claims import Claim

    return (
        Claim("real-excluded-fall", "JT-NF and CPG-RT exceed 100 falls in 20k steps on the robot", "§5.2",
              "over 100 falls (why they were left out)", "mean falls > 100 in the office for both (outdoor beside)",
              _excluded_fall),
        Claim("real-office-speeds", "In the office JT-OEF is fastest and the CPGs walk ~0.3 m/s", "Table 5.3",
              "JT-OEF 0.85, JT-LPF 0.4, CPG-D 0.3, CPG-VF 0.3 m/s",
              "JT-OEF fastest of the four; CPG-D and CPG-VF within 0.15-0.45 m/s", _office_speeds),
        Claim("real-outdoor-jt", "Outdoors the JT approaches slow to ~0.25 (OEF) and ~0.23 (LPF)", "Table 5.4",
              "OEF 0.85 -> 0.25, LPF 0.4 -> 0.23 m/s", "both slower outdoors than in the office, within 0.1-0.4 m/s",
              _outdoor_jt_slow),
        Claim("real-outdoor-cpg", "Outdoors CPG-VF fails while CPG-D keeps ~0.3 m/s with very good yaw", "Table 5.4",
              "CPG-VF N/A, 81 falls, poor yaw; CPG-D 0.33, 39 falls, very good yaw",
              "CPG-VF < 0.1 m/s, most falls, poor yaw; CPG-D >= 0.2 m/s with good or very good yaw", _outdoor_cpg),
        Claim("real-faster-than-believed", "Trained on the estimate, a policy walks faster than it believes",
              "§5.2.1", "office JT-OEF: 1.5 m/s when tested in simulation",
              "office JT-OEF walks (>= 0.2 m/s, true) at more than 1.5x its own estimate", _faster_than_believed),
    )
