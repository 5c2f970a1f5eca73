"""Mutation test of the golden suite (issue 21): deliberately wrong implementations must fail
``gear-rattle check``, and every case added for issue 21 (0013-0025) is needed by some mutant.

The implementations are :mod:`golden_mutants` (tests/golden_mutants.py): a small implementation
written from docs/golden.md around the map track's certified finder, and mutants of it with one
decision changed.  The base passes every case, so each failure below is its mutant's one change.
Mutants run only on the cases they target, except where a claim is about the old cases
(:func:`test_each_new_case_is_needed`: the mutant passes all of 0001-0012).  Correct variants must pass every
case: the position held as the float64 ``s`` or ``s + 1`` (the chatter rule admits them), and every contact
displaced by the per-impact error the amplification rule assumes (docs/golden.md).
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.catalog import contacts
from gear_rattle.validation.golden.formats.index import BUG_CLASSES
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import case_ids, load_case, read_sequence
from gear_rattle.validation.golden.scoring.cases import circular_distance
from golden_mutants import BASE, Mutant, run, write_csv

CASES = case_ids()
#: The cases before issue 21, and those it added.
OLD = [c for c in CASES if int(c[:4]) <= 12]
NEW = [c for c in CASES if int(c[:4]) >= 13]


def _settings(cid: str) -> dict:
    return json.loads((DEFAULT_SUITE / cid / "settings.json").read_text())


def _case(prefix: str) -> str:
    return next(c for c in CASES if c.startswith(prefix))


def _check(m: Mutant, cases: list[str], out, capsys) -> dict[str, bool]:
    """Write the mutant's files for ``cases`` into ``out`` and score them with ``gear-rattle check``;
    returns {case: passed} read from its table (exit status 0 iff all pass, else 1)."""
    out.mkdir(parents=True, exist_ok=True)
    for cid in cases:
        write_csv(run(_settings(cid), m), out / f"{cid}.csv", m)
    capsys.readouterr()
    rc = main(["check", str(out), "--cases", *cases])
    table = capsys.readouterr().out.splitlines()[3 : 3 + len(cases)]  # after the suite line, header, rule
    verdict = {line.split()[0]: line.split()[1] == "PASS" for line in table}
    assert sorted(verdict) == sorted(cases)
    assert rc == (0 if all(verdict.values()) else 1)
    return verdict


#: name -> (mutant, the cases it must fail).  Each mutant is the base with one field changed.
MUTANTS = {
    "fixed-step-0.01": (Mutant("fixed-step-0.01", "skipped-graze", step=0.01), ["0020", "0021", "0022", "0023"]),
    "contact-tolerance-1e-8": (
        Mutant("contact-tolerance-1e-8", "contact-tolerance", contact_tol=1e-8),
        ["0024", "0025"],
    ),
    "contact-tolerance-1e-10": (Mutant("contact-tolerance-1e-10", "contact-tolerance", contact_tol=1e-10), ["0025"]),
    "no-lower-wall-sticking": (
        Mutant("no-lower-wall-sticking", "lower-wall-sticking", lower_wall_sticks=False),
        ["0013", "0014", "0019"],
    ),
    "lower-wall-pressing-sign": (
        Mutant("lower-wall-pressing-sign", "lower-wall-sticking", lower_sign=1.0),
        ["0013", "0014", "0019"],
    ),
    "lower-wall-release-branch": (
        Mutant("lower-wall-release-branch", "lower-wall-sticking", lower_branch=False),
        ["0013", "0019"],
    ),
    "never-release-tested-on-upper-side": (
        Mutant("never-release-tested-on-upper-side", "stuck-forever", never_on_pressing_side=False),
        ["0014"],
    ),
    "release-delay-ignored": (Mutant("release-delay-ignored", "release-delay", delay_check=False), ["0017"]),
    "stick-threshold-x0.99": (Mutant("stick-threshold-x0.99", "sticking-threshold", stick_scale=0.99), ["0018"]),
    "stick-threshold-x1.01": (Mutant("stick-threshold-x1.01", "sticking-threshold", stick_scale=1.01), ["0019"]),
    "stick-threshold-x1.5": (Mutant("stick-threshold-x1.5", "sticking-threshold", stick_scale=1.5), ["0019"]),
    "r1-safe-division": (Mutant("r1-safe-division", "elastic-r1", t_acc_if_no_loss=0.0), ["0016"]),
    "spurious-row-after-release": (
        Mutant("spurious-row-after-release", "release-departure", redetect_after_release=True),
        ["0007", "0012", "0013"],
    ),
    "row-at-search-horizon": (Mutant("row-at-search-horizon", "no-impact-ending", row_at_horizon=True), ["0015"]),
    "rows-dropped-before-no-impact": (
        Mutant("rows-dropped-before-no-impact", "no-impact-ending", drop_rows_if_no_landing=True),
        ["0015"],
    ),
    "trailing-rows": (Mutant("trailing-rows", "trailing-rows", trailing_rows=True), ["0013"]),
    "phase-1e17": (Mutant("phase-1e17", "phase-column", phase_value=1e17), ["0001", "0013"]),
    "phase-1e300": (Mutant("phase-1e300", "phase-column", phase_value=1e300), ["0001", "0013"]),
    "phase-largest-double": (
        Mutant("phase-largest-double", "phase-column", phase_value=sys.float_info.max),
        ["0001", "0013"],
    ),
}

#: A new case -> the mutant that needs it (passes every old case, fails this one).  The graze cases
#: 0020-0023 get fixed-step finders with a step that misses only that graze
#: (:func:`_only_missed_step`).
NEEDS = {
    "0013": "no-lower-wall-sticking",
    "0014": "never-release-tested-on-upper-side",
    "0015": "row-at-search-horizon",
    "0016": "r1-safe-division",
    "0017": "release-delay-ignored",
    "0018": "stick-threshold-x0.99",
    "0019": "stick-threshold-x1.01",
    "0024": "contact-tolerance-1e-8",
    "0025": "contact-tolerance-1e-10",
}
GRAZES = ["0020", "0021", "0022", "0023"]


def test_base_implementation_passes_every_case(tmp_path, capsys):
    """The unmutated implementation passes all cases: the mutants' failures are their one change."""
    verdict = _check(BASE, CASES, tmp_path / "base", capsys)
    assert all(verdict.values()), [c for c, ok in verdict.items() if not ok]


