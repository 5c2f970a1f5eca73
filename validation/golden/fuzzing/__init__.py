"""A differential fuzzer: another implementation against certified cases on demand (``gear-rattle fuzz``;
docs/reference/golden_commands.md, "Fuzzing an implementation").  Its parts, as Hypothesis keeps strategies, engine,
shrinker and reporting apart:

* :mod:`.scenarios` -- the strategies: a registry of scenarios, each reaching a hard place on purpose, that
  draw *recipes* with Hypothesis (reproducible by the seed) and build an input from each;
* :mod:`.runner` -- the search loop and the run's defaults: each input's certified case built by the oracle
  (:func:`..oracle.ondemand.build_user_case`: every tolerance rule and the horizon rule of ``gear-rattle
  case``), the implementation run on a batch of cases with a timeout, every output scored with the suite's
  scorer (:func:`..scoring.cases.score_sequence`);
* :mod:`.process` and :mod:`.reaper` -- the implementation as a process that ``fuzz`` owns: its process
  group, its work folder and lock, the watchdog that cleans up after a SIGKILL;
* :mod:`.shrinker` -- from a failing input to the simplest one that fails the same way (fewer impacts,
  simpler numbers, the paper's parameters);
* :mod:`.triage` -- the reporting: failures grouped by signature (a crash, a timeout, a missing or malformed
  file of one input is a failure of that input, isolated from its batch), one golden-format folder per
  group with what the implementation wrote, the JUnit report.

The protocol: the implementation is a command ``COMMAND CASES_DIR OUT_DIR`` that runs every case folder of
CASES_DIR (``settings.json`` in the suite's layout; no ``expected.csv``) and writes
``OUT_DIR/<case-id>.csv`` -- as it runs the shipped suite.  Importing this package imports none of its
modules (the reaper runs as a script of its own).
"""
