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

This module holds the draws (1); the runner, the shrinker and the triage are :mod:`.fuzz_runner`,
:mod:`.shrink` and :mod:`.triage` (a crash, a timeout, a missing or malformed file of one input is a
failure of that input, isolated from its batch, shrunk and kept like any other).
"""

from __future__ import annotations

import math
from typing import Callable

from ...core.paper import PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS
from ...core.params import Params
from ..extras import require
from . import generate, ondemand
from .ondemand import CaseInput

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
