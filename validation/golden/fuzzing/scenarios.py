"""The fuzzer's strategies (``gear-rattle fuzz``; docs/reference/golden_commands.md, "Fuzzing an implementation"): the
scenarios, what each draws and why, and the construction of an input from a drawn recipe.

A **scenario** (:class:`Scenario`, one object per hard place, in the registry :data:`SCENARIOS`) has a
name, a weight (how often it is drawn), ``why`` (the hard place it reaches: what an implementation gets
wrong there), its **draws** (the numbers it needs, each a distribution: :class:`Uniform`,
:class:`Choice`, ...) and its **build** (the numbers to an input, :class:`..oracle.inputs.CaseInput`, or
``None`` where the hard place does not exist for them, e.g. no switch of the first contact's wall to
graze).  A **recipe** is ``{"scenario": name, ...its numbers}``: :func:`draw_recipes` draws them with
Hypothesis (the seed reproduces them; each scenario draws from its own distributions, so restricting the
scenarios, or adding one to the registry, leaves the numbers of a scenario's recipes as they were), and
:func:`construct` builds the input by the recipe's scenario.

**The box** (:data:`BOX`, documented in docs/golden.md): the ranges of ``core.params.RANGES`` cut where the
model stays meaningful and a case tractable -- alpha up to 1e6, beta 1e-8 ... 1e4 (above, Eq. 3 is stiff:
an explicit integrator needs ~beta steps per unit of time), ``|gamma|`` up to 1e6, r 1e-6 ... 1; orbits of up
to 1000 impacts (the horizon rule of ``gear-rattle case`` truncates them honestly), flights up to the orbit
horizon ``core.horizons.T_MAX``, starts up to ``tau0 = 1e6``, and the sticking threshold ``stick_time``
log-uniform over ``1e-8 ... MAX_STICK_TIME`` half the time (else the default ``STICK_TIME``).  Most
scenarios draw the parameters from the paper's region (:data:`CORE`: where the hard places are dense and
the paper's figures lie); the ``wide-*`` scenarios from the whole box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from ....core.paper import PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS
from ....core.params import Params
from ....mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from ...extras import require
from ..rules.thresholds import release_lead_state, stick_ratio_sdot0
from ..oracle.inputs import CaseInput, case_input
from ..rules.decisions import forcing_in
from ..rules.near_miss import turning_gap

TWO_PI = 2.0 * math.pi
#: The paper's parameter sets (Figs. 2, 3 and 9-11): the ``paper`` scenario's, and the shrinker's targets.
PAPER_SETS = (PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS)


# ---------------------------------------------------------------------------------------------
# the distributions of the draws


def _num(x: float) -> str:
    """A number as the docs write it: 1e6, 1e-8, 0.2."""
    return f"{x:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


@dataclass(frozen=True)
class Uniform:
    """A number uniform in ``[lo, hi]`` (Hypothesis also tries the ends); ``log``: log-uniform (``0 < lo``);
    ``integer``: an integer (rounded down from the log-uniform float with ``log``)."""

    lo: float
    hi: float
    log: bool = False
    integer: bool = False

    def strategy(self, st):
        if self.integer and not self.log:
            return st.integers(int(self.lo), int(self.hi))
        if not self.log:
            return st.floats(self.lo, self.hi, allow_nan=False, allow_infinity=False)
        top = self.hi + 1 if self.integer else self.hi
        draw = st.floats(math.log10(self.lo), math.log10(top)).map(lambda e: 10.0**e)
        return draw.map(lambda x: min(int(self.hi), max(int(self.lo), int(x)))) if self.integer else draw

    def __str__(self) -> str:
        ends = (f"{int(self.lo)} ... {int(self.hi)}") if self.integer else f"{_num(self.lo)} ... {_num(self.hi)}"
        return ends + (" (log)" if self.log else "")


@dataclass(frozen=True)
class Choice:
    """One of ``values``, each as likely."""

    values: tuple

    def strategy(self, st):
        return st.sampled_from(self.values)

    def __str__(self) -> str:
        return " or ".join(_num(v) if isinstance(v, float) else str(v) for v in self.values)


@dataclass(frozen=True)
class OneOf:
    """One of the distributions ``options``, each as likely, then its value."""

    options: tuple

    def strategy(self, st):
        return st.one_of(*(o.strategy(st) for o in self.options))

    def __str__(self) -> str:
        return "either " + ", or ".join(str(o) for o in self.options) + " (as likely)"


Draw = Uniform | Choice | OneOf


# ---------------------------------------------------------------------------------------------
# the box


#: The paper's region (the fuzzer's box before issue 36): alpha, beta, gamma, r.  Most scenarios draw here:
#: the hard places (grazes, chatter, thresholds) are dense, the paper's figures lie inside.
CORE: dict[str, Draw] = {
    "alpha": Uniform(0.0, 4.0),
    "beta": Uniform(1e-3, 1.0, log=True),
    "gamma": Uniform(-1.5, 1.5),
    "r": Uniform(0.2, 1.0),
}
#: The whole box of the ``wide-*`` scenarios (``core.params.RANGES`` cut where the model stays meaningful and
#: a case tractable; docs/golden.md says why): alpha, beta, ``|gamma|`` (its sign drawn apart), r.
BOX: dict[str, Draw] = {
    "alpha": Uniform(1e-3, 1e6, log=True),
    "beta": Uniform(1e-8, 1e4, log=True),
    "gamma": Uniform(1e-6, 1e6, log=True),
    "r": Uniform(1e-6, 1.0, log=True),
}
#: The sticking threshold: the default half the time, else log-uniform up to the library's limit (below
#: ~1e-7 a chatter's slowest bounces reach the horizon rule's limit before it sticks).
STICK: Draw = OneOf((Choice((STICK_TIME,)), Uniform(1e-8, MAX_STICK_TIME, log=True)))
#: Impacts of most cases, and of the ``long-orbit`` scenario.
IMPACTS, LONG_IMPACTS = Uniform(1, 40, integer=True), Uniform(100, 1000, log=True, integer=True)
#: A pre-impact start: phase, wall (the sign of sdot0), speed.
START: dict[str, Draw] = {
    "tau0": Uniform(0.0, TWO_PI),
    "sign": Choice((1.0, -1.0)),
    "speed": Uniform(1e-2, 3.0, log=True),
}
#: The chatter and sticking scenarios' parameters: a force pressing into the wall (``|gamma|`` 0.3 ... 1.8 of
#: the wall's sign), r 0.3 ... 0.9, the phase ``frac`` of the way through the pressing arc.
PRESSING: dict[str, Draw] = {
    "alpha": CORE["alpha"],
    "beta": CORE["beta"],
    "press": Uniform(0.3, 1.8),
    "r": Uniform(0.3, 0.9),
    "frac": Uniform(0.0, 1.0),
}


# ---------------------------------------------------------------------------------------------
# numbers and helpers of the constructions


def _g(x: float, digits: int = 6) -> float:
    """``x`` to ``digits`` significant digits (the numbers a person would type); below 1e-9 in magnitude 0
    (Hypothesis likes the smallest doubles)."""
    return 0.0 if abs(x) < 1e-9 else float(f"{x:.{digits}g}")


def _params(g: dict) -> tuple[float, float, float, float]:
    """``alpha, beta, gamma, r`` of a recipe drawn over :data:`CORE`, rounded (beta at least 1e-3)."""
    return _g(g["alpha"], 4), max(_g(g["beta"], 3), 1e-3), _g(g["gamma"], 4), _g(g["r"], 3)


def _wide_params(g: dict) -> tuple[float, float, float, float]:
    """``alpha, beta, gamma, r`` of a recipe drawn over :data:`BOX` (``gsign``: gamma's sign), rounded."""
    return _g(g["alpha"], 4), _g(g["beta"], 3), g["gsign"] * _g(g["gamma"], 4), _g(g["r"], 3)


def velocity_scale(p: Params) -> float:
    """The speeds of the model at ``p``, at least 1: the gear's velocity amplitude ``alpha``, the speed
    ``sqrt(2 |gamma|)`` a constant force gives across the backlash, and ``beta`` (a free flight of speed
    ``u`` goes ``u / beta`` far); the wide scenarios scale their speeds by it."""
    return max(1.0, p.alpha, math.sqrt(2.0 * abs(p.gamma)), p.beta)


def _input(id: str, p: Params | tuple, tau0: float, sdot0: float, g: dict, s0: float | None = None):
    """The validated input of parameters ``p`` (a :class:`Params` or ``alpha, beta, gamma, r``), with the
    recipe's impacts and sticking threshold (``None`` where a number is out of the inputs' ranges)."""
    alpha, beta, gamma, r = (p.alpha, p.beta, p.gamma, p.r) if isinstance(p, Params) else p
    try:
        st = _g(g["stick_time"], 3)
        return case_input(id, alpha, beta, gamma, r, tau0, sdot0, g["impacts"], s0=s0, stick_time=st)
    except ValueError:
        return None


#: Largest ``beta`` times the longest flight of a ``wide-*`` input (the orbit of the map track): Eq. (3) is stiff
#: where that is large -- an explicit integrator needs ~``beta`` steps per unit of time -- and such an orbit
#: took our scipy track minutes (beta = 3010, alpha = 0.0126, gamma = -0.029: a first flight of 781 time
#: units, 189 s; diffrax 55 s).  Not drawn: docs/reference/golden_commands.md, "What it cannot reach".
STIFFNESS_LIMIT = 1e4


def stiff(inp: CaseInput) -> bool:
    """Whether a flight of the input's orbit (the map track's) lasts longer than ``STIFFNESS_LIMIT / beta``."""
    from ....mapimpl.orbit import map_orbit

    seq = map_orbit(inp.params, inp.tau0, inp.sdot0, inp.impacts, s0=inp.s0, progress=False, stick_time=inp.stick_time)
    taus = [inp.tau0, *seq.tau.tolist()] if inp.s0 is not None else seq.tau.tolist()
    longest = max((b - a for a, b in zip(taus, taus[1:])), default=0.0)
    return inp.params.beta * longest > STIFFNESS_LIMIT


def _tractable(inp: CaseInput | None) -> CaseInput | None:
    """``inp`` unless it is :func:`stiff` (or ``None``)."""
    return None if inp is None or stiff(inp) else inp


_FIRST: list[Callable] = []  # the jitted first-impact finder, compiled on first use


def first_contact(p: Params, tau0: float, sdot0: float) -> tuple[int, float, float] | None:
    """``(wall, flight time, pre-impact sdot)`` of the first contact after the pre-impact state (the map
    track's certified finder, compiled once); ``None`` where no wall is reached."""
    if not _FIRST:
        import jax

        from ....mapimpl.finder import first_impact

        _FIRST.append(jax.jit(first_impact))
    start = 0.0 if sdot0 > 0 else -1.0
    h = _FIRST[0](math.fmod(tau0, TWO_PI) % TWO_PI, start, -p.r * sdot0, p.alpha, p.beta, p.gamma)
    if int(h.status) not in (0, 1):
        return None
    return int(h.wall), float(h.t), float(h.v)


def threshold(p: Params, tau0: float, sign: float, scale: float = 1.0, steps: int = 18) -> tuple[float, float] | None:
    """``(miss, reach)``: adjacent ``sdot0`` (one sign) at which the first flight from the wall of that
    sign does not reach the other wall and does: a scan of ``steps`` speeds ``scale`` times 0.01 1.4^k (18:
    0.01 ... 3.4), then bisection."""
    other = -1 if sign > 0 else 0

    def reach(s):
        c = first_contact(p, tau0, s)
        return c is not None and c[0] == other

    speeds = [sign * scale * 0.01 * 1.4**k for k in range(steps)]
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


def pressing_phase(p: Params, wall: int, frac: float) -> float | None:
    """A phase where the force presses into ``wall`` (``f > 0`` on s = 0, ``< 0`` on s = -1), ``frac`` of the
    way through the pressing arc sampled on a grid; ``None`` where it never presses."""
    taus = [TWO_PI * k / 256 for k in range(256)]
    ok = [t for t in taus if forcing_in(p, t, wall) > 0]
    return ok[min(len(ok) - 1, int(frac * len(ok)))] if ok else None


def graze_sdot0(
    p: Params, tau0: float, sign: float, target: float, scale: float = 1.0, steps: int = 18
) -> float | None:
    """A pre-impact ``sdot0`` whose first flight just reaches the other wall, at a normal speed of about
    ``target`` (the speed grows like the square root of the offset from the threshold: bisection on it);
    ``scale``, ``steps``: the scan of :func:`threshold`."""
    th = threshold(p, tau0, sign, scale, steps)
    if th is None:
        return None
    miss, reach = th
    other = -1 if sign > 0 else 0
    lo, hi = reach, reach + 0.5 * (reach - miss) / abs(reach - miss) * 1e-1 * scale
    c = first_contact(p, tau0, hi)
    if c is None or abs(c[2]) < target:
        return None
    for _ in range(60):
        m = 0.5 * (lo + hi)
        c = first_contact(p, tau0, m)
        if c is not None and c[0] == other and abs(c[2]) >= target:
            hi = m
        else:
            lo = m
    return float(f"{hi:.15g}")


def near_miss_sdot0(p: Params, tau0: float, sign: float, depth: float) -> float | None:
    """A pre-impact ``sdot0`` whose first flight turns back about ``depth`` short of the other wall (the
    closest approach grows linearly with the offset from the threshold: measured at 1e-6, scaled)."""
    th = threshold(p, tau0, sign)
    if th is None:
        return None
    miss, reach = th
    probe = miss + math.copysign(1e-6, miss - reach)
    c = first_contact(p, tau0, probe)
    if c is None:
        return None
    turn = turning_gap(p, math.fmod(tau0, TWO_PI) % TWO_PI, -p.r * probe, 0.0 if probe > 0 else -1.0, c[1])
    if not 0 < turn < 1:
        return None
    return float(f"{miss + math.copysign(depth * 1e-6 / turn, miss - reach):.17g}")


# ---------------------------------------------------------------------------------------------
# the constructions, one per scenario (``build(recipe, id) -> CaseInput | None``)


def _generic(g: dict, id: str) -> CaseInput | None:
    return _input(id, _params(g), _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), g)


