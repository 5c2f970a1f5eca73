"""A golden case for any input (``gear-rattle case``; docs/golden.md, "Asking the oracle").

:func:`build_user_case` certifies the orbit of one input (:func:`mapimpl.certified.certify_orbit`, or
:func:`mapimpl.certified.certify_no_impact_orbit` where the last flight never lands) and gives every row its
tolerance by the rule of docs/golden.md (:func:`generate.row_tolerances`: ``SAFETY`` times the error a correct
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
import math
import os
import time
from dataclasses import dataclass, replace
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ...core.checks import check_int, check_real
from ...core.horizons import T_MAX
from ...core.params import PARAM_NAMES, RANGES, Params, check_value
from ...mapimpl import certified as cert
from ...mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from . import generate
from .boundary import MAX_CASE_IMPACTS, MAX_CASES, check_id, shown
from .catalog import INDEX_NAME, build_index
from .csvformat import Record, check_header, split_line, text_lines
from .jsonformat import parse_json, read_json
from .textformat import MAX_BYTES, MAX_LINES, MalformedFile, position, read_text
from .decisions import doubtful_decision

import numpy as np

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
#: The largest |tau0| and |sdot0| of an input (the command line's ranges, :func:`cliutil.tau0_type`).
TAU0_MAX, SDOT0_MAX = 1e6, 1e6
#: Most inputs of a ``--from`` file (as many cases as a suite may hold).
MAX_INPUTS = MAX_CASES
#: The fields of an input (a ``--from`` file's columns or keys): required, then optional.
REQUIRED_FIELDS = ("id", *PARAM_NAMES, "tau0", "sdot0", "impacts")
OPTIONAL_FIELDS = ("s0", "stick_time")


@dataclass(frozen=True)
class CaseInput:
    """One question to the oracle: the parameters, the initial state (pre-impact ``(tau0, sdot0)``, or
    free flight with ``s0``), the impacts after impact 0 and the sticking threshold."""

    id: str
    params: Params
    tau0: float
    sdot0: float
    impacts: int
    s0: float | None = None
    stick_time: float = STICK_TIME

    def as_dict(self) -> dict:
        """The input as a ``--from`` JSON entry."""
        p = self.params
        d = {"id": self.id, **p.as_dict(), "tau0": self.tau0, "sdot0": self.sdot0, "impacts": self.impacts}
        if self.s0 is not None:
            d["s0"] = self.s0
        if self.stick_time != STICK_TIME:
            d["stick_time"] = self.stick_time
        return d


def _number(name: str, value, lo: float | None = None, hi: float | None = None, allowed: str = "") -> float:
    """A number of an input (a decimal string from a CSV file is read as its float) checked by the one
    boundary helper, :func:`core.checks.check_real` (ValueError naming ``name`` and ``allowed``)."""
    if isinstance(value, bool):
        raise ValueError(f"{name}={value!r} is not a number: allowed {allowed}")
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise ValueError(f"{name}={shown(value)} is not a number: allowed {allowed}") from None
    return check_real(
        name, value, -math.inf if lo is None else lo, math.inf if hi is None else hi, allowed=allowed or None
    )


def _param(name: str) -> Callable[[object], float]:
    def check(value) -> float:
        if isinstance(value, bool):
            raise ValueError(f"parameter {name}={value!r} is not a number: allowed {RANGES[name]} (finite)")
        return check_value(name, value)  # ValueError naming the parameter and its range

    return check


def _s0(value) -> float:
    allowed = "-1 < s0 < 0 (a free-flight start strictly between the walls)"
    s0 = _number("s0", value, allowed=allowed)
    if not -1.0 < s0 < 0.0:
        raise ValueError(f"s0={s0!r} is out of range: allowed {allowed}")
    return s0


def _impacts(value) -> int:
    allowed = f"an integer 0 <= impacts <= {MAX_CASE_IMPACTS}"
    return check_int("impacts", _number("impacts", value, allowed=allowed), 0, MAX_CASE_IMPACTS)


#: The check of each field of an input (:func:`checked_fields`): the value, converted, or ValueError.
FIELD_CHECKS: dict[str, Callable[[object], object]] = {
    "id": lambda v: check_id(v.strip() if isinstance(v, str) else v, "id"),
    **{k: _param(k) for k in PARAM_NAMES},
    "tau0": lambda v: _number("tau0", v, -TAU0_MAX, TAU0_MAX, f"a finite number with |tau0| <= {TAU0_MAX:g}"),
    "sdot0": lambda v: _number("sdot0", v, -SDOT0_MAX, SDOT0_MAX, f"a finite number with |sdot0| <= {SDOT0_MAX:g}"),
    "impacts": _impacts,
    "s0": _s0,
    "stick_time": lambda v: _number(
        "stick_time",
        v,
        0.0,
        MAX_STICK_TIME,
        f"a finite number 0 <= stick_time <= {MAX_STICK_TIME:g} (mapimpl.sticking.MAX_STICK_TIME)",
    ),
}


def checked_fields(values: dict) -> tuple[dict, dict[str, str]]:
    """``(converted, problems)``: every field of ``values`` (those of :data:`FIELD_CHECKS`; an optional one
    absent or None is left out) checked on its own, and the start's joint rule (a pre-impact start needs
    ``sdot0 != 0``); ``problems`` maps each bad field to its reason, in field order."""
    out, bad = {}, {}
    for k in (*REQUIRED_FIELDS, *OPTIONAL_FIELDS):
        if k in values and not (k in OPTIONAL_FIELDS and values[k] is None):
            try:
                out[k] = FIELD_CHECKS[k](values[k])
            except (ValueError, TypeError) as e:
                bad[k] = str(e)
    if out.get("sdot0") == 0.0 and values.get("s0") is None:
        bad["sdot0"] = (
            "sdot0=0.0 is out of range: a pre-impact start needs sdot0 != 0 (> 0: upper wall s = 0, "
            "< 0: lower wall s = -1); give s0 for a start in free flight"
        )
    return out, {k: bad[k] for k in (*REQUIRED_FIELDS, *OPTIONAL_FIELDS) if k in bad}


def _input(out: dict) -> CaseInput:
    params = Params(*(out[k] for k in PARAM_NAMES))
    st = out.get("stick_time", STICK_TIME)
    return CaseInput(out["id"], params, out["tau0"], out["sdot0"], out["impacts"], out.get("s0"), st)


def case_input(id: str, alpha, beta, gamma, r, tau0, sdot0, impacts, s0=None, stick_time=None) -> CaseInput:
    """A validated :class:`CaseInput`; ``ValueError`` naming the (first bad) field and its allowed range."""
    values = dict(zip(REQUIRED_FIELDS, (id, alpha, beta, gamma, r, tau0, sdot0, impacts)))
    out, bad = checked_fields({**values, "s0": s0, "stick_time": stick_time})
    if bad:
        raise ValueError(next(iter(bad.values())))
    return _input(out)


def _blank(v) -> bool:
    return v is None or (isinstance(v, str) and v.strip() == "")


@dataclass
class InputProblem:
    """A bad input of a ``--from`` file: where it is (``line 3``, ``entry 2 (line 5)``) and, per bad field
    (``""``: the line as a whole), the reason."""

    where: str
    fields: dict[str, str]

    def __str__(self) -> str:
        return f"{self.where}: " + "; ".join(f"field {k}: {r}" if k else r for k, r in self.fields.items())


@dataclass
class InputFile:
    """A ``--from`` file read by :func:`read_input_file`: its good inputs and its bad ones, in file order."""

    path: str
    inputs: list[CaseInput]
    problems: list[InputProblem]

    @property
    def total(self) -> int:
        return len(self.inputs) + len(self.problems)


def _entry(values: dict, where: str) -> CaseInput | InputProblem:
    """One input from its fields (strings from a CSV line, JSON values from an entry)."""
    unknown = sorted(set(values) - set(REQUIRED_FIELDS) - set(OPTIONAL_FIELDS), key=str)
    if unknown:
        fields = ", ".join(map(shown, unknown))
        allowed = ", ".join(REQUIRED_FIELDS + OPTIONAL_FIELDS)
        return InputProblem(where, {"": f"unknown field(s) {fields} (allowed: {allowed})"})
    missing = {k: "missing (a value is needed)" for k in REQUIRED_FIELDS if _blank(values.get(k))}
    out, problems = checked_fields({k: (None if _blank(v) else v) for k, v in values.items()})
    bad = {**problems, **missing}
    bad = {k: bad[k] for k in (*REQUIRED_FIELDS, *OPTIONAL_FIELDS) if k in bad}  # in field order
    return InputProblem(where, bad) if bad else _input(out)


def _csv_entries(text: str, path: str) -> list[tuple[str, dict | InputProblem]]:
    """``(where, fields or problem)`` of every data line of a ``--from`` CSV (:mod:`.csvformat`'s grammar,
    each line on its own: a bad line does not stop the others); ValueError for a bad header."""
    lines = text_lines(text)
    if not lines:
        raise ValueError(
            f"--from {path}: empty file (a CSV with the header {','.join(REQUIRED_FIELDS)}"
            "[,s0][,stick_time], or a JSON list)"
        )
    hline, htext = lines[0]
    try:
        header = Record(hline, htext, split_line(htext, path, hline))
        check_header(path, header)
    except MalformedFile as e:
        raise ValueError(f"--from {e}") from None
    names = header.values
    unknown = [h for h in names if h not in REQUIRED_FIELDS + OPTIONAL_FIELDS]
    missing = [k for k in REQUIRED_FIELDS if k not in names]
    if unknown or missing:
        what = (
            f"unknown field(s) {', '.join(map(shown, unknown))}"
            if unknown
            else f"missing field(s) {', '.join(missing)}"
        )
        raise ValueError(
            f"--from {path}: line {hline}: {what} (the header names {','.join(REQUIRED_FIELDS)}, "
            f"optionally {','.join(OPTIONAL_FIELDS)})"
        )
    out: list[tuple[str, dict | InputProblem]] = []
    for line, t in lines[1:]:
        where = f"line {line}"
        try:
            row = split_line(t, path, line)
        except MalformedFile as e:  # "PATH: line L, column C: what": the position and what
            what = str(e).removeprefix(f"{path}: ").removeprefix(f"{where}, ")
            out.append((where, InputProblem(where, {"": what})))
            continue
        if len(row) != len(names):
            out.append(
                (where, InputProblem(where, {"": f"{len(row)} fields, expected {len(names)} (as many as the header)"}))
            )
        else:
            out.append((where, dict(zip(names, row))))
    return out


def _json_entries(text: str, path: str) -> list[tuple[str, dict | InputProblem]]:
    """``(where, fields or problem)`` of every entry of a ``--from`` JSON list (the strict reader,
    :mod:`.jsonformat`: its limits; a syntax error is one ValueError, the entries are then checked one by one)."""
    try:
        doc = parse_json(text, path, top=list)
    except MalformedFile as e:
        raise ValueError(f"--from {e}") from None
    out: list[tuple[str, dict | InputProblem]] = []
    for k, entry in enumerate(doc.value):
        where = f"entry {k} (line {position(text, doc.offsets.get((k,), 0))[0]})"
        if isinstance(entry, dict):
            out.append((where, entry))
        else:
            out.append(
                (
                    where,
                    InputProblem(
                        where, {"": f"an input must be an object with the fields {', '.join(REQUIRED_FIELDS)}"}
                    ),
                )
            )
    return out


def _duplicates(inputs: list[tuple[str, CaseInput]]) -> tuple[list[CaseInput], list[tuple[str, InputProblem]]]:
    """The inputs whose id is new, and a problem for each later one with an id taken (compared in lower
    case: on a case-insensitive file system ``A`` and ``a`` would be one folder)."""
    seen: dict[str, tuple[str, str]] = {}
    good, bad = [], []
    for where, inp in inputs:
        key = inp.id.lower()
        if key in seen:
            first, fid = seen[key]
            why = (
                f"duplicate id {inp.id!r} (also {first})"
                if fid == inp.id
                else (
                    f"id {inp.id!r} differs from {fid!r} ({first}) only in case: one folder on a case-insensitive file system"
                )
            )
            bad.append((where, InputProblem(where, {"id": why})))
        else:
            seen[key] = (where, inp.id)
            good.append(inp)
    return good, bad


def read_input_file(path: str | Path) -> InputFile:
    """Every input of a ``--from`` file (a JSON list of objects, or a CSV with a header of the field names:
    :data:`REQUIRED_FIELDS`, optionally :data:`OPTIONAL_FIELDS`; an empty ``s0`` is a pre-impact start),
    the good ones and the bad ones (each with where it is, its bad fields and why; duplicate ids refused).

    Read as ``check`` reads (:mod:`.textformat`: a regular file, never waited on; 2 MiB, 20000 lines,
    UTF-8; CSV fields of at most 1000 characters; JSON nested at most 32 deep, numbers of at most 100
    characters) and at most :data:`MAX_INPUTS` inputs.  ``ValueError`` (one line naming the file) where the
    file as a whole cannot be read: missing, not a regular file, beyond a limit, invalid JSON, a bad header."""
    path = Path(path)
    try:
        text = read_text(path, MAX_BYTES)
    except MalformedFile as e:
        raise ValueError(f"--from {e}") from None
    json_file = text.lstrip().startswith(("[", "{"))
    entries = _json_entries(text, str(path)) if json_file else _csv_entries(text, str(path))
    if len(entries) > MAX_INPUTS:
        raise ValueError(f"--from {path}: {len(entries)} inputs: allowed at most {MAX_INPUTS} (the limit of a suite)")
    if not entries:
        raise ValueError(f"--from {path}: no inputs")
    good, problems = [], []
    for where, entry in entries:
        got = entry if isinstance(entry, InputProblem) else _entry(entry, where)
        (problems.append((where, got)) if isinstance(got, InputProblem) else good.append((where, got)))
    inputs, dups = _duplicates(good)
    order = {w: k for k, (w, _) in enumerate(entries)}
    problems = sorted(problems + dups, key=lambda wp: order[wp[0]])
    return InputFile(str(path), inputs, [p for _, p in problems])


def read_inputs(path: str | Path) -> list[CaseInput]:
    """The inputs of a ``--from`` file (:func:`read_input_file`), all good: ``ValueError`` naming the file,
    the first bad entry (or line) and its field otherwise."""
    f = read_input_file(path)
    if f.problems:
        raise ValueError(f"--from {path}: {f.problems[0]}")
    return f.inputs


# ---------------------------------------------------------------------------------------------
# tolerances and the horizon rule


def _spec(inp: CaseInput, n_impacts: int) -> generate.Spec:
    p = inp.params
    start = (
        f"pre-impact start (tau0, sdot0) = ({inp.tau0!r}, {inp.sdot0!r})"
        if inp.s0 is None
        else f"free-flight start (tau0, s0, sdot0) = ({inp.tau0!r}, {inp.s0!r}, {inp.sdot0!r})"
    )
    return generate.Spec(
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
#: the case is level 3 and catches ``skipped-graze`` (:func:`_level_and_catches`).
GRAZE_SPEED = 0.1


def _first_over(tols: generate.RowTolerances, limit: float) -> tuple[int, str] | None:
    """``(row, column)`` of the first row with a tolerance at or above ``limit``, or of a contact a correct
    implementation may miss (column ``""``: :attr:`conditioning.RowErrors.fragile`); ``None`` if none."""
    first = None if tols.errors.fragile is None else (tols.errors.fragile, "")
    for c in generate.TOLERANCE_COLUMNS:
        over = np.nonzero(np.nan_to_num(tols.values[c], nan=0.0) >= limit)[0]
        if over.size and (first is None or over[0] < first[0]):
            first = (int(over[0]), c)
    return first


#: A flight that turns back closer to a wall than this many times the gap error ``e`` of a correct float64
#: implementation (:func:`conditioning.gap_error`: ``2 2^-52 + 3e-14 h`` for a flight within one period) may be
#: taken for a contact by one: a case stops before the impact that ends such a flight (the near-miss rule; the
#: shipped near misses lie at 6.6e6 e, 3.3e4 e and 330 e).
NEAR_MISS_SAFETY = 10.0
#: Samples of a flight per refinement when its turning points are searched (three refinements), and per unit of
#: time in the first round (at least :data:`TURN_SAMPLES`; the forcing's period is 2 pi).
TURN_SAMPLES, TURN_SAMPLES_PER_UNIT = 257, 64


_FLIGHT: list = []  # the flight's (ds, v) at TURN_SAMPLES times, compiled once


def turn_grid(dt: float, departure: bool = True):
    """The first round's sample times of a flight of ``dt``: :data:`TURN_SAMPLES_PER_UNIT` per unit of time (a
    long flight oscillates with the forcing) and, for a ``departure`` with a speed (after an impact), ``dt 2^-k``
    for k = 1 ... 64 (a slow departure against a weakening force turns back twice within 1e-6 of its start: a
    257-point grid saw neither turning point of a flight that came back within 1.6e-19 of its start wall,
    found by ``gear-rattle fuzz``).  Not after a release from rest: there the force vanishes to rounding and
    ``sdot`` dips to ~-1e-31 just after the start, no turning point of the model."""
    import numpy as np

    n = max(TURN_SAMPLES, int(math.ceil(dt * TURN_SAMPLES_PER_UNIT)))
    early = dt * 2.0 ** -np.arange(64.0, 0.0, -1.0) if departure else np.zeros(0)
    return np.unique(np.concatenate([early, np.linspace(0.0, dt, n)]))


def turning_gap(p: Params, th0: float, v0: float, s_start: float, dt: float) -> float:
    """The smallest distance to a wall at which the flight from ``(th0, s_start, v0)`` turns back before
    ``dt`` (interior extrema of ``s``, located on :func:`turn_grid` and two refinements of
    :data:`TURN_SAMPLES` samples: the float64 closed form, Eqs. 7-8); ``inf`` without a turning point."""
    if not _FLIGHT:
        import jax

        from ...mapimpl.flight import flight

        _FLIGHT.append(jax.jit(lambda t, th, v, a, b, g: (flight(t, th, v, a, b, g).ds, flight(t, th, v, a, b, g).v)))

    def at(t):
        """``(t, s, v)`` at the times ``t``, in chunks of TURN_SAMPLES (one compiled shape)."""
        ds, vs = [], []
        for k in range(0, len(t), TURN_SAMPLES):
            chunk = t[k : k + TURN_SAMPLES]
            d, w = _FLIGHT[0](
                np.pad(chunk, (0, TURN_SAMPLES - len(chunk)), mode="edge"), th0, v0, p.alpha, p.beta, p.gamma
            )
            ds.append(np.asarray(d)[: len(chunk)])
            vs.append(np.asarray(w)[: len(chunk)])
        return t, s_start + np.concatenate(ds), np.concatenate(vs)

    def zoom(a: float, b: float, pick) -> tuple[float, float]:
        """``(s, v)`` at the sample ``pick(s, v)`` of ``[a, b]`` after two refinements around it."""
        for _ in range(2):
            tt, ss, vv = at(np.linspace(a, b, TURN_SAMPLES))
            k = int(pick(ss, vv))
            a, b = tt[max(k - 1, 0)], tt[min(k + 1, TURN_SAMPLES - 1)]
        return float(ss[k]), float(vv[k])

    t, s, v = at(turn_grid(dt, v0 != 0))
    best = math.inf
    for i in np.nonzero(np.sign(v[1:-1]) != np.sign(v[2:]))[0] + 1:
        up = v[i] > 0
        s_k, _ = zoom(t[i], t[i + 1], lambda ss, vv: np.argmax(ss) if up else np.argmin(ss))
        best = min(best, -s_k if up else s_k + 1.0)
    # two turning points inside one interval (a dip of v through 0 and back, unseen at the samples): where the
    # acceleration changes sign, the extremum of v; after a departure with a speed only (:func:`turn_grid`)
    if v0 != 0:
        acc = p.gamma - p.alpha * np.sin(th0 + t) + p.alpha * p.beta * np.cos(th0 + t) - p.beta * v
        for i in np.nonzero((np.sign(acc[:-1]) != np.sign(acc[1:])) & (np.sign(v[:-1]) == np.sign(v[1:])))[0]:
            up = v[i] > 0
            s_k, v_k = zoom(t[i], t[i + 1], lambda ss, vv: np.argmin(vv) if up else np.argmax(vv))
            if (v_k < 0) == up and v_k != 0:
                best = min(best, -s_k, s_k + 1.0)
    return best


def near_miss_limit(spec: generate.Spec, orb: cert.CertifiedOrbit) -> tuple[int, str] | None:
    """``(impact, note)``: the first impact whose flight turns back within :data:`NEAR_MISS_SAFETY` times the
    gap error of a wall (the case must stop before it), or ``None``."""
    from .conditioning import flight_height, gap_error

    p = spec.params
    rows = generate.certified_rows(orb)
    start = None if spec.s0 is None else (spec.tau0 % (2 * math.pi), spec.sdot0, spec.tau0, spec.s0)
    prev = None
    for i, kind in enumerate(rows.kind):
        tau = float(rows.tau[i])
        if kind == "stick":
            continue
        if kind == "release":
            start = (float(rows.tau_mod_2pi[i]), 0.0, tau, float(rows.wall[i]))
            continue
        if start is None and prev is not None:
            start = (
                float(rows.tau_mod_2pi[prev]),
                -p.r * float(rows.sdot[prev]),
                float(rows.tau[prev]),
                float(rows.wall[prev]),
            )
        if start is not None:
            dt = tau - start[2]
            gap = turning_gap(p, start[0], start[1], start[3], dt)
            e = gap_error(flight_height(p, start[0], start[1], dt), dt)
            if gap < NEAR_MISS_SAFETY * e:
                return int(rows.n[i]), (
                    f"the flight to impact {int(rows.n[i])} turns back {gap:.3g} from a wall, "
                    f"within {NEAR_MISS_SAFETY:g} times the gap error {e:.3g} of a correct float64 "
                    "implementation (it may take it for a contact)"
                )
        prev, start = i, None
    return None


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


def _certify(
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
    from ...mapimpl.certified.track import certified_orbit

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
        radius_limit=generate.RADIUS_LIMIT,
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
    tols = generate.row_tolerances(_spec(inp, inp.impacts), orb)
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
        orb, why = _certify(inp, n, prec, deadline)
        if why and deadline is not None and time.monotonic() > deadline:
            why = f"the time limit of {time_limit_s:g} s (--time-limit) was reached: {why}"
        if orb is None:
            raise CaseError(f"case {inp.id}: impact 0 is not certified: {why}")
        over = _first_over(generate.row_tolerances(_spec(inp, inp.impacts), orb), limit)
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
        over = _first_over(generate.row_tolerances(_spec(inp, inp.impacts), orb), limit)
    return orb, why, over


def build_user_case(
    inp: CaseInput, prec: int = cert.PREC, max_tolerance: float = TOLERANCE_LIMIT, time_limit_s: float | None = None
) -> UserCase:
    """Certify ``inp``, set the tolerance of every row (:func:`generate.row_tolerances`) and apply the horizon
    rule with the limit ``max_tolerance`` (module docstring).  ``time_limit_s``: the case stops at the last
    impact certified within about that time (None: no limit; :func:`_grow`); it has at most
    :data:`MAX_CASE_ROWS` rows.  Raises :class:`CaseError` where no prefix of the orbit is certified within
    the limits, ``ValueError`` for a limit out of range."""
    limit = check_max_tolerance(max_tolerance)
    orb, why, over = _grow(inp, prec, limit, time_limit_s)
    reason = why
    miss = near_miss_limit(_spec(inp, inp.impacts), orb)
    if miss is not None:
        if miss[0] == 0:
            raise CaseError(f"case {inp.id}: {miss[1]} (no impact before it)")
        orb, reason = _prefix(orb, miss[0] - 1), miss[1]
        over = _first_over(generate.row_tolerances(_spec(inp, inp.impacts), orb), limit)
    if over:
        orb, reason = _cut(inp, orb, over, limit)
    kept = _last_impact(orb) if reason else inp.impacts
    spec = _spec(inp, kept)
    tols = generate.row_tolerances(spec, orb)
    # the sticking-decision rule: a row's tolerance is set by the rows before it, so the first decision in
    # doubt within its row's tolerances ends the case there (that impact's decision is then not asked)
    doubt = doubtful_decision(spec, orb, tols.values["tau"], tols.values["sdot"])
    if doubt is not None:
        kept, reason = doubt[0], doubt[1]
        orb = _prefix(orb, kept)
        spec = _spec(inp, kept)
        tols = generate.row_tolerances(spec, orb)
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
    text = generate.expected_csv(orb, tols)
    settings = generate.settings_json(spec, orb, tols)
    settings["level"], settings["catches"] = _level_and_catches(spec, orb)
    radii = generate.radius_stats(text, orb)
    radii.pop("_rows")
    prov = generate.provenance_json(spec, orb, radii, None)
    prov["generator"] = "gear-rattle case"
    return UserCase(inp, settings, text, prov, truncation)


def _has_graze(spec: generate.Spec, orb: cert.CertifiedOrbit) -> bool:
    """Whether a contact reached by a flight against the pull of the force (``s'' = f - beta s'`` points away
    from the wall) is slower than :data:`GRAZE_SPEED`."""
    p = spec.params
    for e in orb.events:
        if e.kind != "impact" or (e.n == 0 and spec.s0 is None):
            continue
        v = cert.nearest_float(e.sdot)
        acc = generate.forcing_in(p, cert.nearest_float(e.tau), 0) - p.beta * v
        if (acc < 0 if e.wall == 0 else acc > 0) and abs(v) < GRAZE_SPEED:
            return True
    return False


def _level_and_catches(spec: generate.Spec, orb: cert.CertifiedOrbit) -> tuple[int, list[str]]:
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


def write_user_case(suite: Path, case: UserCase, write: Callable[[Path, str], object] = generate.write_plain) -> Path:
    """Write ``suite/<id>/`` (settings.json, expected.csv, provenance.json) through ``write`` (the
    command line passes its atomic writer); returns the folder."""
    folder = Path(suite) / case.input.id
    generate.write_case(folder, case.settings, case.expected, case.provenance, write)
    return folder


#: The name a suite built with ``gear-rattle case`` gives itself in its index (until its user renames it).
USER_SUITE_NAME = "user suite (gear-rattle case)"


def index_text(suite: Path, overlay: dict[str, Path] | None = None) -> str:
    """The text of ``suite/index.json`` from its case folders (with ``overlay``, ``{"<id>/<file>": file}``:
    as it will be once those files are moved in, :func:`.catalog.build_index`), keeping every field an
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


def update_index(suite: Path, write: Callable[[Path, str], object] = generate.write_plain) -> Path:
    """Write ``suite/index.json`` (:func:`index_text`) through ``write``; returns its path."""
    path = Path(suite) / INDEX_NAME
    write(path, index_text(suite))
    return path
