"""The golden conformance suite: certified cases and orbit records for any implementation of the model, and
the code that certifies, reads, scores and fuzzes with them (docs/golden.md; validation/golden/README.md),
as its parts:

* :mod:`.catalog` -- the shipped cases and orbit records and their certification;
* :mod:`.rules` -- the tolerance rules (the error of a correct float64 implementation, row by row);
* :mod:`.formats` -- the suite's files, read and written;
* :mod:`.scoring` -- ``gear-rattle check``'s scoring, with typed results up to every report;
* :mod:`.oracle` -- ``gear-rattle case``: a certified case for any input;
* :mod:`.fuzzing` -- ``gear-rattle fuzz``: scenarios, runner, shrinker, triage;
* :mod:`.self_check` (our tracks under test), :mod:`.boundary` (what is checked where input comes in),
  :mod:`.paths` (where the installed suite is), and the generators :mod:`.generate`, :mod:`.orbit_generate`.

The layers between them are a contract of ``pyproject.toml`` (``lint-imports``; docs/architecture.md).
Importing this package imports none of its modules.
"""