def _paper(g: dict, id: str) -> CaseInput | None:
    q = PAPER_SETS[g["paper"]]
    return _input(id, (q.alpha, q.beta, q.gamma, q.r), _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), g)


def _free_flight(g: dict, id: str) -> CaseInput | None:
    sdot0 = _g(g["sign"] * g["speed"] * g["slow"], 3)
    return _input(id, _params(g), _g(g["tau0"], 4), sdot0, g, s0=_g(g["s0"], 3))


def _elastic(g: dict, id: str) -> CaseInput | None:
    alpha, beta, gamma, _ = _params(g)
    return _input(id, (alpha, beta, gamma, 1.0), _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), g)


def _small_beta(g: dict, id: str) -> CaseInput | None:
    alpha, _, gamma, r = _params(g)
    return _input(id, (alpha, _g(g["small"], 2), gamma, r), _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), g)


def _negative_gamma(g: dict, id: str) -> CaseInput | None:
    alpha, beta, gamma, r = _params(g)
    return _input(id, (alpha, beta, -abs(gamma) or -0.1, r), _g(g["tau0"], 4), -_g(g["speed"], 4), g)


def _graze_params(g: dict) -> Params:
    """The drawn parameters, or a paper set (``paper`` 1 or 2: Fig. 3, Figs. 9-11)."""
    return PAPER_SETS[g["paper"]] if g["paper"] > 0 else Params(*_params(g))


