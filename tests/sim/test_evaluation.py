"""The deterministic evaluation: an omni run records eight evaluations and its curriculum, and is drawn."""

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.learning import runner
from mjx_badger.learning.config import TrainConfig
from mjx_badger.outputs import plots
from mjx_badger.sim import evaluation
from mjx_badger.tasks.locomotion import Task
from tests.documents import evaluation_schema


def test_omni_run_records_eight_evaluations_and_the_curriculum_and_draws_every_omni_figure(tmp_path):
    config = TrainConfig(approach="cpg-d", algo="crossq", task="omni-pdec", total_steps=200, chunk_steps=100,
                         warmup_steps=100, eval_steps=10)
    path = tmp_path / "results" / "omni-pdec" / "cpg-d_crossq_omni-pdec.json"
    document = runner.run(config, [0, 1], path, progress=False)
    assert document["wall_clock"]["compile_s"] > 0  # a configuration of its own: compiled here
    metrics = document["metrics"]
    for direction in ("forward", "backward", "left", "right"):
        for level in ("full", "half"):
            for name in ("desired_velocity", "lateral_velocity", "yaw_rate", "desired_mae", "lateral_mae", "yaw_mae"):
                values = np.array(metrics[f"eval/{direction}_{level}/{name}"], dtype=float)
                assert values.shape == (2, 2) and np.isfinite(values).all()
    assert np.array(metrics["curriculum/learned_bins"]).shape == (2, 2)
    runs, names = evaluation_schema(metrics)
    assert len(runs) == 8 and names == set(evaluation.RUN_METRICS)  # the forward task's metric names, eight runs
    assert np.array(metrics["train/desired_velocity"]).shape == (2, 2)
    assert document["gait"]["command"] == [0.5, 0.0, 0.0]

    # The same file stands in for a random-command run, only to exercise the comparison figure.
    random_path = tmp_path / "results" / "omni-random" / "cpg-d_crossq_omni-random.json"
    random_path.parent.mkdir()
    random_path.write_text(path.read_text())
    written = {p.name: p for p in plots.draw(tmp_path / "results", tmp_path / "figures", "smoke")}
    for name in ("omni-pdec_smoke.png", "omni-pdec_smoke.md", "omni-pdec_directions_smoke.png",
                 "omni-pdec_gait_smoke.png", "omni-random_smoke.png", "omni-random_directions_smoke.png",
                 "omni-pdec_vs_omni-random_smoke.png", "overview_smoke.png"):
        assert name in written, name
    assert "| CPG-D | 2 x 200 |" in written["omni-pdec_smoke.md"].read_text()




class _State(NamedTuple):
    obs: jnp.ndarray
    reward: jnp.ndarray
    metrics: dict
    info: dict


class _Episodes:
    """An env whose episodes last 3 steps and whose metric is the command's forward speed; at the time limit it
    restarts under whatever its task's `command` draws, as env.py's auto-reset does."""

    def __init__(self, task):
        self.task = task

    def _state(self, command, t):
        metrics = {"desired_velocity": command[0], "command_lateral_velocity": 0.0, "yaw_rate": 0.0}
        return _State(command, jnp.float32(0.0), metrics, {"terminated": jnp.bool_(False), "t": t})

    def reset(self, key, command):
        return self._state(command, 0)

    def step(self, state, action):
        t = state.info["t"] + 1
        _, drawn = self.task.command((), None)
        return self._state(jnp.where(t % 3 == 0, drawn, state.obs), t)


def test_a_run_longer_than_an_episode_restarts_under_its_own_command_not_one_the_task_draws():
    backward = lambda state, key: (state, jnp.array([-0.5, 0.0, 0.0]))  # noqa: E731  what omni-random might draw
    task = Task(name="omni", command=backward, reward=None, weights={},
                eval_commands={"forward": (0.5, 0.0, 0.0), "left": (0.0, 0.5, 0.0)})
    evaluate, _ = evaluation.make_evaluation(_Episodes(task), lambda policy, obs: obs, eval_steps=10, gait_seconds=0.1)
    metrics = evaluate(None, jax.random.PRNGKey(0))
    # Ten steps span four episodes; every one is scored under the run's command: 0.5 forward throughout.
    assert float(metrics["eval/forward/desired_velocity"]) == 0.5
    assert float(metrics["eval/left/desired_velocity"]) == 0.0
