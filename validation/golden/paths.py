"""Where the suite installed with this package lives (no imports: ``check --help`` names these)."""

from pathlib import Path

#: The installed suite's folder (``validation/golden`` of the installed package: ``cases/`` and ``orbits/``).
GOLDEN = Path(__file__).resolve().parent
#: The committed impact-sequence cases.
DEFAULT_SUITE = GOLDEN / "cases"
#: The committed periodic-orbit and bifurcation-point records.
DEFAULT_ORBITS = GOLDEN / "orbits"

__all__ = ["GOLDEN", "DEFAULT_SUITE", "DEFAULT_ORBITS"]
