"""Fig 4.2: the learning rate x batch size grid of JT-OEF CrossQ (forward, thesis-code) at quick, run as one sweep
per batch size (the batch is an array shape, so it cannot vary inside one program) and drawn as the thesis drew it.

    python -m tools.lr_batch_grid [--run] [--results-dir results/grid] [--figures-dir figures/grid]

--run trains what is missing first (24 members x 3 seeds x 20k steps; about 6 h on a 2-core CPU; each sweep
resumes from its checkpoint). Without it, draws from what has landed.
"""

import argparse
import subprocess
import sys
from pathlib import Path

from mjx_badger.core import safe_io
from mjx_badger.outputs import grid
from mjx_badger.protocol.protocols import THESIS_CODE

SEEDS, STEPS = 3, 20_000
"""The quick profile's budget."""


def sweep_command(batch: int, out: Path) -> list[str]:
    """The `sweep` of one batch size over Fig 4.2's learning rates."""
    rates = ",".join(f"{lr:g}" for lr in grid.LEARNING_RATES)
    return [sys.executable, "-m", "mjx_badger", "sweep", "--seeds", str(SEEDS), "--steps", str(STEPS), "--quiet",
            "--no-tensorboard", "--vary", f"algo_params.learning_rate={rates}", "--algo-param", f"batch_size={batch}",
            "--out", str(out / f"batch-{batch}")]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", action="store_true", help="train the missing members first")
    parser.add_argument("--results-dir", type=Path, default=Path("results/grid"))
    parser.add_argument("--figures-dir", type=Path, default=Path("figures/grid"))
    args = parser.parse_args(argv)
    if args.run:
        for batch in grid.BATCH_SIZES:
            subprocess.run(sweep_command(batch, args.results_dir), check=True)
    numbers = {cell: grid.cell_numbers(document) for cell, document in grid.load_cells(args.results_dir).items()}
    if not numbers:
        print(f"error: no finished sweep members under {args.results_dir}: run with --run first", file=sys.stderr)
        sys.exit(2)
    crossq = THESIS_CODE.agent_config("crossq")
    default = (crossq.learning_rate, crossq.batch_size)
    label = (f"JT-OEF CrossQ forward, thesis-code, {SEEDS} seeds x {STEPS:,} steps ({len(numbers)} of "
             f"{len(grid.LEARNING_RATES) * len(grid.BATCH_SIZES)} cells); the thesis's: 50k steps")
    written = [grid.figure(numbers, default, args.figures_dir / "fig_4_2_quick.png", label)]
    safe_io.write_text(args.figures_dir / "fig_4_2_quick.md", f"{label}. Final evaluation velocity and falls, "
                       f"seeds' mean; the protocol's own setting: lr {default[0]:g}, batch {default[1]}.\n\n"
                       + grid.table(numbers))
    written.append(args.figures_dir / "fig_4_2_quick.md")
    print("\n".join(f"wrote {path}" for path in written))


if __name__ == "__main__":
    main()
