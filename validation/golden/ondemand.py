"""A golden case for any input (``gear-rattle case``; docs/golden.md, "Asking the oracle").

:func:`build_user_case` certifies the orbit of one input (:func:`mapimpl.certified.certify_orbit`, or
:func:`mapimpl.certified.certify_no_impact_orbit` where the last flight never lands) and sets its
tolerances by every rule of docs/golden.md: the case's own 1e-9 (:data:`generate.TOL`), the graze rule
(:func:`graze_tolerance`: ``GAP_BUDGET / v`` at every contact reached against the pull of the force), the
chatter rule (:func:`generate.chatter_tolerance`) and the amplification rule
(:func:`generate.with_amplification_rule`).

**The horizon rule** (the chaotic horizon, generalised): no generated case has a tolerance of
:data:`TOLERANCE_LIMIT` (1e-6) or more in any column.  Where the rules would give one -- the error of a
correct float64 implementation, amplified along the orbit, at a graze or down a chatter, is too large --
the case stops at the last impact whose rows keep every tolerance below the limit, and says so
(``notes.truncation`` of its settings, and :attr:`UserCase.message`).  Every rule is monotone in the
length of the case (a maximum over more rows, a minimum speed over more impacts), so the longest such
prefix is found by bisection.  Why 1e-6: an impact time (or velocity) off by 1e-6 then fails every
generated case at every row -- the promise docs/golden.md makes for its ordinary cases -- and every rule
keeps its safety factor 10 over the error of a correct implementation, so the case's tolerance is never
more than 10 times that error (rounded up to one digit): a wrong implementation whose error exceeds
the correct one's by more than that factor fails.  An impact that cannot be certified (a tangency the
balls cannot separate, a flight longer than ``T_MAX`` that is not proven to never land) ends the case
in the same way, at the last certified impact; so does a flight that turns back closer to a wall than
:data:`NEAR_MISS_SAFETY` times the gap error of a correct implementation (:func:`near_miss_limit`: it may
take such a near miss for a contact).  A case does not ask a sticking decision that an output within its own
tolerances could take the other way either: it stops at that impact (the sticking-decision rule,
:func:`decisions.doubtful_decision`).

:func:`build_user_cases` builds many (``--from FILE``: one process, the JAX functions of the
amplification rule compiled once), :func:`write_user_case` writes a folder and :func:`update_index`
the suite's ``index.json`` (its other fields kept).
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from dataclasses import dataclass, replace
from collections.abc import Callable
from pathlib import Path

from ...core.checks import check_int, check_real
from ...core.horizons import T_MAX
from ...core.params import PARAM_NAMES, RANGES, Params, check_value
from ...mapimpl import certified as cert
from ...mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from . import generate
from .catalog import INDEX_NAME, build_index
from .conditioning import round_up_1
from .contacts import GAP_BUDGET
from .decisions import doubtful_decision

#: Every tolerance of a generated case lies below this (module docstring).
TOLERANCE_LIMIT = 1e-6
#: Impacts a case may ask for, and the first length certified (doubled until the case is decided).
MAX_CASE_IMPACTS, FIRST_CHUNK = 100_000, 64
#: The largest |tau0| and |sdot0| of an input (the command line's ranges, :func:`cliutil.tau0_type`).
TAU0_MAX, SDOT0_MAX = 1e6, 1e6
#: A case id: a folder name (letters, digits, ``.``, ``_``, ``-``; not starting with ``.``).
ID_PATTERN = re.compile(r"[A-Za-z0-9_][A-Za-z0-9._-]{0,99}")
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


def _finite(name: str, value, lo: float | None = None, hi: float | None = None, allowed: str = "") -> float:
    """A number of an input (a decimal string from a CSV file is read as its float) checked by the one
    boundary helper, :func:`core.checks.check_real` (ValueError naming ``name`` and ``allowed``)."""
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise ValueError(f"{name}={value!r} is not a number: allowed {allowed}") from None
    return check_real(
        name, value, -math.inf if lo is None else lo, math.inf if hi is None else hi, allowed=allowed or None
    )


def case_input(id: str, alpha, beta, gamma, r, tau0, sdot0, impacts, s0=None, stick_time=None) -> CaseInput:
    """A validated :class:`CaseInput`; ``ValueError`` naming the field and its allowed range."""
    if not isinstance(id, str) or not ID_PATTERN.fullmatch(id):
        raise ValueError(
            f"id={id!r} is out of range: allowed a folder name of 1-100 letters, digits, '.', '_' "
            "or '-', not starting with '.' or '-'"
        )
    values = dict(zip(PARAM_NAMES, (alpha, beta, gamma, r)))
    for k, v in values.items():
        if isinstance(v, bool):
            raise ValueError(f"parameter {k}={v!r} is not a number: allowed {RANGES[k]} (finite)")
    params = Params(*(check_value(k, v) for k, v in values.items()))  # ValueError naming the parameter, range
    tau0 = _finite("tau0", tau0, -TAU0_MAX, TAU0_MAX, f"a finite number with |tau0| <= {TAU0_MAX:g}")
    sdot0 = _finite("sdot0", sdot0, -SDOT0_MAX, SDOT0_MAX, f"a finite number with |sdot0| <= {SDOT0_MAX:g}")
    if s0 is not None:
        s0 = _finite("s0", s0, allowed="-1 < s0 < 0 (a free-flight start strictly between the walls)")
        if not -1.0 < s0 < 0.0:
            raise ValueError(
                f"s0={s0!r} is out of range: allowed -1 < s0 < 0 (a free-flight start strictly between the walls)"
            )
    elif sdot0 == 0.0:
        raise ValueError(
            "sdot0=0.0 is out of range: a pre-impact start needs sdot0 != 0 (> 0: upper wall s = 0, "
            "< 0: lower wall s = -1); give s0 for a start in free flight"
        )
    n = check_int(
        "impacts",
        _finite("impacts", impacts, allowed=f"an integer 0 <= impacts <= {MAX_CASE_IMPACTS}"),
        0,
        MAX_CASE_IMPACTS,
    )
    st = (
        STICK_TIME
        if stick_time is None
        else _finite(
            "stick_time",
            stick_time,
            0.0,
            MAX_STICK_TIME,
            f"a finite number 0 <= stick_time <= {MAX_STICK_TIME:g} (mapimpl.sticking.MAX_STICK_TIME)",
        )
    )
    return CaseInput(id, params, tau0, sdot0, n, s0, st)


def _blank(v) -> bool:
    return v is None or (isinstance(v, str) and v.strip() == "")


def _from_mapping(entry: dict, where: str) -> CaseInput:
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: an input must be an object with the fields {', '.join(REQUIRED_FIELDS)}")
    unknown = sorted(set(entry) - set(REQUIRED_FIELDS) - set(OPTIONAL_FIELDS))
    if unknown:
        raise ValueError(
            f"{where}: unknown field(s) {', '.join(unknown)} (allowed: {', '.join(REQUIRED_FIELDS + OPTIONAL_FIELDS)})"
        )
    missing = [k for k in REQUIRED_FIELDS if _blank(entry.get(k))]
    if missing:
        raise ValueError(f"{where}: missing field(s) {', '.join(missing)}")
    opt = {k: (None if _blank(entry.get(k)) else entry[k]) for k in OPTIONAL_FIELDS}
    try:
        return case_input(str(entry["id"]).strip(), *(entry[k] for k in REQUIRED_FIELDS[1:]), **opt)
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None


def read_inputs(path: str | Path) -> list[CaseInput]:
    """The inputs of a ``--from`` file: a JSON list of objects, or a CSV with a header of the field
    names (:data:`REQUIRED_FIELDS`, optionally :data:`OPTIONAL_FIELDS`; an empty ``s0`` is a pre-impact
    start).  ``ValueError`` naming the file, the entry (or line) and the field; duplicate ids refused."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as e:
        raise ValueError(f"--from {path}: cannot read: {e.strerror or e}") from None
    except UnicodeDecodeError:
        raise ValueError(f"--from {path}: not UTF-8 text") from None
    out: list[CaseInput] = []
    if text.lstrip().startswith("["):
        try:
            data = json.loads(text)
        except json.JSONDecodeError as e:
            raise ValueError(f"--from {path}: line {e.lineno}: invalid JSON: {e.msg}") from None
        out = [_from_mapping(entry, f"--from {path}: entry {k}") for k, entry in enumerate(data)]
    else:
        rows = list(csv.reader(io.StringIO(text)))
        if not rows:
            raise ValueError(
                f"--from {path}: empty file (a CSV with the header {','.join(REQUIRED_FIELDS)}"
                "[,s0][,stick_time], or a JSON list)"
            )
        head = [h.strip() for h in rows[0]]
        for line, row in enumerate(rows[1:], start=2):
            if not any(c.strip() for c in row):
                continue
            if len(row) != len(head):
                raise ValueError(f"--from {path}: line {line}: {len(row)} fields, expected {len(head)}")
            out.append(_from_mapping(dict(zip(head, row)), f"--from {path}: line {line}"))
    if not out:
        raise ValueError(f"--from {path}: no inputs")
    seen: set[str] = set()
    for c in out:
        if c.id in seen:
            raise ValueError(f"--from {path}: duplicate id {c.id!r}")
        seen.add(c.id)
    return out


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


