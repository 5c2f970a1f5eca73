"""The oracle: a golden case certified for any input (``gear-rattle case``; docs/reference/golden_commands.md, "Asking the
oracle"):

* :mod:`.inputs` -- what is asked: one input, each field checked once, and the inputs of a ``--from`` file;
* :mod:`.ondemand` -- the case built: the certified orbit, the tolerance rules (:mod:`..rules`) and the
  horizon rule, written in the suite's formats (:mod:`..formats`).

The fuzzer (:mod:`..fuzzing`) asks it for the certified case of each input it draws.
"""
