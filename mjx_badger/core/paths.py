"""Where a clone keeps what the package reads from beside itself."""

from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[2]
"""The clone this package lives in (its `figures/data` holds the committed results)."""

REFERENCE = REPOSITORY / "figures" / "data"
"""The committed results (figures/data), found from any working folder."""
