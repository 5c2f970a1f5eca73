"""A differential fuzzer: another implementation against certified cases on demand (``gear-rattle fuzz``;
docs/golden.md, "Fuzzing an implementation").

The protocol: the implementation is a command ``COMMAND CASES_DIR OUT_DIR`` that runs every case folder of
CASES_DIR (``settings.json`` in the suite's layout; no ``expected.csv``) and writes
``OUT_DIR/<case-id>.csv`` -- as it runs the shipped suite.  The fuzzer

1. draws *recipes* with Hypothesis (:func:`recipe_strategy`, reproducible by the seed): a scenario that
   reaches a hard place on purpose (:data:`SCENARIOS`: grazes and near misses built as the suite's generator
   builds them, by bisection on ``sdot0`` at the first contact's switch of wall; chatter and sticking on
   both walls; sticking thresholds; release delays; ``r = 1``; small ``beta``; negative ``gamma``;
   free-flight starts; orbits that end stuck or with ``no_impact``; chaotic and generic orbits) and its
   numbers, from which :func:`construct` builds an input;
2. builds each input's certified case (:func:`ondemand.build_user_case`: every tolerance rule and the
   horizon rule of ``gear-rattle case``);
3. runs the implementation on a batch of cases (one process per batch), with a timeout;
4. scores every output with the suite's scorer (:func:`suite.score_file`);
5. shrinks each failing input (:func:`shrink`: fewer impacts, simpler numbers, the paper's parameters; each
   round of candidates one more batch) and writes the smallest failing case, a golden-format folder, to the
   output directory.

An implementation that exits with an error, outlives the timeout, or writes a missing or malformed file
is a :class:`ImplementationError` (one line): the fuzzer stops with it.
"""

from __future__ import annotations

import json
import math
import shlex
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

from ...core.paper import PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS
from ...core.params import PARAM_NAMES, Params
from ..extras import require
from . import generate, ondemand
from .ondemand import CaseError, CaseInput, UserCase
from .suite import MalformedFile, load_case, score_file

#: The scenarios a recipe starts from (the hard places of docs/golden.md), each with its weight.
SCENARIOS: dict[str, int] = {
    "generic": 3,
    "paper": 2,
    "free-flight": 2,
    "graze": 3,
    "near-miss": 3,
    "chatter-upper": 2,
    "chatter-lower": 2,
    "stick-threshold": 2,
    "release-delay": 2,
    "elastic-r1": 1,
    "small-beta": 1,
    "negative-gamma": 1,
    "stuck-forever": 2,
    "no-impact": 2,
}
#: The parameter box of the draws: the documented ranges (core.params.RANGES) cut to where the model's
#: behaviour changes (the paper's figures lie inside).
ALPHA, BETA, GAMMA, R = (0.0, 4.0), (1e-8, 1.0), (-1.5, 1.5), (0.2, 1.0)
#: Impacts of a drawn case.
IMPACTS = (1, 40)
#: Cases per batch (one process of the implementation each), seconds a batch may take by default.
BATCH, TIMEOUT = 24, 300.0
#: Seconds the shrinking of one failure may take (it usually stops earlier: no simpler candidate fails);
#: at most the budget.
SHRINK_TIME = 90.0
#: The paper's parameter sets, targets of the shrinker (Figs. 2, 3 and 9-11).
PAPER_SETS = (PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS)
TWO_PI = 2.0 * math.pi


class ImplementationError(Exception):
    """The implementation crashed, timed out, or wrote a missing or malformed file (one line)."""


# ---------------------------------------------------------------------------------------------
# recipes and their inputs


