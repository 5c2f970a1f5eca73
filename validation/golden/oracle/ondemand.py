"""A golden case for any input (``gear-rattle case``; docs/reference/golden_commands.md, "Asking the oracle").

:func:`build_user_case` certifies the orbit of one input (:func:`mapimpl.certified.certify_orbit`, or
:func:`mapimpl.certified.certify_no_impact_orbit` where the last flight never lands) and gives every row its
tolerance by the rule of docs/golden_tolerances.md (:func:`row_tolerances`: ``SAFETY`` times the error a correct
float64 implementation can make at that row, from :mod:`.conditioning`).

**The horizon rule** (the chaotic horizon, generalised): no row of a generated case has a tolerance of
``max_tolerance`` (default :data:`TOLERANCE_LIMIT`, 1e-6; ``gear-rattle case --max-tolerance T``) or more in any
column.  Where the rule would give one -- the error of a correct float64 implementation, amplified along the
orbit, at a graze or down a chatter, is too large -- the case stops at the last impact whose rows keep every
tolerance below the limit, and says so (``notes.truncation`` of its settings, and :attr:`UserCase.message`).
A row's tolerance depends on the rows before it only, so that impact is the last before the first row over
the limit.  Why 1e-6 by default: an impact time (or velocity) off by 1e-6 then fails every generated case at
every row, and every row's tolerance is 10 times the error of a correct implementation there: a wrong
implementation whose error exceeds the correct one's by more than that factor fails.  A smaller limit gives a
shorter case.  An impact that cannot be certified (a tangency the balls cannot separate, a flight longer than
``T_MAX`` that is not proven to never land) ends the case in the same way, at the last certified impact; so
does a flight that turns back closer to a wall than :data:`NEAR_MISS_SAFETY` times the gap error of a correct
implementation (:func:`near_miss_limit`: it may take such a near miss for a contact), and a graze whose
excursion beyond the wall lies within 10 gap errors (:attr:`conditioning.RowErrors.fragile`: it may miss it).
A case does not ask a sticking decision that an output within the tolerances of its row could take the other
way either: it stops at that impact (the sticking-decision rule, :func:`decisions.doubtful_decision`).

:func:`build_user_cases` builds many (``--from FILE``: one process, the JAX functions of the tolerance rule
compiled once), :func:`write_user_case` writes a folder and :func:`update_index` the suite's ``index.json``
(its other fields kept).
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ....core.checks import check_real
from ....core.horizons import T_MAX
from ....mapimpl import certified as cert
from ..formats.case_writer import expected_csv, provenance_json, radius_stats, settings_json, write_case, write_plain
from ..formats.cases import TOLERANCE_COLUMNS
from ..formats.index import INDEX_NAME, build_index
from ..formats.jsonformat import read_json
from ..formats.spec import Spec
from ..formats.textformat import MAX_BYTES, MAX_LINES, MalformedFile
from ..rules.decisions import doubtful_decision, forcing_in
from ..rules.near_miss import near_miss_limit
from ..rules.tolerances import RADIUS_LIMIT, RowTolerances, row_tolerances
from .inputs import CaseInput

#: Every tolerance of a generated case lies below this by default (module docstring).
TOLERANCE_LIMIT = 1e-6
#: The limits a case may ask for (``max_tolerance``): no row's tolerance is below ~1e-14 (10 times half an
#: ulp of 2 pi); every row stays below the limit, and a suite states no tolerance of 1e-4 or more
#: (:data:`.boundary.MAX_TOLERANCE`).
MIN_TOLERANCE_LIMIT, MAX_TOLERANCE_LIMIT = 1e-14, 1e-4
TOLERANCE_RANGE = f"{MIN_TOLERANCE_LIMIT:g} <= max_tolerance <= {MAX_TOLERANCE_LIMIT:g}"
#: The first length certified (doubled until the case is decided); the impacts a case may ask for are
#: :data:`.boundary.MAX_CASE_IMPACTS`.
FIRST_CHUNK = 64


# ---------------------------------------------------------------------------------------------
# tolerances and the horizon rule


def input_spec(inp: CaseInput, n_impacts: int) -> Spec:
    p = inp.params
    start = (
        f"pre-impact start (tau0, sdot0) = ({inp.tau0!r}, {inp.sdot0!r})"
        if inp.s0 is None
        else f"free-flight start (tau0, s0, sdot0) = ({inp.tau0!r}, {inp.s0!r}, {inp.sdot0!r})"
    )
    return Spec(
        inp.id,
        f"A case on demand (gear-rattle case): alpha={p.alpha!r}, beta={p.beta!r}, "
        f"gamma={p.gamma!r}, r={p.r!r}, {start}.",
        p,
        inp.tau0,
        inp.sdot0,
        n_impacts,
        s0=inp.s0,
        tags=("user",),
        stick_time=inp.stick_time,
    )


#: A contact reached against the pull of the force (the flight was turning back) slower than this is a graze:
#: the case is level 3 and catches ``skipped-graze`` (``_level_and_catches``).
GRAZE_SPEED = 0.1


def _first_over(tols: RowTolerances, limit: float) -> tuple[int, str] | None:
    """``(row, column)`` of the first row with a tolerance at or above ``limit``, or of a contact a correct
    implementation may miss (column ``""``: :attr:`conditioning.RowErrors.fragile`); ``None`` if none."""
    first = None if tols.errors.fragile is None else (tols.errors.fragile, "")
    for c in TOLERANCE_COLUMNS:
        over = np.nonzero(np.nan_to_num(tols.values[c], nan=0.0) >= limit)[0]
        if over.size and (first is None or over[0] < first[0]):
            first = (int(over[0]), c)
    return first


def _prefix(orb: cert.CertifiedOrbit, k: int) -> cert.CertifiedOrbit:
    """The orbit up to impact ``k`` (its rows, no row after it): a case of ``k`` impacts, status active."""
    last = max(i for i, e in enumerate(orb.events) if e.kind == "impact" and e.n == k)
    return cert.CertifiedOrbit(
        orb.events[: last + 1],
        "active",
        f"truncated at impact {k}",
        orb.prec,
        [f for f in orb.flights if f["impact"] <= k],
    )


def _last_impact(orb: cert.CertifiedOrbit) -> int:
    return max(e.n for e in orb.events if e.kind == "impact")


def certify_input(
    inp: CaseInput, n: int, prec: int, deadline: float | None = None
) -> tuple[cert.CertifiedOrbit | None, str]:
    """``(orbit, why it ends early)``: the certified orbit of ``n`` impacts; where a flight cannot be
    certified, the longest certified prefix (``why``: the impact and the reason), with the ``no_impact``
    ending where the flight after it is proven never to land.  ``None`` where not even impact 0 is certified.

    One mechanism decides how far and at what precision: the certified track's schedule
    (:func:`mapimpl.certified.track.certified_orbit`, from ``prec`` bits up, raised by itself up to its limit).
    The case's balls are then those of :func:`mapimpl.certified.certify_orbit` at the precision the schedule
    settled on, for the impacts it certified (the generator's orbit, with its flight certificates and its
    radius limit).  ``deadline`` (``time.monotonic()``): the schedule stops there (its time budget)."""
    from ....mapimpl.certified.track import certified_orbit

    budget = None if deadline is None else max(deadline - time.monotonic(), 1.0)
    run = certified_orbit(
        inp.params,
        inp.tau0,
        inp.sdot0,
        n,
        s0=inp.s0,
        stick_time=inp.stick_time,
        prec=prec,
        progress=False,
        time_budget_s=budget,
    )
    last = run.impacts_certified - 1
    kw: dict[str, Any] = dict(
        s0=inp.s0,
        prec=run.precision,
        stick_time=inp.stick_time,
        radius_limit=RADIUS_LIMIT,
        t_max=T_MAX,  # the orbit's horizon, the certified track's (a flight of 400 ... 2000 lands: a row)
    )
    if last < 0:
        return None, run.reason
    why = "" if run.complete else f"impact {run.first_uncertified} is not certified ({run.reason})"
    try:
        if run.status == "no_impact":
            try:
                return cert.certify_no_impact_orbit(inp.params, inp.tau0, inp.sdot0, last, **kw), ""
            except cert.CertificationError as e:  # the case's own proof of the ending (cf. the docstring)
                why = f"the flight after impact {last} is not certified to never land ({e})"
        elif run.complete:  # all n (the orbit's own ending, e.g. stuck forever, is found again)
            return cert.certify_orbit(inp.params, inp.tau0, inp.sdot0, n, **kw), ""
        return cert.certify_orbit(inp.params, inp.tau0, inp.sdot0, last, **kw), why
    except cert.CertificationError as e:  # the generator's certificate at the schedule's precision disagrees
        return None, f"the certified track reached impact {last} at {run.precision} bits, its case does not: {e}"


@dataclass
class UserCase:
    """A built case: its files' contents, the impacts asked for and kept, and why it stops early
    (``truncation``: ``None`` when it has every impact asked for or ends as the orbit does)."""

    input: CaseInput
    settings: dict
    expected: str
    provenance: dict
    truncation: dict | None = None

    @property
    def message(self) -> str | None:
        """One line for stderr where the case stops before the impacts asked for."""
        t = self.truncation
        if t is None:
            return None
        return f"case {self.input.id}: stops at impact {t['kept_impacts']} of {t['requested_impacts']}: {t['reason']}"


class CaseError(Exception):
    """An input whose case cannot be built (not even impact 0 within the rules); one line."""


def check_max_tolerance(value) -> float:
    """``max_tolerance`` of :func:`build_user_case`, validated (``ValueError`` naming it and its range)."""
    return check_real("max_tolerance", value, MIN_TOLERANCE_LIMIT, MAX_TOLERANCE_LIMIT, allowed=TOLERANCE_RANGE)


def _cut(
    inp: CaseInput, orb: cert.CertifiedOrbit, over: tuple[int, str], limit: float
) -> tuple[cert.CertifiedOrbit, str]:
    """The orbit up to the last impact before the row ``over`` (whose tolerance reaches ``limit``, or whose
    contact a correct implementation may miss) and why; :class:`CaseError` where no impact is left."""
    row, col = over
    ev = orb.events[row]
    last = ev.n - 1 if ev.kind == "impact" else ev.n  # a stick/release row comes after its impact
    tols = row_tolerances(input_spec(inp, inp.impacts), orb)
    if col:
        why = (
            f"with impact {ev.n} the tolerance of a correct float64 implementation would be {col} "
            f"{tols.values[col][row]:.2g} (line {row + 2} of expected.csv, the error of impact "
            f"{int(tols.errors.source[row])} carried there), not below the limit {limit:g}"
        )
    else:
        why = f"impact {ev.n} is a graze that a correct float64 implementation may miss (its excursion is within 10 gap errors)"
    if last < 0:
        raise CaseError(f"case {inp.id}: {why} (no impact within the limit)")
    return _prefix(orb, last), why


#: Most rows of a case's ``expected.csv``: ``check`` reads at most 20000 lines and 2 MiB (a row ~100-160 bytes).
MAX_CASE_ROWS = 12_000
#: The time a case may take by default (``case --time-limit``), in seconds.
TIME_LIMIT_S = 600.0


def _grow(inp: CaseInput, prec: int, limit: float, time_limit_s: float | None):
    """``(orbit, why it ends early, the first row over the limit or None)``: the orbit certified in chunks
    doubled from :data:`FIRST_CHUNK` until the case is decided (every impact asked for, a tolerance at the
    limit, an ending, an impact not certified) -- or the time limit: a chunk is started only if twice the
    last one's time is left (the next is twice as long), and the certified track stops at the deadline
    itself -- then cut to :data:`MAX_CASE_ROWS` rows."""
    deadline = None if time_limit_s is None else time.monotonic() + time_limit_s
    n = min(inp.impacts, FIRST_CHUNK)
    while True:
        t0 = time.monotonic()
        orb, why = certify_input(inp, n, prec, deadline)
        if why and deadline is not None and time.monotonic() > deadline:
            why = f"the time limit of {time_limit_s:g} s (--time-limit) was reached: {why}"
        if orb is None:
            raise CaseError(f"case {inp.id}: impact 0 is not certified: {why}")
        over = _first_over(row_tolerances(input_spec(inp, inp.impacts), orb), limit)
        if over or why or orb.status != "active" or n >= inp.impacts:
            break
        now = time.monotonic()
        if deadline is not None and now + 2 * (now - t0) > deadline:
            why = f"the time limit of {time_limit_s:g} s (--time-limit) leaves no time to certify impacts after {n}"
            break
        n = min(2 * n, inp.impacts)
    if len(orb.events) > MAX_CASE_ROWS:
        k = max(e.n for e in orb.events[:MAX_CASE_ROWS] if e.kind == "impact")
        orb, why = (
            _prefix(orb, k),
            (
                f"with impact {k + 1} the case would have more than {MAX_CASE_ROWS} rows (expected.csv "
                f"must stay within what check reads: {MAX_LINES} lines, {MAX_BYTES} bytes)"
            ),
        )
        over = _first_over(row_tolerances(input_spec(inp, inp.impacts), orb), limit)
    return orb, why, over


def build_user_case(
    inp: CaseInput, prec: int = cert.PREC, max_tolerance: float = TOLERANCE_LIMIT, time_limit_s: float | None = None
) -> UserCase:
    """Certify ``inp``, set the tolerance of every row (:func:`row_tolerances`) and apply the horizon
    rule with the limit ``max_tolerance`` (module docstring).  ``time_limit_s``: the case stops at the last
    impact certified within about that time (None: no limit; ``_grow``); it has at most
    :data:`MAX_CASE_ROWS` rows.  Raises :class:`CaseError` where no prefix of the orbit is certified within
    the limits, ``ValueError`` for a limit out of range."""
    limit = check_max_tolerance(max_tolerance)
    orb, why, over = _grow(inp, prec, limit, time_limit_s)
    reason = why
    miss = near_miss_limit(input_spec(inp, inp.impacts), orb)
    if miss is not None:
        if miss[0] == 0:
            raise CaseError(f"case {inp.id}: {miss[1]} (no impact before it)")
        orb, reason = _prefix(orb, miss[0] - 1), miss[1]
        over = _first_over(row_tolerances(input_spec(inp, inp.impacts), orb), limit)
    if over:
        orb, reason = _cut(inp, orb, over, limit)
    kept = _last_impact(orb) if reason else inp.impacts
    spec = input_spec(inp, kept)
    tols = row_tolerances(spec, orb)
    # the sticking-decision rule: a row's tolerance is set by the rows before it, so the first decision in
    # doubt within its row's tolerances ends the case there (that impact's decision is then not asked)
    doubt = doubtful_decision(spec, orb, tols.values["tau"], tols.values["sdot"])
    if doubt is not None:
        kept, reason = doubt[0], doubt[1]
        orb = _prefix(orb, kept)
        spec = input_spec(inp, kept)
        tols = row_tolerances(spec, orb)
    truncation = None
    notes = {"tolerances": tols.note()}
    if reason:
        truncation = {
            "requested_impacts": inp.impacts,
            "kept_impacts": kept,
            "limit": limit,
            "reason": reason,
            "rule": f"the case stops at the last impact whose rows keep every tolerance below {limit:g}, or at "
            "the last certified impact (docs/golden.md, asking the oracle)",
        }
        notes["truncation"] = truncation
    spec = replace(spec, tags=spec.tags + (("truncated",) if reason else ()), notes={**spec.notes, **notes})
    text = expected_csv(orb, tols)
    settings = settings_json(spec, orb, tols)
    settings["level"], settings["catches"] = _level_and_catches(spec, orb)
    radii = radius_stats(text, orb)
    radii.pop("_rows")
    prov = provenance_json(spec, orb, radii, None)
    prov["generator"] = "gear-rattle case"
    return UserCase(inp, settings, text, prov, truncation)


def _has_graze(spec: Spec, orb: cert.CertifiedOrbit) -> bool:
    """Whether a contact reached by a flight against the pull of the force (``s'' = f - beta s'`` points away
    from the wall) is slower than :data:`GRAZE_SPEED`."""
    p = spec.params
    for e in orb.events:
        if e.kind != "impact" or (e.n == 0 and spec.s0 is None):
            continue
        v = cert.nearest_float(e.sdot)
        acc = forcing_in(p, cert.nearest_float(e.tau), 0) - p.beta * v
        if (acc < 0 if e.wall == 0 else acc > 0) and abs(v) < GRAZE_SPEED:
            return True
    return False


def _level_and_catches(spec: Spec, orb: cert.CertifiedOrbit) -> tuple[int, list[str]]:
    """The level a case needs (2 with stick rows, 3 when it ends with no_impact or has a graze) and the bug
    classes of the catalogue it can catch, from its rows."""
    kinds = {e.kind for e in orb.events}
    walls = {e.wall for e in orb.events if e.kind == "impact"}
    catches = ["flight-or-impact-law"]
    if spec.s0 is not None:
        catches.append("free-flight-start")
    if -1 in walls or spec.params.gamma < 0:
        catches.append("lower-wall-conventions")
    if spec.params.beta < 1e-4:
        catches.append("cancellation")
    if "stick" in kinds:
        catches.append("sticking-threshold")
        if any(e.kind == "stick" and e.wall == -1 for e in orb.events):
            catches.append("lower-wall-sticking")
    if "release" in kinds:
        catches.append("release-departure")
    if orb.status == "stuck_forever":
        catches.append("stuck-forever")
    if orb.status == "no_impact":
        catches.append("no-impact-ending")
    if spec.params.r == 1.0:
        catches.append("elastic-r1")
    graze = _has_graze(spec, orb)
    if graze:
        catches.append("skipped-graze")
    level = 3 if (orb.status == "no_impact" or graze) else (2 if "stick" in kinds else 1)
    return level, catches


def build_user_cases(
    inputs: list[CaseInput],
    progress=None,
    time_limit_s: float | None = None,
    max_tolerance: float = TOLERANCE_LIMIT,
) -> list[UserCase | CaseError]:
    """:func:`build_user_case` for each input (a :class:`CaseError` in place of a case that cannot be
    built); ``progress(done, total)`` after each; ``time_limit_s`` and ``max_tolerance``: each case's."""
    out: list[UserCase | CaseError] = []
    for k, inp in enumerate(inputs):
        try:
            out.append(build_user_case(inp, max_tolerance=max_tolerance, time_limit_s=time_limit_s))
        except CaseError as e:
            out.append(e)
        if progress is not None:
            progress(k + 1, len(inputs))
    return out


