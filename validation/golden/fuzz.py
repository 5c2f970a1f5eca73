"""A differential fuzzer: another implementation against certified cases on demand (``gear-rattle fuzz``;
docs/golden.md, "Fuzzing an implementation").

The protocol: the implementation is a command ``COMMAND CASES_DIR OUT_DIR`` that runs every case folder of
CASES_DIR (``settings.json`` in the suite's layout; no ``expected.csv``) and writes
``OUT_DIR/<case-id>.csv`` -- as it runs the shipped suite.  The fuzzer

1. draws *recipes* with Hypothesis (:mod:`.scenarios`: :func:`~.scenarios.draw_recipes`, reproducible
   by the seed): a scenario of the registry :data:`~.scenarios.SCENARIOS` that reaches a hard place on
   purpose, and its numbers, from which :func:`~.scenarios.construct` builds an input;
2. builds each input's certified case (:func:`ondemand.build_user_case`: every tolerance rule and the
   horizon rule of ``gear-rattle case``);
3. runs the implementation on a batch of cases (one process per batch), with a timeout (:mod:`.fuzz_runner`,
   in a process group and a work folder of its own: :mod:`.fuzz_process`, :mod:`.fuzz_reaper`);
4. scores every output with the suite's scorer (:func:`suite.score_file`);
5. groups the failures by signature (:mod:`.triage`: a crash, a timeout, a missing or malformed file of
   one input is a failure of that input, isolated from its batch), shrinks each group's first member
   (:mod:`.shrink`: fewer impacts, simpler numbers, the paper's parameters) and writes it, a golden-format
   folder with what the implementation wrote, to the output directory.

This module names the parts and holds the run's defaults.
"""

from __future__ import annotations

from .scenarios import PAPER_SETS, SCENARIOS, construct, draw_recipes

#: Cases per batch (one process of the implementation each), seconds a batch may take by default.
BATCH, TIMEOUT = 24, 300.0
#: Seconds the shrinking of one failure may take (it usually stops earlier: no simpler candidate fails);
#: at most the budget.
SHRINK_TIME = 90.0

__all__ = ["BATCH", "TIMEOUT", "SHRINK_TIME", "PAPER_SETS", "SCENARIOS", "construct", "draw_recipes"]
