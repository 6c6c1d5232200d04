"""Sweeps: a grid of members of one shape, each member with its own values; bad grids refused before compiling."""

import subprocess
import sys

import numpy as np
import pytest

from mjx_badger.learning import sweep
from tests.conftest import TINY_TRAIN


def test_a_grid_whose_members_differ_in_shape_is_refused_naming_the_field():
    with pytest.raises(ValueError, match=r"members differ in shape: algo_params.ensemble_size changes .*agent_state"):
        sweep.Sweep(TINY_TRAIN, (("algo_params.ensemble_size", (2, 3)),), [0])
    with pytest.raises(ValueError, match="cannot sweep algo_params.updates_per_step: the program needs it as a Python "
                                         "number"):
        sweep.Sweep(TINY_TRAIN, (("algo_params.updates_per_step", (1, 2)),), [0])
    for bad, message in ((("robot", (1, 2)), "cannot sweep 'robot'"),
                         (("algo_params.learning_rate", ("fast",)), "must be numbers"),
                         (("task_params.speed", (1.0,)), "task 'forward' takes")):
        with pytest.raises(ValueError, match=message):
            sweep.members(TINY_TRAIN, (bad,))
    assert sweep.parse_axis("task_params.target_velocity=0.3, 0.5") == ("task_params.target_velocity", (0.3, 0.5))
    with pytest.raises(ValueError, match="must be numbers"):
        sweep.parse_axis("task_params.target_velocity=0.3,fast")


def test_the_sweep_command_refuses_a_bad_grid_before_compiling(tmp_path):
    grid = tmp_path / "grid.json"
    grid.write_text('{"algo_params.ensemble_size": [2, 3]}')
    command = [sys.executable, "-m", "mjx_badger", "sweep", "--grid", str(grid), "--out", str(tmp_path / "out"),
               "--quiet"]
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 2 and "members differ in shape: algo_params.ensemble_size" in done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "out").exists()  # nothing written, not even the folder


@pytest.mark.slow  # minutes of compile: `make test-slow`
def test_members_vmapped_together_each_get_their_own_values():
    """With all members in one vmapped group, each member's environment runs at its own swept target velocity."""
    targets = (0.25, 0.5, 0.75)
    program = sweep.Sweep(TINY_TRAIN, (("task_params.target_velocity", targets),), [0, 1], vmapped=3)
    carry, chunk, _ = program.compiled()
    (values, state), metrics = chunk(carry, 0)
    np.testing.assert_array_equal(np.asarray(values)[:, 0], np.float32(targets))
    commanded = np.asarray(state.env_state.obs)[:, :, 48]  # [member][seed]: the observed target velocity
    np.testing.assert_allclose(commanded, np.repeat(np.float32(targets)[:, None], 2, axis=1))
    assert np.asarray(metrics["train/falls"]).shape == (3, 2)


def test_a_grid_splits_into_groups_of_vmapped_members_for_separate_processes_or_jobs():
    assert sweep.parts(6, 2) == [(0, 1), (2, 3), (4, 5)]
    assert sweep.parts(3, 1) == [(0,), (1,), (2,)]
    with pytest.raises(ValueError, match="4 members do not split into groups of 3"):
        sweep.parts(4, 3)