#: Correct variants, not mutants: the position held as the float64 ``s`` or ``s + 1``, the contact where
#: it reaches the wall's value (:func:`golden_mutants.rounded_coordinate_contact`).  Near the wall where the
#: coordinate is near -1 or 1 its rounding step is 2^-53, so a bounce of speed v lands up to 2^-54 / v early,
#: and a chatter adds these up: the chatter rule of the tolerances (docs/golden.md) must admit both.
#: The gap-error variants displace every contact by the per-impact error of the amplification rule
#: (:func:`golden_mutants.displaced_contact`), all late (first order: as all early) or with pseudo-random signs.
VARIANTS = {
    "s-coordinates": Mutant("s-coordinates", coordinate=0.0),
    "s+1-coordinates": Mutant("s+1-coordinates", coordinate=1.0),
    "gap-error-late": Mutant("gap-error-late", gap_error="late"),
    "gap-error-random": Mutant("gap-error-random", gap_error="random"),
}


@pytest.mark.parametrize("name", VARIANTS)
def test_correct_variant_passes_every_case(name, tmp_path, capsys):
    verdict = _check(VARIANTS[name], CASES, tmp_path / name, capsys)
    assert all(verdict.values()), [c for c, ok in verdict.items() if not ok]


def _max_tau_error(m: Mutant, cid: str) -> float:
    exp = read_sequence(DEFAULT_SUITE / cid / "expected.csv")
    got = np.array([row[1] for row in run(_settings(cid), m)])
    assert got.size == len(exp)
    return float(np.max(np.abs(got - exp.tau)))


def test_rounded_coordinates_need_the_chatter_rule():
    """The variants are not vacuous: where the coordinate is coarse at the chattering wall, their impact
    times are off by more than the 1e-9 the chatter cases had before the rule (0015: bounces down to 1.3e-8
    on s = 0, measured 4.2e-8 in s + 1; 0008: 1.9e-9), and by far less where it is fine (s at s = 0)."""
    up, down = VARIANTS["s+1-coordinates"], VARIANTS["s-coordinates"]
    assert _max_tau_error(up, _case("0015")) > 1e-8
    assert _max_tau_error(up, _case("0008")) > 1e-9
    assert _max_tau_error(down, _case("0014")) > 1e-10  # s at s = -1 (measured 6.3e-10)
    assert _max_tau_error(down, _case("0015")) < 1e-13