def recipe_strategy(scenarios: list[str] | None = None):
    """The Hypothesis strategy of a recipe: ``{"scenario": name, ...its numbers}`` (``scenarios``: only these,
    default all of :data:`SCENARIOS`, drawn by their weights)."""
    import importlib

    require("hypothesis", "test", "gear-rattle fuzz (the draws)")  # one line naming the extra where it is missing
    st = importlib.import_module("hypothesis.strategies")

    def fl(lo, hi):
        return st.floats(lo, hi, allow_nan=False, allow_infinity=False)

    def logf(lo, hi):
        return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)

    common = {
        "alpha": fl(*ALPHA),
        "beta": logf(1e-3, BETA[1]),
        "gamma": fl(*GAMMA),
        "r": fl(*R),
        "tau0": fl(0.0, TWO_PI),
        "impacts": st.integers(*IMPACTS),
        "sign": st.sampled_from([1.0, -1.0]),
        "speed": logf(1e-2, 3.0),
        "s0": fl(-0.95, -0.05),
        "paper": st.integers(0, len(PAPER_SETS) - 1),
        "depth": logf(1.5e-11, 1e-7),
        "ratio": fl(0.9, 1.1),
        "near1": logf(1e-4, 0.1),
        "lead": logf(1e-8, 5e-7),
        "small": logf(*BETA),
    }
    names = sorted(scenarios or SCENARIOS)
    weighted = [n for n in names for _ in range(SCENARIOS[n])]
    return st.fixed_dictionaries({"scenario": st.sampled_from(weighted), **common})


#: Examples Hypothesis generates per recipe (the last is kept: its first ones are the simplest).
EXAMPLES_PER_RECIPE = 3


def draw_recipes(seed: int, count: int, scenarios: list[str] | None = None) -> list[dict]:
    """``count`` recipes drawn by Hypothesis from :func:`recipe_strategy`, recipe ``k`` with the random seed
    ``(seed, k)`` (the same seed gives the same recipes; one search per recipe: within one search Hypothesis
    mutates its earlier examples, which repeats numbers)."""
    hyp = require("hypothesis", "test", "gear-rattle fuzz (the draws)")
    strategy = recipe_strategy(scenarios)
    out: list[dict] = []
    for k in range(count):
        got: list[dict] = []

        @hyp.seed(seed * 1_000_003 + k)
        @hyp.settings(
            max_examples=EXAMPLES_PER_RECIPE,
            database=None,
            deadline=None,
            phases=[hyp.Phase.generate],
            derandomize=False,
            suppress_health_check=list(hyp.HealthCheck),
            print_blob=False,
        )
        @hyp.given(strategy)
        def collect(recipe):
            got.append(recipe)

        collect()
        out.append(got[-1])
    return out


def _g(x: float, digits: int = 6) -> float:
    """``x`` to ``digits`` significant digits (the numbers a person would type); below 1e-9 in magnitude 0
    (Hypothesis likes the smallest doubles)."""
    return 0.0 if abs(x) < 1e-9 else float(f"{x:.{digits}g}")


_FIRST: list[Callable] = []  # the jitted first-impact finder, compiled on first use


def first_contact(p: Params, tau0: float, sdot0: float) -> tuple[int, float, float] | None:
    """``(wall, flight time, pre-impact sdot)`` of the first contact after the pre-impact state (the map
    track's certified finder, compiled once); ``None`` where no wall is reached."""
    if not _FIRST:
        import jax

        from ...mapimpl.finder import first_impact

        _FIRST.append(jax.jit(first_impact))
    start = 0.0 if sdot0 > 0 else -1.0
    h = _FIRST[0](math.fmod(tau0, TWO_PI) % TWO_PI, start, -p.r * sdot0, p.alpha, p.beta, p.gamma)
    if int(h.status) not in (0, 1):
        return None
    return int(h.wall), float(h.t), float(h.v)


def _threshold(p: Params, tau0: float, sign: float) -> tuple[float, float] | None:
    """``(miss, reach)``: adjacent ``sdot0`` (one sign) at which the first flight from the wall of that
    sign does not reach the other wall and does: a scan of speeds 0.01 ... 4, then bisection."""
    other = -1 if sign > 0 else 0

    def reach(s):
        c = first_contact(p, tau0, s)
        return c is not None and c[0] == other

    speeds = [sign * 0.01 * 1.4**k for k in range(18)]
    hits = [reach(s) for s in speeds]
    for a, b, ha, hb in zip(speeds, speeds[1:], hits, hits[1:]):
        if ha != hb:
            lo, hi = (a, b) if hb else (b, a)  # reach(lo) false, reach(hi) true
            for _ in range(70):
                m = 0.5 * (lo + hi)
                if m in (lo, hi):
                    break
                if reach(m):
                    hi = m
                else:
                    lo = m
            return lo, hi
    return None


