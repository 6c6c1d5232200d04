"""The claims about how the policies move: gaits named from the record, Fig 5.5's dips, DroQ's penalties."""

import numpy as np

from mjx_badger.scoring import behaviour_claims, claims
from tests.documents import simulation_document, write_run


def _with_gait(document, velocity, contacts, dt=0.005):
    """`document` with a 1 s gait record of 2 seeds: forward velocity `velocity` per physics step, `contacts`."""
    return dict(document, gait={"physics_dt": dt, "seconds": 1.0, "contacts": [contacts.tolist()] * 2,
                                "forward_velocity": [list(velocity)] * 2})


def test_behaviour_claims_name_gaits_and_measure_dips_from_the_gait_record(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    t = np.arange(200) * 0.005
    trot = np.stack([((t * 2.0 + o) % 1.0) >= 0.5 for o in (0.0, 0.5, 0.5, 0.0)], axis=1).astype(int)
    steady = np.full(200, 0.6)
    dipping = 0.6 - 0.3 * (np.sin(2 * np.pi * 2 * t) > 0.9)  # 0.3 m/s under 0.6 for a seventh of each cycle
    longer = 0.6 - 0.15 * (np.sin(2 * np.pi * 2 * t) > 0.0)  # 0.15 under for half the time
    for name, velocity in (("jt-lpf", steady), ("jt-oef", steady), ("cpg-vf", steady), ("cpg-d", dipping),
                           ("cpg-rt", longer)):
        write_run(folder, "forward", name, _with_gait(simulation_document(0.55, 0.0), velocity, trot))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}
    assert board["forward-trot"].holds is True and "JT-LPF trot 2" in board["forward-trot"].ours
    assert behaviour_claims.MARGIN_SHARE == 0.05 and board["target-margin"].holds is True and "CPG-VF 0% of the second below" in board["target-margin"].ours
    # CPG-D dips 0.2 below 0.5 m/s; CPG-RT sits at 0.45 for half the second: deepest and longest as the thesis says
    assert board["cpg-dips"].holds is True and "CPG-D dips 0.20 m/s" in board["cpg-dips"].ours
    assert "CPG-RT dips 0.05 m/s, 50% below" in board["cpg-dips"].ours


def test_droq_penalties_are_compared_over_the_same_simulated_time(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    for name, yaw, energy, chunks in (("sac", 0.03, 0.12, 20), ("sac-utd20", 0.03, 0.11, 5), ("droq", 0.02, 0.08, 5),
                                      ("crossq", 0.025, 0.10, 20)):
        document = simulation_document(0.55, 1.0, chunks=chunks)
        # CrossQ's penalties fall to 0.001 after DroQ's run ends (2 min): the comparison must not see them
        late = [[0.001] * 2] * (chunks - 5)
        document["metrics"].update({"reward/yaw": [[-yaw] * 2] * min(chunks, 5) + late,
                                    "reward/energy": [[-energy] * 2] * min(chunks, 5) + late})
        write_run(folder, "algo-comparison", name, document)
    verdict = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code")}["droq-penalties"]
    assert verdict.holds is True and "yaw SAC 0.030, SAC-UTD20 0.030, DroQ 0.020, CrossQ 0.025" in verdict.ours