def _graze(g: dict, id: str) -> CaseInput | None:
    p, tau0 = _graze_params(g), _g(g["tau0"], 4)
    sdot0 = graze_sdot0(p, tau0, g["sign"], g["target"])
    return None if sdot0 is None else _input(id, p, tau0, sdot0, g)


def _near_miss(g: dict, id: str) -> CaseInput | None:
    p, tau0 = _graze_params(g), _g(g["tau0"], 4)
    sdot0 = near_miss_sdot0(p, tau0, g["sign"], g["depth"])
    return None if sdot0 is None else _input(id, p, tau0, sdot0, g)


def _pressing(g: dict, wall: int) -> Params:
    """Parameters whose force presses into ``wall`` somewhere (``press``: |gamma| with the wall's sign)."""
    gamma = (1 if wall == 0 else -1) * _g(g["press"], 3)
    return Params(_g(g["alpha"], 4), max(_g(g["beta"], 3), 1e-3), gamma, _g(g["r"], 3))


def _chatter(wall: int | None) -> Callable[[dict, str], CaseInput | None]:
    """A slow impact where the force presses into ``wall`` (``None``: the wall of the drawn sign): the
    bounces accumulate, the tooth sticks and is released."""

    def build(g: dict, id: str) -> CaseInput | None:
        w = wall if wall is not None else (0 if g["sign"] > 0 else -1)
        p = _pressing(g, w)
        phase = pressing_phase(p, w, g["frac"])
        if phase is None:
            return None
        return _input(id, p, phase, (1 if w == 0 else -1) * _g(g["speed"], 3), g)

    return build