def _largest_share(m: Mutant, cid: str) -> float:
    """The largest ``|error| / tolerance`` over the rows and columns of ``m``'s output on case ``cid``, each row
    against its own tolerance (inf for other events)."""
    case = load_case(DEFAULT_SUITE / cid)
    rows = run(_settings(cid), m)
    if len(rows) != len(case.expected):
        return math.inf
    got = {
        "tau": [r[1] for r in rows],
        "tau_mod_2pi": [r[1] % (2 * math.pi) for r in rows],
        "sdot": [r[3] for r in rows],
    }
    share = 0.0
    for c, x in got.items():
        g = getattr(case.expected, c)
        err = circular_distance(np.array(x), g) if c == "tau_mod_2pi" else np.abs(np.array(x) - g)
        share = max(share, float(np.max(np.where(np.isnan(g), 0.0, err / case.row_tolerances(c)[0]))))
    return share


#: The share of every row's tolerance the gap-error variants use: the modelled error at every contact, so 1 /
#: SAFETY to first order, plus their base finder's own error and second-order terms (measured <= 0.1012,
#: 0024 late: its finder's error is 0.0034 of that row's tolerance).
VARIANT_SHARE = 0.1 * 1.03


@pytest.mark.parametrize("name", ["gap-error-late", "gap-error-random"])
def test_a_correct_implementation_uses_a_tenth_of_every_row(name):
    """The promise of docs/golden_tolerances.md, row by row: an implementation that makes the modelled error of a correct
    float64 implementation at every contact (one sign, or pseudo-random signs) uses 1/10 of the tolerance of
    every row of every case (with the 2-digit rounding up, at least 0.091 on each case's tightest row)."""
    for cid in CASES:
        share = _largest_share(VARIANTS[name], cid)
        assert 0.08 < share <= VARIANT_SHARE, (cid, share)


def test_twelve_times_the_error_of_a_correct_implementation_fails():
    """The other side: the same variant with twelve times the modelled error (ten times, and the rounding of
    the tolerances up to 2 digits) fails every case but 0025, whose 4 rows' tolerances are mostly the
    representation of tau (measured: 24 of 25 fail; shares 1.07 ... 1.20)."""
    m = Mutant("gap-error-x12", gap_error="random", gap_scale=12.0)
    passed = [cid[:4] for cid in CASES if _largest_share(m, cid) <= 1.0]
    assert passed == ["0025"], passed


@pytest.mark.parametrize("name", MUTANTS)
def test_mutant_fails_check(name, tmp_path, capsys):
    m, targets = MUTANTS[name]
    assert m.bug_class in BUG_CLASSES or m.bug_class == "phase-column"
    cases = [_case(t) for t in targets]
    verdict = _check(m, cases, tmp_path / name, capsys)
    assert not any(verdict.values()), f"{name} passes {[c for c, ok in verdict.items() if ok]}"


def _excursions() -> dict[str, tuple[float, float]]:
    """The certified excursions (settings notes) of the graze cases 0020-0023."""
    out = {}
    for g in GRAZES:
        e = _settings(_case(g))["notes"]["excursion"]
        out[g] = (e["t_enter"], e["t_exit"])
    return out


def _only_missed_step(graze: str) -> float:
    """A step in [1e-3, 1] whose fixed-step finder catches every graze but ``graze`` (the middle of
    the first interval of such steps)."""
    exc = _excursions()
    others = contacts.steps_catching_all([exc[g] for g in GRAZES if g != graze])
    own = contacts.steps_that_catch(*exc[graze])
    for lo, hi in others:
        h = 0.5 * (lo + hi)
        if not any(a <= h <= b for a, b in own):
            return h
    raise AssertionError(f"no step misses only {graze}")