def write_user_case(suite: Path, case: UserCase, write: Callable[[Path, str], object] = write_plain) -> Path:
    """Write ``suite/<id>/`` (settings.json, expected.csv, provenance.json) through ``write`` (the
    command line passes its atomic writer); returns the folder."""
    folder = Path(suite) / case.input.id
    write_case(folder, case.settings, case.expected, case.provenance, write)
    return folder


#: The name a suite built with ``gear-rattle case`` gives itself in its index (until its user renames it).
USER_SUITE_NAME = "user suite (gear-rattle case)"


def index_text(suite: Path, overlay: dict[str, Path] | None = None) -> str:
    """The text of ``suite/index.json`` from its case folders (with ``overlay``, ``{"<id>/<file>": file}``:
    as it will be once those files are moved in, :func:`..formats.index.build_index`), keeping every field an
    existing index has beside the case list (a suite version, a changelog ...) and adding the standard ones
    it lacks.  The existing index and every case are read as ``check`` reads them (regular files inside
    the suite, within the limits): ``ValueError`` (one line) otherwise."""
    path = Path(suite) / INDEX_NAME
    old: dict = {}
    if os.path.lexists(path):
        try:
            old = read_json(path, suite, MAX_BYTES).value
        except MalformedFile as e:
            raise ValueError(f"{e} (not updated)") from None
        if not isinstance(old, dict):
            raise ValueError(f"{path}: not a JSON object (not updated)")
    try:
        fresh = build_index(Path(suite), overlay)
    except MalformedFile as e:
        raise ValueError(f"suite {str(suite)!r}: {e}") from None
    # the suite block: this suite's name and version (the user's, if the index had them; never the shipped
    # suite's) with the digests of its files as they are now, so that check says it matches
    mine = old.get("suite")
    mine = mine if isinstance(mine, dict) else {}
    block = {
        **fresh["suite"],
        "name": str(mine.get("name", USER_SUITE_NAME)),
        "version": str(mine.get("version", "unversioned")),
    }
    merged = {
        **fresh,
        **{k: v for k, v in old.items() if k not in ("cases", "suite")},
        "suite": block,
        "cases": fresh["cases"],
    }
    return json.dumps(merged, indent=1) + "\n"


def update_index(suite: Path, write: Callable[[Path, str], object] = write_plain) -> Path:
    """Write ``suite/index.json`` (:func:`index_text`) through ``write``; returns its path."""
    path = Path(suite) / INDEX_NAME
    write(path, index_text(suite))
    return path
