"""Count the Hypothesis examples a property test really checks (issue 11).

An example a property cannot judge (a sticking step has no Jacobian, hit-or-miss near a tangency
is ill-conditioned for every track) must not pass silently: ``return`` inside ``@given`` counts it
as a pass.  Such examples are rejected with ``hypothesis.assume`` instead, so Hypothesis draws
another one, and a :class:`Tally` counts the checked and the excluded examples (per reason, also
reported as Hypothesis events, see ``--hypothesis-show-statistics``).  The test runs its property
and then asserts that enough examples were checked, so a strategy that mostly lands in the excluded
region fails instead of thinning the test.
"""

from __future__ import annotations

from collections import Counter

from hypothesis import assume, event


class Tally:
    """Checked / excluded example counts of one property run."""

    def __init__(self) -> None:
        self.counts: Counter[str] = Counter()

    def exclude_if(self, condition: bool, reason: str) -> None:
        """Reject the current example (``assume``) when ``condition`` holds, and count it."""
        if condition:
            self.counts[reason] += 1
            event(f"excluded: {reason}")
        assume(not condition)

    def checked(self) -> None:
        """Count the current example as checked (call after its last assertion)."""
        self.counts["checked"] += 1

    @property
    def n_checked(self) -> int:
        return self.counts["checked"]

    @property
    def n_seen(self) -> int:
        return sum(self.counts.values())

    def assert_enough(self, min_checked: int, min_fraction: float) -> None:
        """At least ``min_checked`` examples checked, and at least ``min_fraction`` of all examples."""
        assert self.n_checked >= min_checked, dict(self.counts)
        assert self.n_checked >= min_fraction * self.n_seen, dict(self.counts)