def graze_tolerance(spec: generate.Spec, orb: cert.CertifiedOrbit) -> tuple[float, str] | None:
    """The graze rule for any orbit: at every impact reached by a flight against the pull of the force
    (the acceleration ``s'' = f - beta s'`` points away from the wall: the flight was turning back, its
    un-reset continuation leaves the wall after a short excursion) the tolerance ``GAP_BUDGET / v`` at the
    impact speed ``v``, rounded up to one digit; the largest, with its note, where it exceeds the case's
    own 1e-9 (``None`` otherwise).  A contact reached with the force pressing is a chatter bounce: the
    chatter rule's."""
    p, worst = spec.params, None
    for e in orb.events:
        if e.kind != "impact" or (e.n == 0 and spec.s0 is None):
            continue
        v = cert.nearest_float(e.sdot)
        acc = generate.forcing_in(p, cert.nearest_float(e.tau), 0) - p.beta * v
        away = acc < 0 if e.wall == 0 else acc > 0
        if away and v != 0 and (worst is None or abs(v) < abs(worst[1])):
            worst = (e.n, v, e.wall)
    if worst is None:
        return None
    t = round_up_1(GAP_BUDGET / abs(worst[1]))
    if t <= generate.TOL["tau"]["abs"]:
        return None
    return t, (
        f"graze: the slowest contact against the pull of the force, impact {worst[0]} (wall {worst[2]}), "
        f"speed {abs(worst[1]):.4g}: {GAP_BUDGET:g} / v = {GAP_BUDGET / abs(worst[1]):.3g}, rounded up to one "
        "digit (docs/golden.md, grazes and near misses)"
    )


