"""What is asked of the oracle (``gear-rattle case``; docs/reference/golden_commands.md, "Asking the oracle"): one input
(:class:`CaseInput`: parameters, start, impacts, sticking threshold), each field checked by the one boundary
helper of its kind (:func:`checked_fields`, :func:`case_input`), and the inputs of a ``--from`` file, CSV or
JSON, read with ``check``'s limits, every bad line named (:func:`read_input_file`).  :mod:`.ondemand`
answers them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ....core.checks import check_int, check_real
from ....core.params import PARAM_NAMES, RANGES, Params, check_value
from ....mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from ..boundary import MAX_CASE_IMPACTS, MAX_CASES, check_id, shown
from ..formats.csvformat import Record, check_header, split_line, text_lines
from ..formats.jsonformat import parse_json
from ..formats.textformat import MAX_BYTES, MalformedFile, position, read_text

#: The largest ``|tau0|`` and ``|sdot0|`` of an input (the command line's ranges, ``validation.cliutil.tau0_type``).
TAU0_MAX, SDOT0_MAX = 1e6, 1e6
#: Most inputs of a ``--from`` file (as many cases as a suite may hold).
MAX_INPUTS = MAX_CASES
#: The fields of an input (a ``--from`` file's columns or keys): required, then optional.
REQUIRED_FIELDS = ("id", *PARAM_NAMES, "tau0", "sdot0", "impacts")
#: The optional fields of an input (:data:`REQUIRED_FIELDS` are required).
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