def _stick_threshold(g: dict, id: str) -> CaseInput | None:
    """``t_acc / stick_time = 1 +- near1`` at impact 0: the threshold is where a scaled one shows."""
    wall = 0 if g["sign"] > 0 else -1
    p = _pressing(g, wall)
    phase = pressing_phase(p, wall, g["frac"])
    if phase is None:
        return None
    st = _g(g["stick_time"], 3)
    ratio = (1.0 + g["side"] * _g(g["near1"], 2)) * st / STICK_TIME  # stick_ratio_sdot0 scales STICK_TIME
    return _input(id, p, phase, stick_ratio_sdot0(p, phase, wall, ratio), g)


def _release_delay(g: dict, id: str) -> CaseInput | None:
    """An impact ``lead`` before the force stops pressing whose ``t_acc`` (at most ``stick_time``) is longer."""
    wall = 0 if g["sign"] > 0 else -1
    p = _pressing(g, wall)
    if abs(p.gamma) >= p.alpha * math.hypot(1.0, p.beta):
        return None
    st = _g(g["stick_time"], 3)
    lead = _g(g["lead"] * st, 2)
    tau0, sdot0 = release_lead_state(p, wall, lead, _g(min(st, lead * g["excess"]), 2))
    return _input(id, p, tau0, sdot0, g)