def _pressing_phase(p: Params, wall: int, frac: float) -> float | None:
    """A phase where the force presses into ``wall`` (``f > 0`` on s = 0, ``< 0`` on s = -1), ``frac`` of the
    way through the pressing arc sampled on a grid; ``None`` where it never presses."""
    taus = [TWO_PI * k / 256 for k in range(256)]
    ok = [t for t in taus if generate.forcing_in(p, t, wall) > 0]
    return ok[min(len(ok) - 1, int(frac * len(ok)))] if ok else None


def construct(recipe: dict, id: str) -> CaseInput | None:
    """The input of a recipe (``None`` where its scenario does not exist for the drawn numbers, e.g. no
    switch of the first contact's wall to graze)."""
    from ...mapimpl.sticking import STICK_TIME
    from .generate import release_lead_state, stick_ratio_sdot0

    k, g = recipe["scenario"], recipe
    alpha, beta, gamma, r = _g(g["alpha"], 4), max(_g(g["beta"], 3), 1e-3), _g(g["gamma"], 4), _g(g["r"], 3)
    tau0, sdot0, s0, n = _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), None, g["impacts"]
    if k == "paper":
        q = PAPER_SETS[g["paper"]]
        alpha, beta, gamma, r = q.alpha, q.beta, q.gamma, q.r
    elif k == "free-flight":
        s0, sdot0 = _g(g["s0"], 3), _g(g["sign"] * g["speed"] * (g["ratio"] - 0.9) * 5, 3)
    elif k == "elastic-r1":
        r = 1.0
    elif k == "small-beta":
        beta = _g(g["small"], 2)
    elif k == "negative-gamma":
        gamma, sdot0 = -abs(gamma) or -0.1, -abs(sdot0)
    elif k in ("chatter-upper", "chatter-lower", "stick-threshold", "release-delay"):
        wall = 0 if (k == "chatter-upper" or (k != "chatter-lower" and g["sign"] > 0)) else -1
        gamma = (1 if wall == 0 else -1) * _g(0.3 + abs(g["gamma"]), 3)
        r = _g(0.3 + 0.6 * (g["r"] - R[0]) / (R[1] - R[0]), 3)
        p = Params(alpha, beta, gamma, r)
        phase = _pressing_phase(p, wall, g["ratio"] - 0.9) if k != "release-delay" else None
        if k == "release-delay":
            if abs(gamma) >= p.alpha * math.hypot(1.0, beta):
                return None
            lead = _g(g["lead"], 2)
            tau0, sdot0 = release_lead_state(
                p, wall, lead, _g(min(STICK_TIME, lead * (1 + 10 * (g["ratio"] - 0.9))), 2)
            )
        elif phase is None:
            return None
        elif k == "stick-threshold":
            # t_acc / STICK_TIME = 1 +- 1e-4 ... 0.1 (log): the threshold is where a scaled one shows
            tau0 = phase
            sdot0 = stick_ratio_sdot0(p, tau0, wall, 1.0 + g["sign"] * _g(g["near1"], 2))
        else:
            tau0, sdot0 = phase, (1 if wall == 0 else -1) * _g(g["speed"] / 30, 3)
    elif k == "stuck-forever":
        gamma = g["sign"] * _g(alpha * math.hypot(1.0, beta) * (1.0 + 0.5 * (g["ratio"] - 0.9)) + 1e-3, 4)
        r = _g(0.3 + 0.5 * (g["r"] - R[0]) / (R[1] - R[0]), 3)
        sdot0 = math.copysign(abs(sdot0), gamma)
    elif k == "no-impact":
        gamma, alpha, beta = 0.0, _g(0.02 + 0.3 * alpha / ALPHA[1], 3), _g(0.1 + g["beta"], 3)
        r = _g(0.3 + 0.6 * (g["r"] - R[0]) / (R[1] - R[0]), 3)
        if g["paper"] == 0:  # a slow start where the force presses: chatter, stick, release, then no landing
            wall = 0 if g["sign"] > 0 else -1
            phase = _pressing_phase(Params(alpha, beta, gamma, r), wall, g["ratio"] - 0.9)
            if phase is None:
                return None
            tau0 = phase
            sdot0 = g["sign"] * _g(g["speed"] / 30, 3)
    elif k in ("graze", "near-miss"):
        if g["paper"] > 0:
            q = PAPER_SETS[g["paper"]]
            alpha, beta, gamma, r = q.alpha, q.beta, q.gamma, q.r
        p = Params(alpha, beta, gamma, r)
        th = _threshold(p, tau0, g["sign"])
        if th is None:
            return None
        miss, reach = th
        if k == "near-miss":  # the closest approach grows linearly with the offset: measured at 1e-6, scaled
            probe = miss + math.copysign(1e-6, miss - reach)
            c = first_contact(p, tau0, probe)
            if c is None:
                return None
            turn = ondemand._turns(p, math.fmod(tau0, TWO_PI) % TWO_PI, -p.r * probe, 0.0 if probe > 0 else -1.0, c[1])
            if not 0 < turn < 1:
                return None
            sdot0 = miss + math.copysign(g["depth"] * 1e-6 / turn, miss - reach)
        else:  # the speed at the grazed wall grows like sqrt(offset): the offset for a speed 1e-4 ... 3e-2
            target = 10.0 ** (-4 + 2.5 * (g["ratio"] - 0.9) / 0.2)
            lo, hi = reach, reach + 0.5 * (reach - miss) / abs(reach - miss) * 1e-1
            c = first_contact(p, tau0, hi)
            if c is None or abs(c[2]) < target:
                return None
            for _ in range(60):
                m = 0.5 * (lo + hi)
                c = first_contact(p, tau0, m)
                if c is not None and c[0] == (-1 if g["sign"] > 0 else 0) and abs(c[2]) >= target:
                    hi = m
                else:
                    lo = m
            sdot0 = float(f"{hi:.15g}")
        sdot0 = float(f"{sdot0:.17g}")
    try:
        return ondemand.case_input(id, alpha, beta, gamma, r, tau0, sdot0, n, s0=s0)
    except ValueError:
        return None


