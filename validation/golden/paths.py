"""Where the suite installed with this package lives (no imports: ``check --help`` names these)."""

from pathlib import Path

#: The committed impact-sequence cases (``validation/golden/cases`` of the installed package).
DEFAULT_SUITE = Path(__file__).resolve().parent / "cases"
#: The committed periodic-orbit and bifurcation-point records.
DEFAULT_ORBITS = Path(__file__).resolve().parent / "orbits"