def _stuck_forever(g: dict, id: str) -> CaseInput | None:
    """``|gamma|`` just above ``R = alpha sqrt(1 + beta^2)``: the force never stops pressing."""
    alpha, beta, _, _ = _params(g)
    gamma = g["sign"] * _g(alpha * math.hypot(1.0, beta) * (1.0 + g["excess"]) + 1e-3, 4)
    sdot0 = math.copysign(_g(g["speed"], 4), gamma)
    return _input(id, (alpha, beta, gamma, _g(g["r"], 3)), _g(g["tau0"], 4), sdot0, g)


def _no_impact(g: dict, id: str) -> CaseInput | None:
    """``gamma = 0``, a weak force: a flight that never lands (half the time after a slow start where the
    force presses: chatter, stick, release, then no landing)."""
    p = Params(_g(g["weak"], 3), _g(0.1 + g["beta"], 3), 0.0, _g(g["r"], 3))
    tau0, sdot0 = _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4)
    if g["slow"]:
        wall = 0 if g["sign"] > 0 else -1
        phase = pressing_phase(p, wall, g["frac"])
        if phase is None:
            return None
        tau0, sdot0 = phase, g["sign"] * _g(g["speed"] / 30, 3)
    return _input(id, p, tau0, sdot0, g)


def _wide_generic(g: dict, id: str) -> CaseInput | None:
    """Any parameters of the box, a start at any phase up to ``tau0 = 1e6``, speeds scaled to the model's."""
    p = _wide_params(g)
    sdot0 = _g(g["sign"] * g["speed"] * velocity_scale(Params(*p)), 4)
    return _tractable(_input(id, p, _g(g["tau0"], 6), sdot0, g))


def _wide_graze(g: dict, id: str) -> CaseInput | None:
    """A graze at parameters of the box, its speeds scaled to the model's."""
    p, tau0 = Params(*_wide_params(g)), _g(g["tau0"], 4)
    scale = velocity_scale(p)
    # post-impact speeds 1e-4 ... 7e3 times the model's (a scan of 40 speeds): where it lies varies most here
    sdot0 = graze_sdot0(p, tau0, g["sign"], g["target"] * scale, 0.01 * scale / p.r, 40)
    return None if sdot0 is None else _tractable(_input(id, p, tau0, sdot0, g))


