"""The tolerance rules of the golden cases (docs/golden_tolerances.md, "Tolerances from the conditioning" and "Asking
the oracle"), shared by the shipped catalogue (:mod:`..catalog`) and the oracle (:mod:`..oracle`):

* :mod:`.conditioning` -- the error a correct float64 implementation can make at each row (the gap-error
  model, the graze rule);
* :mod:`.tolerances` -- each row's tolerance from that error and the row's printed radius;
* :mod:`.decisions` -- the sticking-decision rule: a case stops where a sticking decision is in doubt;
* :mod:`.near_miss` -- the near-miss rule: a case stops before a flight that turns back too close to a wall;
* :mod:`.thresholds` -- the states at a sticking threshold or just before a release, found by rule.

Above :mod:`..formats` alone.
"""
