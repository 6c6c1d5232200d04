"""A saved run loaded again: checked without compiling, then its env, its seed's NumPy actor and the command."""

import json

import pytest

from mjx_badger.core.paths import REFERENCE
from mjx_badger.learning import saved_run

WALKER = REFERENCE / "quick" / "thesis-code" / "forward" / "jt-oef_crossq_forward.json"  # committed, with its policy


def test_a_committed_run_loads_with_its_best_seeds_actor_and_the_tasks_first_command():
    saved_run.check(WALKER, None, 20.0, 3600.0, None, None)
    env, actor, command = saved_run.load(WALKER, None, seconds=20.0)
    published = json.loads(WALKER.read_text())["published_policy_seeds"]
    assert actor.seed == published[0] and command == [0.5, 0.0, 0.0]
    assert env.episode_steps == int(round(21.0 / env.control_dt))  # one episode longer than the evaluation
    env, _, command = saved_run.load(WALKER, None, 5.0, command="0.3,0,0.1", conditions="office")
    assert command == [0.3, 0.0, 0.1] and env.conditions.name == "office" and env.sensing is not None


@pytest.mark.parametrize("command, says", [("0.5,0", "three numbers"), ("0.5,0,x", "three numbers"),
                                           ("11,0,0", r"--command VX must be a finite number in \[-10, 10\]")])
def test_a_command_is_three_bounded_numbers(command, says):
    with pytest.raises(ValueError, match=says):
        saved_run.parse_command(command)


def test_what_cannot_run_is_refused_before_anything_is_built(tmp_path):
    for args, says in (((WALKER, 99, 20.0, 3600.0, None, None), "seed"),
                       ((WALKER, None, 0.0, 3600.0, None, None), "--seconds"),
                       ((WALKER, None, 20.0, 3600.0, None, "moon"), "choose from sim, office, outdoor"),
                       ((tmp_path / "none.json", None, 20.0, 3600.0, None, None), "no results file")):
        with pytest.raises(ValueError, match=says):
            saved_run.check(*args)