def _wide_chatter(g: dict, id: str) -> CaseInput | None:
    """A slow impact where the force of parameters of the box presses into the wall of the drawn sign."""
    wall = 0 if g["sign"] > 0 else -1
    alpha, beta, gamma, r = _wide_params(g)
    p = Params(alpha, beta, (1 if wall == 0 else -1) * abs(gamma), r)
    phase = pressing_phase(p, wall, g["frac"])
    if phase is None:
        return None
    return _tractable(_input(id, p, phase, (1 if wall == 0 else -1) * _g(g["speed"] * velocity_scale(p), 3), g))


def _long_flight(g: dict, id: str) -> CaseInput | None:
    """A flight of about ``t_flight`` (10 ... 1950) to the other wall: post-impact speed ``u = push /
    t_flight`` and the constant force ``gamma = 2 (1 - push) / t_flight^2`` towards it (weak alpha, beta)."""
    t, push = g["t_flight"], g["push"]
    sign = g["sign"]  # the start wall: + upper (the flight goes down), - lower (it goes up)
    gamma = -sign * _g(2.0 * (1.0 - push) / t**2, 3)
    p = (_g(g["weak"], 2), _g(g["damp"], 2), gamma, _g(g["r"], 3))
    sdot0 = _g(sign * push / (t * p[3]), 4)  # post-impact speed r |sdot0| = push / t
    return _input(id, p, _g(g["tau0"], 4), sdot0, g)


def _long_orbit(g: dict, id: str) -> CaseInput | None:
    """Hundreds of impacts from the paper's region or a paper set (``paper`` 0: the drawn parameters)."""
    p = PAPER_SETS[g["paper"] - 1] if g["paper"] > 0 else Params(*_params(g))
    return _input(id, p, _g(g["tau0"], 4), _g(g["sign"] * g["speed"], 4), g)


# ---------------------------------------------------------------------------------------------
# the registry


@dataclass(frozen=True)
class Scenario:
    """One scenario: ``name`` (``--scenarios``), ``weight`` (drawn in proportion), ``why`` (the hard place it
    reaches and what an implementation gets wrong there), ``draws`` (the recipe's numbers, each a
    distribution) and ``build`` (a recipe to an input, ``None`` where its hard place does not exist)."""

    name: str
    weight: int
    why: str
    draws: dict
    build: Callable[[dict, str], CaseInput | None]

    def strategy(self, st):
        """The Hypothesis strategy of this scenario's recipes."""
        numbers = {k: d.strategy(st) for k, d in self.draws.items()}
        return st.fixed_dictionaries({"scenario": st.just(self.name), **numbers})


def _draws(*parts: dict, **more: Draw) -> dict:
    """A scenario's draws: the parts, then its own numbers; every scenario draws ``impacts`` and ``stick_time``
    (given in ``more`` to override)."""
    out: dict = {}
    for d in parts:
        out.update(d)
    return {**out, "impacts": IMPACTS, "stick_time": STICK, **more}


_GRAZE_PAPER = Uniform(0, 2, integer=True)  # 0: the drawn parameters; 1, 2: Fig. 3, Figs. 9-11
_WIDE_START = {"gsign": Choice((1.0, -1.0)), "tau0": Uniform(0.0, TWO_PI), "sign": START["sign"]}

