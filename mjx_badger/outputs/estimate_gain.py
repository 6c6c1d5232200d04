"""The estimate-gain study drawn (scoring/estimate_gain.py): each real-world finding against the gain of the
simulated robot's estimate, the office speeds beside Table 5.3's, and the band of gains that agrees with the thesis."""

from pathlib import Path

from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.outputs.style import plt, save
from mjx_badger.records.analysis import display_color, display_name

APPROACHES = ("jt-oef", "jt-lpf", "cpg-d", "cpg-vf")
"""Table 5.3's CrossQ rows, whose office speeds panel (b) draws."""


def placed(rows: list[dict]) -> list[dict]:
    """The study's rows that have a measured gain, by slope."""
    return sorted((row for row in rows if row["gain"] is not None), key=lambda row: row["gain"]["slope"])


def held(row: dict) -> int:
    return sum(bool(f["holds"]) for f in row["findings"].values())


def band(rows: list[dict], measure: str = "slope") -> tuple[float, float] | None:
    """(lowest, highest) `measure` (slope or walk_ratio) of the values at which the most findings hold, None where
    none holds anywhere."""
    rows = placed(rows)
    best = max((held(row) for row in rows), default=0)
    gains = [row["gain"][measure] for row in rows if held(row) == best and row["gain"].get(measure) is not None]
    if best == 0 or not gains:
        return None
    return min(gains), max(gains)


def band_line(rows: list[dict]) -> str:
    """The band that agrees with the thesis, in the training slope and in the walk's own ratio, in words."""
    slopes, walks = band(rows), band(rows, "walk_ratio")
    if slopes is None:
        return "no value makes any finding hold: no band"
    walk = "none walks" if walks is None else f"{walks[0]:.2f}-{walks[1]:.2f}"
    return f"most findings hold at slope {slopes[0]:.2f}-{slopes[1]:.2f}, walk ratio {walk}"


def walk_label(row: dict) -> str:
    """'walk 0.04': a value's walk ratio as its line and the figure name it."""
    ratio = row["gain"].get("walk_ratio")
    return "walk: none" if ratio is None else f"walk {ratio:.2f}"


def figure(rows: list[dict], out: Path, label: str) -> Path:
    """(a) every finding, holds or fails, at each value's gain; (b) the office evaluation speeds against Table 5.3."""
    rows = placed(rows)
    fig, (findings_ax, speed_ax) = plt.subplots(1, 2, figsize=(15, 4.6), constrained_layout=True)
    ids = list(rows[0]["findings"]) if rows else []
    for row in rows:
        slope = row["gain"]["slope"]
        for y, claim in enumerate(ids):
            holds = row["findings"][claim]["holds"]
            marker, color = ("o", "tab:green") if holds else ("x", "tab:red") if holds is False else ("?", "tab:gray")
            findings_ax.scatter(slope, y, marker=marker if marker != "?" else "$?$", color=color, s=70)
        # The slope overstates what a walking policy is rewarded for (scoring/estimate_gain.walk_ratio): both shown.
        findings_ax.annotate(f"trust {row['value']:g}\n{walk_label(row)}", (slope, len(ids) - 0.45), fontsize=7,
                             ha="center")
    findings_ax.set_yticks(range(len(ids)), ids)
    findings_ax.set_ylim(-0.6, len(ids) + 0.2)
    findings_ax.set_title("(a) each real-world finding: o holds, x fails", fontsize=9)
    thesis = EXPERIMENTS["real-office"].thesis_numbers
    for approach in APPROACHES:
        points = [(row["gain"]["slope"], row["runs"].get("real-office", {}).get(approach, {}).get("velocity"))
                  for row in rows]
        points = [(x, y) for x, y in points if y is not None]
        if points:
            speed_ax.plot(*zip(*points), "o-", color=display_color(approach), label=display_name(approach))
        speed_ax.axhline(thesis[approach]["velocity"], color=display_color(approach), ls="--", lw=1)
    speed_ax.set_title("(b) office evaluation speed (true), Table 5.3's dashed", fontsize=9)
    speed_ax.set_ylabel("m/s")
    speed_ax.legend(fontsize=8)
    agreeing = band(rows)
    for ax in (findings_ax, speed_ax):
        ax.set_xlabel("gain: slope of the estimate against the true forward velocity")
        ax.grid(alpha=0.3)
        if agreeing is not None:
            low, high = agreeing
            ax.axvspan(low - 0.01, high + 0.01, color="tab:green", alpha=0.12, lw=0,
                       label="most findings hold" if ax is speed_ax else None)
    fig.suptitle(f"The estimate's weight (kalman.contact_trust): {label}", fontsize=10)
    return save(fig, out)
