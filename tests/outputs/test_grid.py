"""Fig 4.2's grid read from sweep members' files, its table and the cells it marks."""

from mjx_badger.outputs import grid
from mjx_badger.records import results
from tests.documents import simulation_document


def _member(lr, batch, velocity, falls, complete=True):
    document = simulation_document(velocity, falls)
    document["metrics"]["eval/desired_velocity"] = document["metrics"]["train/forward_velocity"]
    document["config"]["agent"] = {"learning_rate": lr, "batch_size": batch}
    document["complete"] = complete
    return document


def test_the_grid_reads_each_member_and_marks_best_worst_and_the_protocols_cell(tmp_path):
    for lr, batch, velocity in ((1e-3, 32, 0.2), (5e-3, 128, 0.6), (5e-2, 256, 0.01)):
        results.write(tmp_path / f"batch-{batch}" / f"m_lr={lr:g}.json", _member(lr, batch, velocity, 4.0))
    results.write(tmp_path / "batch-64" / "unfinished.json", _member(1e-4, 64, 0.9, 0.0, complete=False))
    numbers = {cell: grid.cell_numbers(d) for cell, d in grid.load_cells(tmp_path).items()}
    assert set(numbers) == {(1e-3, 32), (5e-3, 128), (5e-2, 256)}  # the unfinished member is left out
    assert grid.marked(numbers, (5e-3, 128)) == {"best": (5e-3, 128), "worst": (5e-2, 256),
                                                 "the protocol's": (5e-3, 128)}
    table = grid.table(numbers)
    assert "| 128 | not run | not run | not run | 0.60 m/s, 4 falls | not run | not run |" in table
    assert "| 64 | not run |" in table
    assert grid.figure(numbers, (5e-3, 128), tmp_path / "fig.png", "test").exists()
