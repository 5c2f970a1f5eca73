"""A mutant of tests/golden_mutants.py as an implementation under the suite's protocol, for
``gear-rattle fuzz`` (tests/test_fuzz.py): ``python tests/mutant_impl.py NAME CASES_DIR OUT_DIR`` runs
every case folder of CASES_DIR (settings.json) with the mutant NAME (a key of test_golden_mutants.MUTANTS
or VARIANTS, ``base``, ``fixed-step-H`` for the fixed-step finder of step H, or a planted error of a size:
``restitution-EPS`` (``r (1 + EPS)`` in every bounce), ``digits-D`` (every value written with D significant
digits), ``gap-scale-K`` (every contact displaced by K times the modelled per-contact error, random signs),
``two-pi-EPS`` (``2 pi (1 + EPS)``), ``forcing-EPS`` (``alpha (1 + EPS)`` in the flights), ``contact-tolerance-T``
(a turning point within T of a wall taken for a contact)) and writes
OUT_DIR/<case-id>.csv.  ``NAME+crash-alpha-2``: the mutant NAME that also panics (a line on stderr, exit
status 101) at the first case with ``alpha > 2``, in sorted order (tests/test_fuzz_triage.py)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from golden_mutants import BASE, Mutant, run, write_csv


def mutant(name: str) -> Mutant:
    """The mutant called ``name``."""
    if name == "base":
        return BASE
    if name.startswith("fixed-step-"):
        return Mutant(name, "skipped-graze", step=float(name[len("fixed-step-") :]))
    sized = {
        "restitution-": lambda x: Mutant(name, restitution=float(x)),
        "digits-": lambda x: Mutant(name, digits=int(x)),
        "gap-scale-": lambda x: Mutant(name, gap_error="random", gap_scale=float(x)),
        "two-pi-": lambda x: Mutant(name, two_pi=float(x)),
        "forcing-": lambda x: Mutant(name, forcing=float(x)),
        "contact-tolerance-": lambda x: Mutant(name, "contact-tolerance", contact_tol=float(x)),
    }
    for prefix, make in sized.items():
        if name.startswith(prefix):
            return make(name[len(prefix) :])
    from test_golden_mutants import MUTANTS, VARIANTS

    return MUTANTS[name][0] if name in MUTANTS else VARIANTS[name]


def main(argv: list[str]) -> int:
    name, cases, out = argv
    name, crash = name.split("+")[0], name.endswith("+crash-alpha-2")
    m = mutant(name)
    Path(out).mkdir(parents=True, exist_ok=True)
    for folder in sorted(p for p in Path(cases).iterdir() if (p / "settings.json").is_file()):
        settings = json.loads((folder / "settings.json").read_text())
        if crash and settings["params"]["alpha"] > 2:
            sys.stderr.write(f"panic: alpha {settings['params']['alpha']} > 2 not supported\n")
            return 101
        write_csv(run(settings, m), Path(out) / f"{settings['id']}.csv", m)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
