"""The fuzzer's shrinker (``gear-rattle fuzz``; docs/reference/golden_commands.md, "Fuzzing an implementation"): from a failing
input to the simplest one that fails **the same way** (the same :class:`.triage.Signature`: a crash with
the same exit status, a wrong wall, a value of the same column beyond its tolerance, ...).

Simpler means :func:`complexity`: fewer impacts, then fewer significant digits, then parameters closer to
one of the paper's sets.  Each round runs the candidates one change simpler (:func:`shrink_candidates`) in
one batch, then all their failing changes at once (``_merged``), and keeps the simplest input that
still fails the same way, until none does or the deadline.
"""

from __future__ import annotations

import csv
import time
from dataclasses import replace
from typing import Callable

from ....core.params import PARAM_NAMES
from ..oracle.inputs import CaseInput, case_input
from ..oracle.ondemand import CaseError, UserCase, build_user_case
from .scenarios import PAPER_SETS


def complexity(inp: CaseInput) -> tuple:
    """The order of the shrinker (smaller is simpler): impacts, then the significant digits of the numbers,
    then the parameters that differ from the nearest paper set."""
    nums = [inp.params.alpha, inp.params.beta, inp.params.gamma, inp.params.r, inp.tau0, inp.sdot0]
    nums += [] if inp.s0 is None else [inp.s0]
    digits = sum(significant_digits(x) for x in nums)
    off = min(sum(getattr(inp.params, k) != getattr(q, k) for k in PARAM_NAMES) for q in PAPER_SETS)
    return (inp.impacts, digits, off)


def significant_digits(x: float) -> int:
    """Significant digits of the shortest repr of ``x`` (0 for 0)."""
    if x == 0:
        return 0
    m = repr(abs(x)).split("e")[0].replace(".", "").strip("0")
    return len(m)


def shrink_candidates(inp: CaseInput, fail_impact: int | None) -> list[CaseInput]:
    """Simpler inputs to try (each one change): fewer impacts (down to the first failing one, halves),
    numbers with fewer significant digits, parameters of a paper set."""
    out: list[CaseInput] = []
    seen = {inp}

    def add(**ch):
        try:
            c = case_input(inp.id, **{**_fields(inp), **ch})
        except ValueError:
            return
        if c not in seen and complexity(c) < complexity(inp):
            seen.add(c)
            out.append(c)

    n, f = inp.impacts, fail_impact
    near = set() if f is None else {f - 1, f, f + 1, f + 2}
    for k in sorted({0, 1, 2, n // 8, n // 4, n // 2, (3 * n) // 4, n - 1} | near):
        if 0 <= k < n:
            add(impacts=k)
    for name in (*PARAM_NAMES, "tau0", "sdot0", "s0"):
        x = _fields(inp)[name]
        if x is None:
            continue
        for d in range(1, significant_digits(x)):
            add(**{name: float(f"{x:.{d}g}")})
        if name in ("gamma", "tau0"):
            add(**{name: 0.0})
    for q in PAPER_SETS:
        add(**q.as_dict())
        for name in PARAM_NAMES:
            add(**{name: getattr(q, name)})
    return out


def _fields(inp: CaseInput) -> dict:
    p = inp.params
    return {
        **p.as_dict(),
        "tau0": inp.tau0,
        "sdot0": inp.sdot0,
        "impacts": inp.impacts,
        "s0": inp.s0,
        "stick_time": inp.stick_time,
    }


def first_failing_impact(case: UserCase, score) -> int | None:
    """The impact index ``n`` of the expected row at the score's first difference (``score.first_row``: the
    0-based data row of the first failing value, or for a different number of events the first event whose
    kind or wall differs; blank lines of the implementation's file do not count); ``None`` where there is
    no score (a crash, a timeout, a missing or malformed file) or no row."""
    if score is None or score.passed or score.first_row < 0:
        return None
    rows = list(csv.DictReader(case.expected.splitlines()))
    return int(rows[min(score.first_row, len(rows) - 1)]["n"]) if rows else None


def _merged(inp: CaseInput, failing: list[CaseInput]) -> CaseInput | None:
    """``inp`` with every change of the failing candidates at once (per field the simplest failing value;
    the fewest impacts), or ``None`` where that is one of them or not a valid input."""
    fields = _fields(inp)
    for c in failing:
        for k, v in _fields(c).items():
            if v == _fields(inp)[k]:
                continue
            if k == "impacts":
                fields[k] = min(fields[k], v)
            elif k in PARAM_NAMES and fields[k] != _fields(inp)[k]:
                continue  # a paper set's parameters: the first one found
            elif fields[k] == _fields(inp)[k] or significant_digits(v) < significant_digits(fields[k]):
                fields[k] = v
    try:
        m = case_input(inp.id, **fields)
    except ValueError:
        return None
    return None if m in failing else m


def shrink(case: UserCase, outcome, evaluate: Callable[[list[UserCase]], dict], deadline: float) -> tuple:
    """The simplest case reachable by :func:`shrink_candidates` rounds that fails with ``outcome``'s
    signature, until no candidate does or the deadline; returns ``(case, its outcome, rounds)``.
    ``evaluate(cases)`` runs the implementation on cases and returns ``{id: outcome}`` (an outcome has
    ``signature``, None when the case passes, and ``score``).  Each round runs every candidate of the
    current input in one batch, then (one more batch) all their failing changes at once; it keeps that
    merged input where it fails the same way, else the simplest candidate that does (:func:`complexity`)."""
    target, inp, rounds = outcome.signature, case.input, 0
    fail_impact = first_failing_impact(case, outcome.score)
    while time.monotonic() < deadline:
        built = _build([replace(c, id=f"{inp.id}-s{k}") for k, c in enumerate(shrink_candidates(inp, fail_impact))])
        if not built:
            break
        outcomes = evaluate(built)
        failing = [b for b in built if outcomes[b.input.id].signature == target]
        if not failing:
            break
        best = min(failing, key=lambda b: complexity(b.input))
        got = outcomes[best.input.id]
        merged = _merged(replace(inp, id=f"{inp.id}-m"), [b.input for b in failing])
        if merged is not None and complexity(merged) < complexity(best.input) and time.monotonic() < deadline:
            mb = _build([merged])
            mo = evaluate(mb)[merged.id] if mb else None
            if mo is not None and mo.signature == target:
                best, got = mb[0], mo
        rounds += 1
        inp = replace(best.input, id=inp.id)
        case, outcome, fail_impact = renamed(best, inp.id), got, first_failing_impact(best, got.score)
    return case, outcome, rounds


def _build(inputs: list[CaseInput]) -> list[UserCase]:
    """The cases of ``inputs`` that can be built (:func:`..oracle.ondemand.build_user_case`)."""
    out = []
    for c in inputs:
        try:
            out.append(build_user_case(c))
        except CaseError:
            continue
    return out


def renamed(case: UserCase, id: str) -> UserCase:
    """``case`` under the id ``id`` (its input, settings and provenance)."""
    settings = {**case.settings, "id": id}
    return replace(case, input=replace(case.input, id=id), settings=settings, provenance={**case.provenance, "id": id})