#: The scenarios, by name (docs/reference/golden_commands.md, "Fuzzing an implementation", lists them with these words).
SCENARIOS: dict[str, Scenario] = {
    s.name: s
    for s in (
        Scenario(
            "generic", 3, "any orbit of the paper's region: the common path, chaos", _draws(CORE, START), _generic
        ),
        Scenario(
            "paper",
            2,
            "the paper's parameter sets (Figs. 2, 3, 9-11) from any start",
            _draws(START, paper=Uniform(0, len(PAPER_SETS) - 1, integer=True)),
            _paper,
        ),
        Scenario(
            "free-flight",
            2,
            "a start in free flight (s0 between the walls, any sdot0 including slow ones): the first impact "
            "searched from inside",
            _draws(CORE, START, s0=Uniform(-0.95, -0.05), slow=Uniform(0.0, 1.0)),
            _free_flight,
        ),
        Scenario(
            "graze",
            3,
            "a first flight that just reaches the other wall (normal speed 1e-4 ... 3e-2, by bisection on sdot0): "
            "a finder with a step or a sign test misses it",
            _draws(CORE, START, paper=_GRAZE_PAPER, target=Uniform(1e-4, 3e-2, log=True)),
            _graze,
        ),
        Scenario(
            "near-miss",
            3,
            "a first flight that turns back 3e-13 ... 1e-7 short of the other wall: a contact tolerance takes "
            "it for an impact",
            _draws(CORE, START, paper=_GRAZE_PAPER, depth=Uniform(3e-13, 1e-7, log=True)),
            _near_miss,
        ),
        Scenario(
            "chatter-upper",
            2,
            "a slow impact on s = 0 where the force presses: bounces accumulate, the tooth sticks and is released",
            _draws(PRESSING, speed=Uniform(1e-2 / 30, 0.1, log=True)),
            _chatter(0),
        ),
        Scenario(
            "chatter-lower",
            2,
            "the same on s = -1 (the signs of the lower wall's pressing, sticking and release)",
            _draws(PRESSING, speed=Uniform(1e-2 / 30, 0.1, log=True)),
            _chatter(-1),
        ),
        Scenario(
            "stick-threshold",
            2,
            "an impact whose accumulation time is stick_time (1 +- 1e-4 ... 0.1), at the default threshold or "
            "another: t_acc or the threshold scaled shows",
            _draws(PRESSING, sign=START["sign"], side=Choice((1.0, -1.0)), near1=Uniform(1e-4, 0.1, log=True)),
            _stick_threshold,
        ),
        Scenario(
            "release-delay",
            2,
            "an impact just before the force stops pressing (1e-2 ... 0.5 stick_time) whose t_acc is longer: "
            "the policy's release test",
            _draws(PRESSING, sign=START["sign"], lead=Uniform(1e-2, 0.5, log=True), excess=Uniform(1.0, 3.0)),
            _release_delay,
        ),
        Scenario(
            "elastic-r1",
            1,
            "r = 1: nothing accumulates, never sticks (a division by 1 - r)",
            _draws(CORE, START),
            _elastic,
        ),
        Scenario(
            "small-beta",
            1,
            "beta 1e-8 ... 1: the closed form's (1 - exp(-beta t)) / beta cancels",
            _draws(CORE, START, small=Uniform(1e-8, 1.0, log=True)),
            _small_beta,
        ),
        Scenario(
            "negative-gamma",
            1,
            "gamma < 0 and a start on s = -1: the mirrored signs",
            _draws(CORE, START),
            _negative_gamma,
        ),
        Scenario(
            "stuck-forever",
            2,
            "gamma of a magnitude just above alpha sqrt(1 + beta^2): the force never stops pressing, the orbit ends stuck",
            _draws(CORE, START, r=Uniform(0.3, 0.8), excess=Uniform(0.0, 0.05)),
            _stuck_forever,
        ),
        Scenario(
            "no-impact",
            2,
            "gamma = 0 and a weak force: a flight that never lands (the orbit ends no_impact), half the time "
            "after a chatter, stick and release",
            _draws(
                START,
                weak=Uniform(0.02, 0.32),
                beta=CORE["beta"],
                r=Uniform(0.3, 0.9),
                slow=Choice((False, True)),
                frac=Uniform(0.0, 1.0),
            ),
            _no_impact,
        ),
        Scenario(
            "wide-generic",
            2,
            "any parameters of the whole box (alpha to 1e6, beta 1e-8 ... 1e4, gamma to +-1e6, r down to 1e-6), any "
            "phase up to tau0 = 1e6: flights of 1e-3 time units or of hundreds, speeds of 1e6, heavy damping",
            _draws(
                BOX,
                _WIDE_START,
                tau0=OneOf((Uniform(0.0, TWO_PI), Uniform(10.0, 1e6, log=True))),
                speed=Uniform(1e-2, 3.0, log=True),
            ),
            _wide_generic,
        ),
        Scenario(
            "wide-graze",
            1,
            "a graze at parameters of the whole box (its speeds scaled to the model's)",
            _draws(BOX, _WIDE_START, target=Uniform(1e-4, 3e-2, log=True)),
            _wide_graze,
        ),
        Scenario(
            "wide-chatter",
            2,
            "chatter and sticking at parameters of the whole box (tiny r, huge forces, heavy damping)",
            _draws(BOX, _WIDE_START, frac=Uniform(0.0, 1.0), speed=Uniform(1e-4, 1e-1, log=True)),
            _wide_chatter,
        ),
        Scenario(
            "long-orbit",
            2,
            "100 ... 1000 impacts (the horizon rule truncates a chaotic one): turn counters, repeated sticking, "
            "error accumulation",
            _draws(CORE, START, paper=Uniform(0, len(PAPER_SETS), integer=True), impacts=LONG_IMPACTS),
            _long_orbit,
        ),
        Scenario(
            "long-flight",
            2,
            "a flight of 10 ... 1950 time units (the orbit horizon T_MAX is 2000) under a weak force: a search "
            "with a short horizon, or coarse steps, misses its landing",
            _draws(
                START,
                t_flight=Uniform(10.0, 1950.0, log=True),
                push=Uniform(0.05, 1.0),
                weak=Uniform(1e-6, 1e-3, log=True),
                damp=Uniform(1e-8, 1e-4, log=True),
                r=Uniform(0.3, 1.0),
                impacts=Uniform(1, 6, integer=True),
            ),
            _long_flight,
        ),
    )
}


