"""The catalogue of the shipped suite and its certification (``python -m gear_rattle.validation.golden.generate``
and ``orbit_generate``):

* :mod:`.specs` -- the shipped impact cases as specs, in order, with the settings found by rule (grazes,
  the chaotic horizon, the states at a sticking threshold or before a release);
* :mod:`.contacts` -- the contacts that are hard to find (grazes, near misses) and what a fixed-step finder
  sees of them;
* :mod:`.build` -- each case certified in ball arithmetic, its rows given their tolerances, and the agreement
  of two of our tracks recorded in its provenance;
* :mod:`.orbits` -- the shipped periodic orbits and bifurcation points, found in float64 and proven;
* :mod:`.orbit_records` -- a proven orbit as a JSON record, its tolerances and its re-verification.

Above the formats (:mod:`..formats`) and the tolerance rules (:mod:`..rules`); the scoring, the oracle and
the fuzzer do not import it.
"""
