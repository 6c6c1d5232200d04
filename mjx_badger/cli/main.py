"""Command line: `python -m mjx_badger {train,sweep,reproduce,figures,claims,publish,attribute,realtime,robot-server,
link-keys,evaluate,render,export,estimator,list}`.

tyro builds every option from the command classes (one module per group of commands) and the run specs
they hold (TrainConfig, RealtimeConfig), so each option is declared once, its docstring its help.
Every argument is checked before anything is compiled; bad input gets one line naming what
is wrong (and the valid choices) and exit code 2. A command's class parses and checks; the work is
one call into the layer that owns it.
"""

import contextlib
import dataclasses
import io
import re
import sys

import tyro

from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.cli.common import DESCRIPTION
from mjx_badger.cli.estimator import Estimator
from mjx_badger.cli.experiments import Attribute, Claims, EstimateGain, Figures, Publish, Reproduce
from mjx_badger.cli.robot import LinkKeys, Realtime, RobotServer
from mjx_badger.cli.saved_runs import Evaluate, Export, Render
from mjx_badger.cli.training import Sweep, Train
from mjx_badger.control.actions import APPROACHES
from mjx_badger.core import faults
from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES
from mjx_badger.learning.spec import AGENT_FIELDS
from mjx_badger.protocol.protocols import FIELDS, PROTOCOLS
from mjx_badger.realtime.adapters import ADAPTERS
from mjx_badger.robot.description import ROBOTS
from mjx_badger.scoring.attribution import SWAPS_BY_NAME
from mjx_badger.tasks.locomotion import TASKS, task_params


@dataclasses.dataclass(frozen=True)
class List:
    """List approaches, algorithms, tasks, experiments, profiles, protocols, robots, robot adapters and everyone's
    parameters."""

    def check(self) -> None:
        pass

    def __call__(self) -> int:
        for title, names in (("approaches", APPROACHES), ("algorithms", ALGORITHMS), ("tasks", TASKS),
                             ("experiments", EXPERIMENTS), ("profiles", PROFILES), ("protocols", PROTOCOLS),
                             ("protocol fields", FIELDS), ("robots", ROBOTS), ("robot adapters", ADAPTERS),
                             ("attribution swaps", [f"'{name}'" for name in SWAPS_BY_NAME])):
            print(f"{title}: {', '.join(names)}")
        print("approach parameters: " + "; ".join(f"{name}: {', '.join(a.params)}"
                                                  for name, a in APPROACHES.items() if a.params))
        print("task parameters: " + "; ".join(f"{name}: {', '.join(task_params(name))}"
                                              for name in TASKS if task_params(name)))
        print(f"algorithm parameters: {', '.join(AGENT_FIELDS)}")
        return 0


COMMANDS = {"train": Train, "sweep": Sweep, "reproduce": Reproduce, "figures": Figures, "claims": Claims,
            "publish": Publish, "attribute": Attribute, "estimate-gain": EstimateGain, "realtime": Realtime, "robot-server": RobotServer,
            "link-keys": LinkKeys, "evaluate": Evaluate, "render": Render, "export": Export,
            "estimator": Estimator, "list": List}


def one_line(box: str) -> str:
    """tyro's framed error message as one line: the message rows, without frame, title, help text or footer."""
    rows = [re.sub(r"^[\s│─]+|[\s│─]+$", "", line) for line in box.splitlines() if not line.startswith(("╭", "╰"))]
    sections, current = [], []
    for row in rows + [""]:
        if row:
            current.append(row)
        elif current:  # a rule between sections, its frame stripped away
            sections.append(" ".join(current))
            current = []
    kept = [s for s in sections if not s.startswith(("Argument helptext", "For full helptext", "usage:"))]
    return "; ".join(kept[:2]) or "bad arguments"


def parse(argv=None):
    """The command `argv` asks for, built and checked; SystemExit(2) with one line on stderr if it cannot be."""
    argv = sys.argv[1:] if argv is None else list(argv)
    errors = io.StringIO()
    try:
        with contextlib.redirect_stderr(errors):
            command = tyro.extras.subcommand_cli_from_dict(COMMANDS, args=argv, prog="python -m mjx_badger",
                                                           description=DESCRIPTION)
        command.check()
    except SystemExit as done:
        if done.code:
            print(f"error: {one_line(errors.getvalue())} (see --help)", file=sys.stderr)
        else:
            sys.stderr.write(errors.getvalue())
        raise
    except ValueError as error:  # a spec or a check refused the input
        print(f"error: {error}", file=sys.stderr)
        raise SystemExit(2) from None
    return command


def main(argv=None) -> int:
    command = parse(argv)
    enable_compilation_cache()
    return run_safely(command)


def run_safely(command) -> int:
    """Run a checked command; a refusal, a stop by signal or a failed write ends it in one line, not a traceback."""
    return faults.run(command)