@pytest.mark.parametrize("new", [c[:4] for c in NEW])
def test_each_new_case_is_needed(new, tmp_path, capsys):
    """Each case added for issue 21 is needed: some mutant passes every old case (0001-0012) and fails it
    (for a graze: a fixed-step finder that misses that graze and catches the three others)."""
    if new in GRAZES:
        h = _only_missed_step(new)
        m = Mutant(f"fixed-step-{h:.12g}", "skipped-graze", step=h)
        also = [_case(g) for g in GRAZES if g != new]  # ... and passes the other graze cases
    else:
        m, also = MUTANTS[NEEDS[new]][0], []
    verdict = _check(m, OLD + also + [_case(new)], tmp_path / "needs", capsys)
    assert not verdict[_case(new)], f"{m.name} passes {new}"
    assert all(ok for c, ok in verdict.items() if c != _case(new)), (
        f"{m.name} fails {[c for c, ok in verdict.items() if not ok and c != _case(new)]}"
    )
    assert m.bug_class in _settings(_case(new))["catches"]


def test_graze_excursions_defeat_every_fixed_step_finder():
    """The certified excursions of 0020-0023 are shorter than 1e-4, and no step h in [1e-3, 1] puts a
    sample k h (k >= 1) inside all four (the sets of catching steps, as intervals, have an empty
    intersection): every fixed-step sign-change finder in that range misses one of them.  Each graze
    is necessary: without it, some step catches the other three."""
    exc = _excursions()
    assert all(0 < b - a < 1e-4 for a, b in exc.values())
    assert contacts.steps_catching_all(list(exc.values()), 1e-3, 1.0) == []
    for g in GRAZES:
        assert contacts.steps_catching_all([exc[k] for k in GRAZES if k != g], 1e-3, 1.0)


def test_steps_that_catch_an_excursion():
    """The interval arithmetic of the coverage claim against a brute-force sample of steps."""
    a, b = 1.2345, 1.2345 + 4e-5
    iv = contacts.steps_that_catch(a, b, 1e-3, 1.0)
    for h in np.geomspace(1e-3, 1.0, 20001):
        k = np.arange(1, int(b / h) + 2)
        caught = bool(np.any((k * h >= a) & (k * h <= b)))
        assert caught == any(lo <= h <= hi for lo, hi in iv), h
    with pytest.raises(ValueError, match="excursion"):
        contacts.steps_that_catch(2.0, 1.0)


#: Steps of the sweep: log-spaced over [1e-3, 1] plus the ends.
SWEEP = sorted(set(np.geomspace(1e-3, 1.0, 25).tolist()) | {1e-3, 1.0})


def test_fixed_step_finder_fails_over_the_step_range(tmp_path, capsys):
    """A sweep of the fixed-step mutant over [1e-3, 1]: every step fails at least one graze case
    (the proof for every step is test_graze_excursions_defeat_every_fixed_step_finder)."""
    grazes = [_case(g) for g in GRAZES]
    for k, h in enumerate(SWEEP):
        verdict = _check(Mutant("fixed-step", "skipped-graze", step=h), grazes, tmp_path / f"h{k}", capsys)
        assert not all(verdict.values()), f"step {h} passes every graze case"


def test_case_catches_lists_match_the_mutants():
    """Every new case's 'catches' names bug classes of the catalogue, and each mutant's bug class is
    listed by the cases it targets (the table of bug classes x cases in docs/golden.md)."""
    for cid in CASES:
        s = _settings(cid)
        assert s["catches"] and set(s["catches"]) <= set(BUG_CLASSES), cid
        assert s["level"] in (1, 2, 3)
    for name, (m, targets) in MUTANTS.items():
        if m.bug_class == "phase-column":
            continue
        assert any(m.bug_class in _settings(_case(t))["catches"] for t in targets), name


def test_mutants_are_small():
    """Each mutant differs from the base in exactly one decision (one field of Mutant)."""
    fields = [f for f in BASE.__dataclass_fields__ if f not in ("name", "bug_class")]
    for name, (m, _) in MUTANTS.items():
        changed = [
            f
            for f in fields
            if getattr(m, f) != getattr(BASE, f)
            and not (isinstance(getattr(m, f), float) and math.isnan(getattr(m, f)))
        ]
        assert len(changed) == 1, (name, changed)
