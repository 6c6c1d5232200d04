"""Videos of the experiments: a GIF of each experiment's best seed walking on native MuJoCo (sim/render.py draws)."""

from pathlib import Path

from mjx_badger.experiments.registry import EXPERIMENTS, load_experiment
from mjx_badger.learning import saved_run
from mjx_badger.learning.config import from_results
from mjx_badger.outputs import drawn
from mjx_badger.records import analysis, policy, results
from mjx_badger.robot import mjcf
from mjx_badger.sim import native
from mjx_badger.sim.render import check_gl, record


def best(folder: Path) -> tuple[Path, int, float] | None:
    """(results file, seed, final evaluation return) of the best seed among an experiment's runs with saved policies."""
    found = None
    for path in sorted(Path(folder).glob("*.json")):
        document = results.read_or_skip(path, leave_out_diverged=True)
        if document is None or not document.get("complete") or not document["seeds"] or "policy" not in document or not (path.parent / document["policy"]).exists():
            continue
        seed, value = analysis.best_seed(document)
        if found is None or value > found[2]:
            found = (path, seed, value)
    return found


def draw(results_dir: Path, figures_dir: Path, profile: str, names, protocol: str, seconds: float = 4.0,
         kept: list | None = None) -> list[Path]:
    """A GIF of the best seed of each experiment (highest final evaluation return), where rendering works here.

    A GIF drawn before from more complete runs than there are now is kept (noted in `kept`; drawn.py).
    """
    try:
        check_gl(mjcf.load_model())
    except RuntimeError as error:
        print(f"no videos: {error}")
        return []
    written = []
    for name in names:
        out = Path(figures_dir) / protocol / f"{name}_{profile}.gif"
        history = drawn.Drawn(out.parent, profile)
        done, needed = drawn.complete_runs(EXPERIMENTS[name],
                                           load_experiment(EXPERIMENTS[name], Path(results_dir) / name))
        if history.keeps([out], done, needed, f"{done} of {needed} runs complete under {Path(results_dir) / name}",
                        kept):
            continue
        chosen = best(Path(results_dir) / name)
        if chosen is None:
            continue
        path, seed, _ = chosen
        document = results.read(path)
        try:
            env = native.evaluation_env(from_results(document), seconds)
            actor = policy.load(path.parent / document["policy"], seed)
        except ValueError as error:
            print(f"no video of {name}: {error}")
            continue
        record(env, actor, list(next(iter(env.task.eval_commands.values()))), seconds, out, size=(320, 240))
        history.note([out], done)
        written.append(out)
    return written


def render_saved(path: Path, seed: int | None, seconds: float, command: str | None, conditions: str | None,
                 out: Path) -> dict:
    """A GIF at `out` of a run's saved policy (learning/saved_run.py) walking on native MuJoCo; `record`'s report."""
    env, actor, chosen = saved_run.load(path, seed, seconds, command, conditions)
    return record(env, actor, chosen, seconds, out)