# ---------------------------------------------------------------------------------------------
# running the implementation


def split_command(command: str) -> list[str]:
    """``COMMAND`` as an argument list (shell words); ``ValueError`` when empty or unbalanced."""
    try:
        words = shlex.split(command)
    except ValueError as e:
        raise ValueError(f"--impl {command!r}: {e}") from None
    if not words:
        raise ValueError("--impl is empty: allowed a command, called as COMMAND CASES_DIR OUT_DIR")
    return words


def run_implementation(command: list[str], cases: list[UserCase], timeout: float, work: Path) -> dict:
    """Run the implementation once on ``cases`` (their settings only) and score each output with the suite's
    scorer; returns ``{id: CaseScore}``.  :class:`ImplementationError` on a crash, a timeout, or a missing
    or malformed file."""
    if work.exists():
        shutil.rmtree(work)
    given, ref, out = work / "cases", work / "reference", work / "out"
    out.mkdir(parents=True)
    for c in cases:
        (given / c.input.id).mkdir(parents=True)
        (given / c.input.id / "settings.json").write_text(json.dumps(c.settings, indent=1) + "\n")
        ondemand.write_user_case(ref, c)
    try:
        proc = subprocess.run(
            [*command, str(given), str(out)], capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL
        )
    except subprocess.TimeoutExpired:
        raise ImplementationError(
            f"the implementation did not finish {len(cases)} cases within {timeout:g} s (--timeout)"
        ) from None
    except OSError as e:
        raise ImplementationError(f"cannot start the implementation {command[0]!r}: {e.strerror or e}") from None
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout or "").strip().splitlines()
        raise ImplementationError(
            f"the implementation exited with status {proc.returncode} on {len(cases)} cases"
            + (f": {tail[-1][:300]}" if tail else "")
        )
    scores = {}
    for c in cases:
        try:
            sc = score_file(load_case(ref / c.input.id), out / f"{c.input.id}.csv")
        except MalformedFile as e:
            raise ImplementationError(f"malformed output: {' '.join(str(e).split())[:400]}") from None
        sc.message = sc.message.replace(str(out), "OUT_DIR")  # the batch's folder is temporary
        scores[c.input.id] = sc
    return scores


# ---------------------------------------------------------------------------------------------
# shrinking