def ruled_spec(spec: generate.Spec, orb: cert.CertifiedOrbit) -> generate.Spec:
    """``spec`` with the tolerances of every rule on ``orb`` (its own, graze, chatter, amplification)."""
    g = graze_tolerance(spec, orb)
    if g is not None:
        spec = replace(spec, tolerances=generate.tol(g[0]), notes={**spec.notes, "graze_rule": g[1]})
    return generate.with_amplification_rule(generate.with_chatter_rule(spec, orb), orb)


#: A flight that turns back closer to a wall than this many times the gap error ``e`` of a correct float64
#: implementation (:func:`conditioning.local_error`: ``2^-52 + 1e-12 h``) may be taken for a contact by one: a
#: case stops before the impact that ends such a flight (the near-miss rule; the shipped near misses lie at
#: 20 000 e, 1000 e and 9.9 e).
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
    import numpy as np

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
    from .conditioning import POSITION_STEP, FLIGHT_ERROR, flight_height

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
            e = POSITION_STEP + FLIGHT_ERROR * flight_height(p, start[0], start[1], dt)
            if gap < NEAR_MISS_SAFETY * e:
                return int(rows.n[i]), (
                    f"the flight to impact {int(rows.n[i])} turns back {gap:.3g} from a wall, "
                    f"within {NEAR_MISS_SAFETY:g} times the gap error {e:.3g} of a correct float64 "
                    "implementation (it may take it for a contact)"
                )
        prev, start = i, None
    return None


