"""The real-world findings of the thesis (§5.2, Tables 5.3-5.5) as claims over the runs under on-robot conditions."""

from mjx_badger.records.analysis import display_name
from mjx_badger.records.real_world import summary
from mjx_badger.scoring.verdicts import Claim


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


CLAIMS = (
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
"""The real-world findings (§5.2) as claims, scored like the simulation ones (claims.py)."""
