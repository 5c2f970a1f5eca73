"""``gear-rattle check``'s scoring, with typed results up to every report (docs/reference/golden_commands.md, "What a
failing case reports" and "In CI"):

* :mod:`.cases` -- an impact sequence scored against ``expected.csv``, row by row against its tolerances;
  :mod:`.differences` -- where it first and worst differs (expected against got);
* :mod:`.orbits` -- an implementation's values scored against an orbit record;
* :mod:`.results` -- the typed results: one per case or record, the verdicts, the counts, the run;
* :mod:`.run` -- a run: selection, known failures, outputs read, items scored;
* :mod:`.text_report` and :mod:`.junit` -- the table and details on stdout, the JUnit XML file (the JSON
  document is :meth:`.results.CheckRun.as_dict`).

Above :mod:`..formats` alone (numpy and the standard library: ``check`` scores anywhere); it imports neither
the catalogue nor the fuzzer.
"""