def complexity(inp: CaseInput) -> tuple:
    """The order of the shrinker (smaller is simpler): impacts, then the significant digits of the numbers,
    then the parameters that differ from the nearest paper set."""
    nums = [inp.params.alpha, inp.params.beta, inp.params.gamma, inp.params.r, inp.tau0, inp.sdot0]
    nums += [] if inp.s0 is None else [inp.s0]
    digits = sum(_digits(x) for x in nums)
    off = min(sum(getattr(inp.params, k) != getattr(q, k) for k in PARAM_NAMES) for q in PAPER_SETS)
    return (inp.impacts, digits, off)


def _digits(x: float) -> int:
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
            c = ondemand.case_input(inp.id, **{**_fields(inp), **ch})
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
        for d in range(1, _digits(x)):
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
    """The impact index of the first failing row of a score (``None`` when not known)."""
    import csv

    rows = list(csv.DictReader(case.expected.splitlines()))
    line = None
    for c in score.columns.values():
        if not c.passed and c.first_row >= 0:
            line = c.first_row if line is None else min(line, c.first_row)
    if line is None and "line " in score.message:
        try:
            line = int(score.message.split("line ")[1].split()[0]) - 2
        except (ValueError, IndexError):
            return None
    return int(rows[min(line, len(rows) - 1)]["n"]) if line is not None and rows else None


@dataclass
class Failure:
    """A failing case found and shrunk."""

    case: UserCase
    message: str
    scenario: str
    found_after_s: float
    original: CaseInput
    shrink_rounds: int = 0
    folder: str = ""

    def summary(self) -> dict:
        return {
            "id": self.case.input.id,
            "folder": self.folder,
            "scenario": self.scenario,
            "message": self.message,
            "found_after_s": round(self.found_after_s, 2),
            "impacts": self.case.settings["n_impacts"],
            "rows": self.case.settings["expected_rows"],
            "input": self.case.input.as_dict(),
            "original_input": self.original.as_dict(),
            "shrink_rounds": self.shrink_rounds,
        }


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
            elif fields[k] == _fields(inp)[k] or _digits(v) < _digits(fields[k]):
                fields[k] = v
    try:
        m = ondemand.case_input(inp.id, **fields)
    except ValueError:
        return None
    return None if m in failing else m


def shrink(
    inp: CaseInput, case: UserCase, message: str, evaluate: Callable, fail_impact: int | None, deadline: float
) -> tuple[UserCase, str, int]:
    """The smallest failing case reachable by :func:`shrink_candidates` rounds, until no candidate fails or the
    deadline; returns ``(case, its failure message, rounds)``.  Each round runs every candidate of the current
    input in one batch, then (one more batch) all their failing changes at once; it keeps that merged input
    where it fails, else the simplest failing candidate (:func:`complexity`)."""
    rounds = 0
    while time.monotonic() < deadline:
        built = _build([replace(c, id=f"{inp.id}-s{k}") for k, c in enumerate(shrink_candidates(inp, fail_impact))])
        if not built:
            break
        scores = evaluate(built)
        failing = [b for b in built if not scores[b.input.id].passed]
        if not failing:
            break
        best = min(failing, key=lambda b: complexity(b.input))
        sc = scores[best.input.id]
        merged = _merged(replace(inp, id=f"{inp.id}-m"), [b.input for b in failing])
        if merged is not None and complexity(merged) < complexity(best.input) and time.monotonic() < deadline:
            mb = _build([merged])
            msc = evaluate(mb)[merged.id] if mb else None
            if msc is not None and not msc.passed:
                best, sc = mb[0], msc
        rounds += 1
        inp = replace(best.input, id=inp.id)
        case, message, fail_impact = _renamed(best, inp.id), sc.message, first_failing_impact(best, sc)
    return case, message, rounds


def _build(inputs: list[CaseInput]) -> list[UserCase]:
    """The cases of ``inputs`` that can be built (:func:`ondemand.build_user_case`)."""
    out = []
    for c in inputs:
        try:
            out.append(ondemand.build_user_case(c))
        except CaseError:
            continue
    return out


def _renamed(case: UserCase, id: str) -> UserCase:
    settings = {**case.settings, "id": id}
    return replace(case, input=replace(case.input, id=id), settings=settings, provenance={**case.provenance, "id": id})


# ---------------------------------------------------------------------------------------------
# the loop