def check_scenarios(names) -> list[str]:
    """``names`` as a list of registered scenario names; ``ValueError`` naming the first unknown one and the
    allowed names (one line)."""
    names = list(names)
    for n in names:
        if n not in SCENARIOS:
            raise ValueError(f"scenario {n!r} is unknown: allowed {', '.join(sorted(SCENARIOS))}")
    if not names:
        raise ValueError(f"no scenario given: allowed {', '.join(sorted(SCENARIOS))}")
    return names


# ---------------------------------------------------------------------------------------------
# recipes and their inputs


def recipe_strategy(scenarios: list[str] | None = None):
    """The Hypothesis strategy of a recipe: ``{"scenario": name, ...its numbers}`` (``scenarios``: only these,
    default all of :data:`SCENARIOS`, drawn by their weights; each scenario's numbers from its own draws)."""
    # one line naming the extra where it is missing; importing hypothesis imports its strategies
    st = require("hypothesis", "test", "gear-rattle fuzz (the draws)").strategies
    names = sorted(check_scenarios(scenarios) if scenarios is not None else SCENARIOS)
    if len(names) == 1:
        return SCENARIOS[names[0]].strategy(st)
    weighted = [n for n in names for _ in range(SCENARIOS[n].weight)]
    return st.sampled_from(weighted).flatmap(lambda n: SCENARIOS[n].strategy(st))


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


def construct(recipe: dict, id: str) -> CaseInput | None:
    """The input of a recipe, built by its scenario (``None`` where the scenario's hard place does not exist
    for the drawn numbers, or they fall out of the inputs' ranges)."""
    return SCENARIOS[recipe["scenario"]].build(recipe, id)


def describe() -> list[str]:
    """The registry and the box as the lines docs/golden.md shows ("What it draws"; tests/test_scenarios.py
    checks that the page holds every one): a Markdown table row per scenario, then the box."""
    rows = ["| scenario | weight | the hard place it reaches |", "|---|---|---|"]
    rows += [f"| `{s.name}` | {s.weight} | {s.why} |" for s in SCENARIOS.values()]
    box = ", ".join(f"{k} {d}" for k, d in BOX.items())
    core = ", ".join(f"{k} {d}" for k, d in CORE.items())
    rows += [
        f"* the whole box (`wide-*`): {box} (gamma's sign drawn apart);",
        f"* the paper's region (the other scenarios): {core};",
        f"* `stick_time`: {STICK}; impacts {IMPACTS}, `long-orbit` {LONG_IMPACTS}.",
    ]
    return rows


__all__ = [
    "SCENARIOS",
    "Scenario",
    "BOX",
    "CORE",
    "STICK",
    "PAPER_SETS",
    "check_scenarios",
    "recipe_strategy",
    "draw_recipes",
    "construct",
    "first_contact",
    "threshold",
    "pressing_phase",
    "velocity_scale",
    "stiff",
    "STIFFNESS_LIMIT",
    "describe",
]