def _loosest(spec: generate.Spec) -> float:
    return max(v["abs"] for v in spec.tolerances.values())


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


def _certify(inp: CaseInput, n: int, prec: int) -> tuple[cert.CertifiedOrbit | None, str]:
    """``(orbit, why it ends early)``: the certified orbit of ``n`` impacts; where a flight cannot be
    certified, the longest certified prefix (``why``: the impact and the reason), with the ``no_impact``
    ending where the flight after it is proven never to land.  ``None`` where not even impact 0 is certified.

    One mechanism decides how far and at what precision: the certified track's schedule
    (:func:`mapimpl.certified.track.certified_orbit`, from ``prec`` bits up, raised by itself up to its limit).
    The case's balls are then those of :func:`mapimpl.certified.certify_orbit` at the precision the schedule
    settled on, for the impacts it certified (the generator's orbit, with its flight certificates and its
    radius limit)."""
    from ...mapimpl.certified.track import certified_orbit

    run = certified_orbit(
        inp.params, inp.tau0, inp.sdot0, n, s0=inp.s0, stick_time=inp.stick_time, prec=prec, progress=False
    )
    last = run.impacts_certified - 1
    kw = dict(
        s0=inp.s0,
        prec=run.precision,
        stick_time=inp.stick_time,
        radius_limit=generate.RADIUS_FRACTION * generate.TOL["tau"]["abs"],
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


def build_user_case(inp: CaseInput, prec: int = cert.PREC) -> UserCase:
    """Certify ``inp``, set its tolerances by every rule and apply the horizon rule (module docstring).
    Raises :class:`CaseError` where no prefix of the orbit is certified within the limit."""
    n = min(inp.impacts, FIRST_CHUNK)
    while True:
        orb, why = _certify(inp, n, prec)
        if orb is None:
            raise CaseError(f"case {inp.id}: impact 0 is not certified: {why}")
        ruled = ruled_spec(_spec(inp, inp.impacts), orb)
        over = _loosest(ruled) >= TOLERANCE_LIMIT
        if over or why or orb.status != "active" or n >= inp.impacts:
            break
        n = min(2 * n, inp.impacts)
    reason = ""
    miss = near_miss_limit(_spec(inp, inp.impacts), orb)
    if miss is not None:
        if miss[0] == 0:
            raise CaseError(f"case {inp.id}: {miss[1]} (no impact before it)")
        orb, why = _prefix(orb, miss[0] - 1), miss[1]
        ruled = ruled_spec(_spec(inp, inp.impacts), orb)
        over = _loosest(ruled) >= TOLERANCE_LIMIT
    if over:
        last = _last_impact(orb)
        lo, hi = -1, last  # prefix lo within the limit (-1: none), the whole orbit (hi) over it
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _loosest(ruled_spec(_spec(inp, mid), _prefix(orb, mid))) < TOLERANCE_LIMIT:
                lo = mid
            else:
                hi = mid
        bad = ruled_spec(_spec(inp, hi), _prefix(orb, hi) if hi < last or orb.status == "active" else orb)
        cols = ", ".join(f"{c} {v['abs']:g}" for c, v in bad.tolerances.items() if c != "tau_mod_2pi")
        rules = [k for k in ("graze_rule", "tolerance_rule") if k in bad.notes]
        rules += ["amplification"] if bad.notes["amplification"]["sets"] else []
        where = bad.notes["amplification"]
        reason = (
            f"with impact {hi} the tolerance of a correct float64 implementation would be {cols} (rules: "
            f"{', '.join(rules)}; amplified tau error {where['tau_error']:.3g} at {where['tau_worst']}), not "
            f"below the limit {TOLERANCE_LIMIT:g}"
        )
        if lo < 0:
            raise CaseError(f"case {inp.id}: {reason} (no impact within the limit)")
        orb = _prefix(orb, lo)
    elif why:
        reason = why
    kept = _last_impact(orb) if reason else inp.impacts
    # the rules do not depend on the length asked for: the orbit's spec serves unless it was cut since
    spec = replace(ruled, n_impacts=kept) if not over else ruled_spec(_spec(inp, kept), orb)
    doubt = doubtful_decision(spec, orb)
    if doubt is not None:  # the sticking-decision rule: the longest prefix whose decisions are clear
        kept, reason = _clear_prefix(inp, orb, doubt, _last_impact(orb))
        orb = _prefix(orb, kept)
        spec = ruled_spec(_spec(inp, kept), orb)
    truncation = None
    if reason:
        truncation = {
            "requested_impacts": inp.impacts,
            "kept_impacts": kept,
            "limit": TOLERANCE_LIMIT,
            "reason": reason,
            "rule": f"the case stops at the last impact whose rows keep every tolerance below "
            f"{TOLERANCE_LIMIT:g}, or at the last certified impact (docs/golden.md, asking the "
            "oracle)",
        }
        spec = replace(spec, tags=spec.tags + ("truncated",), notes={**spec.notes, "truncation": truncation})
    text = generate.expected_csv(orb)
    settings = generate.settings_json(spec, orb)
    settings["level"], settings["catches"] = _level_and_catches(spec, orb)
    radii = generate.radius_stats(text, orb)
    radii.pop("_rows")
    prov = generate.provenance_json(spec, orb, radii, None)
    prov["generator"] = "gear-rattle case"
    return UserCase(inp, settings, text, prov, truncation)


def _clear_prefix(inp: CaseInput, orb: cert.CertifiedOrbit, doubt: tuple[int, str], hi: int) -> tuple[int, str]:
    """The longest prefix ``doubt[0] <= k <= hi`` (``hi``: the orbit's last impact) of ``orb`` whose asked
    sticking decisions are clear under its own tolerances (:func:`decisions.doubtful_decision`), and the note
    of the decision that ends it.  Prefix ``doubt[0]`` is clear (its tolerances are at most the whole case's,
    under which every decision before that impact was), the whole orbit is not, and a longer prefix has
    larger tolerances and more decisions: bisection.  (With a tolerance per row, set by the rows before it,
    the first doubt would be final.)"""
    lo, note = doubt
    while hi - lo > 1:
        mid = (lo + hi) // 2
        d = doubtful_decision(ruled_spec(_spec(inp, mid), _prefix(orb, mid)), _prefix(orb, mid))
        if d is None:
            lo = mid
        else:
            hi, note = mid, d[1]
    return lo, note


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
    if "graze_rule" in spec.notes:
        catches.append("skipped-graze")
    level = 3 if (orb.status == "no_impact" or "graze_rule" in spec.notes) else (2 if "stick" in kinds else 1)
    return level, catches


def build_user_cases(inputs: list[CaseInput], progress=None) -> list[UserCase | CaseError]:
    """:func:`build_user_case` for each input (a :class:`CaseError` in place of a case that cannot be
    built); ``progress(done, total)`` after each."""
    out: list[UserCase | CaseError] = []
    for k, inp in enumerate(inputs):
        try:
            out.append(build_user_case(inp))
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


def update_index(suite: Path, write: Callable[[Path, str], object] = generate.write_plain) -> Path:
    """Write ``suite/index.json`` from its case folders, keeping every field an existing index has beside
    the case list (a suite version, a changelog ...) and adding the standard ones it lacks."""
    path = Path(suite) / INDEX_NAME
    old: dict = {}
    if path.is_file():
        try:
            old = json.loads(path.read_text())
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}: line {e.lineno}: invalid JSON: {e.msg} (not updated)") from None
        if not isinstance(old, dict):
            raise ValueError(f"{path}: not a JSON object (not updated)")
    fresh = build_index(Path(suite))
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
    write(path, json.dumps(merged, indent=1) + "\n")
    return path
