"""The real-world tables and claims (real_world.py) follow from the numbers in the results files."""


import numpy as np

from mjx_badger.scoring import claims, real_world
from tests.documents import real_world_document, write_run


def test_the_real_world_claims_follow_the_numbers(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    for label, velocity, falls in (("jt-oef", 0.85, 10), ("jt-lpf", 0.4, 12), ("cpg-d", 0.3, 0), ("cpg-vf", 0.3, 0),
                                   ("jt-nf", 0.5, 150), ("cpg-rt", 0.2, 120)):
        write_run(folder, "real-office", label, real_world_document(velocity, falls))
    for label, velocity, falls, yaw in (("jt-oef", 0.25, 20, 20), ("jt-lpf", 0.23, 25, 20), ("cpg-d", 0.3, 39, 5),
                                        ("cpg-vf", 0.02, 81, 90), ("jt-nf", 0.2, 130, 40), ("cpg-rt", 0.1, 40, 40)):
        write_run(folder, "real-outdoor", label, real_world_document(velocity, falls, yaw_rate=np.radians(yaw) / 10.0,
                                                        conditions="outdoor"))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.CLAIMS)}
    assert all(v.holds is True for v in board.values()), {k: v.ours for k, v in board.items()}
    assert "office: JT-NF 150, CPG-RT 120" in board["real-excluded-fall"].ours
    assert "CPG-VF 0.02 m/s, 81 falls, yaw poor" in board["real-outdoor-cpg"].ours

    # CPG-RT below 100 falls in the office: the reason for leaving it out does not hold.
    write_run(folder, "real-office", "cpg-rt", real_world_document(0.2, 60))
    # A policy that believes its speed: no faster than 1.5 x its estimate.
    write_run(folder, "real-office", "jt-oef", real_world_document(0.85, 10, estimated=0.8))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.CLAIMS)}
    assert board["real-excluded-fall"].holds is False and board["real-faster-than-believed"].holds is False
    # Standing still and believing it stands stiller is no finding.
    write_run(folder, "real-office", "jt-oef", real_world_document(0.04, 10, estimated=0.006))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.CLAIMS)}
    assert board["real-faster-than-believed"].holds is False