@dataclass
class FuzzResult:
    """What a run found: ``failures`` (shrunk, written), the cases run, batches, scenarios drawn."""

    failures: list = field(default_factory=list)
    cases: int = 0
    batches: int = 0
    drawn: int = 0
    skipped: int = 0
    scenarios: dict = field(default_factory=dict)
    elapsed: float = 0.0
    error: str = ""


def fuzz(
    command: list[str],
    *,
    seed: int = 0,
    budget: float = 60.0,
    out: Path | None = None,
    keep_going: bool = False,
    timeout: float = TIMEOUT,
    batch: int = BATCH,
    scenarios: list[str] | None = None,
    progress: Callable | None = None,
    write: Callable[[Path, str], object] = generate.write_plain,
    written: Callable[[], object] | None = None,
) -> FuzzResult:
    """Fuzz the implementation ``command`` for ``budget`` seconds (module docstring); failures are written
    under ``out`` as golden-format case folders (``fuzz-<seed>-<k>``) with an ``index.json``.  Stops at the
    first failure (after shrinking it) unless ``keep_going``; ``progress(cases, failures)`` after each batch.
    The failing cases are written through ``write(path, text)`` and, after each, ``written()`` is called
    (the command line passes its atomic writer and the call that moves a found case into place at once).
    An :class:`ImplementationError` ends the run: ``result.error``."""
    t0 = time.monotonic()
    deadline = t0 + budget
    res = FuzzResult()
    allowed = scenarios or list(SCENARIOS)
    with tempfile.TemporaryDirectory(prefix="gear-rattle-fuzz-") as tmp:
        work = Path(tmp)

        def evaluate(cases: list[UserCase]) -> dict:
            res.batches += 1
            return run_implementation(command, cases, timeout, work / f"b{res.batches}")

        round_ = 0
        try:
            while time.monotonic() < deadline:
                recipes = draw_recipes(seed * 100_003 + round_, batch, allowed)
                round_ += 1
                cases: list[tuple[UserCase, str]] = []
                for rec in recipes:
                    if len(cases) >= batch or time.monotonic() >= deadline:
                        break
                    res.drawn += 1
                    inp = construct(rec, f"fuzz-{seed}-{res.drawn:06d}")
                    if inp is None:
                        res.skipped += 1
                        continue
                    try:
                        cases.append((ondemand.build_user_case(inp), rec["scenario"]))
                    except CaseError:
                        res.skipped += 1
                        continue
                    res.scenarios[rec["scenario"]] = res.scenarios.get(rec["scenario"], 0) + 1
                if not cases:
                    continue
                scores = evaluate([c for c, _ in cases])
                res.cases += len(cases)
                for c, scen in cases:
                    sc = scores[c.input.id]
                    if sc.passed:
                        continue
                    found = time.monotonic() - t0
                    shrunk, msg, rounds = shrink(
                        c.input,
                        c,
                        sc.message,
                        evaluate,
                        first_failing_impact(c, sc),
                        time.monotonic() + min(budget, SHRINK_TIME),
                    )
                    f = Failure(shrunk, msg, scen, found, c.input, rounds)
                    if out is not None:
                        f.folder = str(ondemand.write_user_case(out, _with_fuzz_notes(shrunk, f, seed), write))
                        if written is not None:
                            written()  # in place before the index lists and digests the folders
                        ondemand.update_index(out, write)
                        if written is not None:
                            written()
                    res.failures.append(f)
                    if not keep_going:
                        break
                if progress is not None:
                    progress(res.cases, len(res.failures))
                if res.failures and not keep_going:
                    break
        except ImplementationError as e:
            res.error = str(e)
    res.elapsed = time.monotonic() - t0
    return res


def _with_fuzz_notes(case: UserCase, f: Failure, seed: int) -> UserCase:
    """The case with ``notes.fuzz`` (how it was found) in its settings: a regression case to keep."""
    notes = {
        **case.settings["notes"],
        "fuzz": {
            "found_by": f"gear-rattle fuzz --seed {seed}",
            "scenario": f.scenario,
            "failure": f.message,
            "original_input": f.original.as_dict(),
            "shrink_rounds": f.shrink_rounds,
        },
    }
    settings = {**case.settings, "notes": notes, "tags": [*case.settings["tags"], "fuzz", f.scenario]}
    return replace(case, settings=settings)
