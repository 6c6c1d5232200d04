"""The real-world experiments drawn and tabled: Tables 5.3-5.5 and 6.1/6.2 beside ours, the on-robot loop beside the
vmapped runs, and the figure of true against estimated velocity (numbers from records/real_world.py)."""

import numpy as np

from mjx_badger.outputs.style import plt, save
from mjx_badger.protocol.conditions import get as get_conditions
from mjx_badger.realtime import milestones
from mjx_badger.records.analysis import display_color, display_name, final, series
from mjx_badger.records.real_world import loop_summary, summary


def _thesis_velocity(numbers: dict) -> str:
    if "velocity" not in numbers:
        return "left out"
    return "N/A (no headway)" if numbers["velocity"] is None else f"{numbers['velocity']:g}"


def _number(value) -> str:
    return "-" if value is None or value != value else f"{value:.0f}"


def _stops(s: dict) -> str:
    """'before a fall / premature' safety stops, '-' for files from before they were counted."""
    return "-" if s["stops_before_fall"] is None else f"{s['stops_before_fall']:.0f} / {s['premature_stops']:.0f}"


def table(experiment, documents: dict, x_axis: str = "steps") -> str:
    """Markdown: per approach, ours beside the thesis's (ours: mean over seeds, [min-max])."""
    lines = ["| approach | seeds x steps | eval speed m/s (thesis) | ours, true [min-max] | ours, as estimated "
             "| yaw control (thesis) | ours: heading drift, category | falls (thesis) | ours [min-max] "
             "| ours by 10k steps | of ours: no fall yet / noise alone | minutes on the robot (thesis) "
             "| ours, resets included |", "|---" * 13 + "|"]
    for label, document in documents.items():
        s = summary(document)
        thesis = experiment.thesis_numbers.get(label, {})
        size = f"{s['seeds']} x {s['steps']:,}{'' if s['complete'] else ' (incomplete)'}"
        low, high = s["velocity_range"]
        lines.append(
            f"| {display_name(label)} | {size} | {_thesis_velocity(thesis)} | {s['velocity']:.2f} [{low:.2f}-{high:.2f}] "
            f"| {s['estimated_velocity']:.2f} | {thesis.get('yaw') or 'N/A'} | {s['yaw_drift_deg']:.0f} deg, {s['yaw']} "
            f"| {thesis.get('falls', '-')} | {s['falls']:.0f} [{s['falls_range'][0]:.0f}-{s['falls_range'][1]:.0f}] "
            f"| {_number(s['falls_10k'])} | {_stops(s)} | {thesis.get('minutes', '-')} | {s['minutes']:.0f} |")
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
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.3), constrained_layout=True)
    for name, document in documents.items():
        steps = np.asarray(document["steps"])
        color = display_color(name.split()[0])
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
    return save(fig, out)


def _minutes(ours, thesis) -> str:
    """'train / with resets (thesis)' for one milestone."""
    mine = "not reached" if ours is None else f"{ours[0]:.1f} / {ours[1]:.1f}"
    return f"{mine} ({'-' if thesis is None else f'{thesis:g}'})"


def milestones_table(loops: dict) -> str:
    """Markdown: per conditions and approach, the on-robot run's milestones beside the thesis's (§5.2)."""
    lines = ["| conditions | approach | steps | falls | first steps: min (thesis) | bigger steps | peak | peak m/s "
             "(30 s) | evaluation: true m/s, best 1 s | thesis: policy in simulation m/s |", "|---" * 10 + "|"]
    for conditions, runs in loops.items():
        for approach, (document, trace) in runs.items():
            ours = milestones.milestones(trace, get_conditions(conditions).reset_seconds)
            thesis = milestones.THESIS.get(conditions, {}).get(approach, {})
            evaluation = document.get("evaluation") or {}
            true, best = evaluation.get("true_velocity"), evaluation.get("true_peak_1s")
            words = ("-" if true is None else f"fell after {evaluation['seconds']:.2f} s" if evaluation.get("fell")
                     else f"{true:.2f}, {'-' if best is None else f'{best:.2f}'}")  # a tumble's speed is no walk's
            lines.append(f"| {conditions} | {display_name(approach)} | {document['steps']:,} | {document['falls']} "
                         + "".join(f"| {_minutes(ours[key], thesis.get(key))} " for key in ("first", "bigger", "peak"))
                         + f"| {ours['peak_velocity']:.2f} | {words} | {thesis.get('sim') or '-'} |")
    return "\n".join(lines) + "\n"


def milestones_figure(loops: dict, out):
    """Per conditions, each run's 30 s mean true velocity over session minutes, its milestones and the thesis's."""
    fig, axes = plt.subplots(1, len(loops), figsize=(7 * len(loops), 4.3), constrained_layout=True, squeeze=False)
    for ax, (conditions, runs) in zip(axes[0], loops.items()):
        reset = get_conditions(conditions).reset_seconds
        for approach, (_, trace) in runs.items():
            color = display_color(approach)
            seconds, speed = milestones.windowed_speed(trace)
            ax.plot(milestones.with_resets(trace, seconds, reset), speed, color=color, label=display_name(approach))
            ours = milestones.milestones(trace, reset)
            for key, marker in (("first", "o"), ("bigger", "s"), ("peak", "*")):
                if ours[key] is not None:
                    ax.plot(ours[key][1], np.interp(ours[key][0] * 60, seconds, speed), marker, color=color, ms=7)
                thesis = milestones.THESIS.get(conditions, {}).get(approach, {}).get(key)
                if thesis is not None:
                    ax.plot(thesis, -0.04, marker, color=color, ms=7, mfc="none")
        for level in (milestones.FIRST_STEPS, milestones.BIGGER_STEPS):
            ax.axhline(level, color="k", ls=":", lw=0.8)
        ax.set_title(f"{conditions}: filled ours, hollow (at the bottom) the thesis's; o first steps, "
                     "square bigger, * peak", fontsize=9)
        ax.set_xlabel("minutes into the session (resets included)")
        ax.set_ylabel("true forward velocity, 30 s mean [m/s]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return save(fig, out)
