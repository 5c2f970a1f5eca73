"""The model in balls: the parameters of Eq. (3) as ``arb`` balls and the closed-form flight.

The model is Eq. (3), ``s'' + beta s' = f(tau)``, ``f = -alpha sin tau + alpha beta cos tau + gamma``
(see ``docs/model.md``).  A flight leaving ``(tau0, s0, v0)`` is, with ``w0 = v0 - alpha cos tau0``,
``E = exp(-beta t)``, ``E1 = (1 - E)/beta`` and ``B = beta w0 - gamma``,

    s(t)    = s0 + 2 alpha cos(tau0 + t/2) sin(t/2) + w0 E1 + gamma (t - E1)/beta      (Eq. 7)
    s'(t)   = alpha cos(tau0 + t) + w0 E + gamma E1                                  (Eq. 8)
    s''(t)  = -alpha sin(tau0 + t) - B E,     s'''(t) = -alpha cos(tau0 + t) + beta B E,
    s''''(t) = alpha sin(tau0 + t) - beta^2 B E.

Every quantity is an ``arb`` ball at the current precision; the parameters are exact float64
numbers (a :class:`Params`) or exact decimals (``{"alpha": "1.245", ...}``, balls of radius
~2^-prec; :class:`Model`).
"""

from __future__ import annotations

from collections.abc import Mapping

from flint import arb

from ...core.checks import InputTypeError
from ...core.params import PARAM_NAMES, Params
from .balls import exact, span


def parameter_ball(name: str, value) -> arb:
    """A parameter as a ball at the current precision: a float is the exact binary number it holds,
    a string is the exact *decimal* it spells (``"1.245"``: a ball of radius ~2^-prec around
    1.245, which no float holds).  Validated with the ranges of :mod:`core.params`."""
    from ...core.params import RANGES, check_param, check_value

    if isinstance(value, str):
        text = value.strip()
        try:
            x = float(text)
        except ValueError:
            raise ValueError(f"parameter {name}={value!r} is not a decimal number: allowed {RANGES[name]}") from None
        check_value(name, x)
        ball = arb(text)
        if not ball.is_finite():
            raise ValueError(f"parameter {name}={value!r} is not a finite decimal number: allowed {RANGES[name]}")
        return ball
    return exact(check_param(name, value))


class Model:
    """Parameters as balls, with the forcing and its rate.

    ``params``: a :class:`Params` (float64 values, taken as exact binary numbers) or a mapping
    ``{"alpha": ..., "beta": ..., "gamma": ..., "r": ...}`` whose values are floats (exact) or
    decimal strings (exact decimals, e.g. ``{"alpha": "1.245", ...}``: the paper's printed values
    rather than their float64 roundings).  Build it inside :func:`precision`: string parameters
    are enclosed at the precision current at construction.  ``self.params`` holds the float64
    values (nearest) for messages and float64 code.
    """

    def __init__(self, params):
        if isinstance(params, Params):
            values = params.as_dict()
        else:
            if not isinstance(params, Mapping):
                raise InputTypeError(
                    f"params is a {type(params).__name__}: allowed a gear_rattle.Params or a mapping "
                    f"of {', '.join(PARAM_NAMES)} to floats or decimal strings"
                )
            values = dict(params)
            missing = [k for k in PARAM_NAMES if k not in values]
            extra = [k for k in values if k not in PARAM_NAMES]
            if missing or extra:
                raise ValueError(f"params={params!r}: allowed exactly the keys {', '.join(PARAM_NAMES)}")
        balls = {k: parameter_ball(k, values[k]) for k in PARAM_NAMES}
        self.params = params if isinstance(params, Params) else Params(**{k: float(values[k]) for k in PARAM_NAMES})
        self.alpha, self.beta, self.gamma, self.r = (balls[k] for k in PARAM_NAMES)

    @classmethod
    def from_balls(cls, alpha: arb, beta: arb, gamma: arb, r: arb) -> "Model":
        """A model whose parameters are the given balls (e.g. the enclosure of a bifurcation
        parameter: every statement proven with it holds for every parameter value in the balls);
        ``self.params`` holds the float64 values nearest to their midpoints."""
        self = cls.__new__(cls)
        self.alpha, self.beta, self.gamma, self.r = (arb(b) for b in (alpha, beta, gamma, r))
        self.params = Params(**{k: float(getattr(self, k).mid()) for k in PARAM_NAMES})
        return self

    def balls(self) -> dict[str, arb]:
        """The parameters' balls by name (the order of :data:`core.params.PARAM_NAMES`)."""
        return {k: getattr(self, k) for k in PARAM_NAMES}

    def forcing(self, tau: arb) -> arb:
        """f(tau) = -alpha sin tau + alpha beta cos tau + gamma."""
        s, c = tau.sin_cos()
        return -self.alpha * s + self.alpha * self.beta * c + self.gamma

    def forcing_rate(self, tau: arb) -> arb:
        """f'(tau) = -alpha cos tau - alpha beta sin tau."""
        s, c = tau.sin_cos()
        return -self.alpha * c - self.alpha * self.beta * s


class Flight:
    """Closed-form flight leaving ``(tau0, s0, v0)`` in balls; ``t`` is the elapsed flight time."""

    def __init__(self, model: Model, tau0: arb, s0: arb, v0: arb):
        self.m = model
        self.tau0, self.s0, self.v0 = tau0, s0, v0
        self.w0 = v0 - model.alpha * tau0.cos()
        self.B = model.beta * self.w0 - model.gamma

    def _e(self, t: arb):
        bt = self.m.beta * t
        em1 = (-bt).expm1()
        return em1 + 1, -em1 / self.m.beta  # E, E1

    def s(self, t: arb) -> arb:
        """Position (for a point ``t``: no cancellation trouble at high precision)."""
        m = self.m
        bt = m.beta * t
        em1 = (-bt).expm1()
        e1 = -em1 / m.beta
        half = t / 2
        trig = 2 * m.alpha * (self.tau0 + half).cos() * half.sin()
        t_minus_e1 = (bt + em1) / m.beta
        return self.s0 + trig + self.w0 * e1 + m.gamma * t_minus_e1 / m.beta

    def v(self, t: arb) -> arb:
        e, e1 = self._e(t)
        return self.m.alpha * (self.tau0 + t).cos() + self.w0 * e + self.m.gamma * e1

    def a(self, t: arb) -> arb:
        e, _ = self._e(t)
        return -self.m.alpha * (self.tau0 + t).sin() - self.B * e

    def j(self, t: arb) -> arb:
        e, _ = self._e(t)
        return -self.m.alpha * (self.tau0 + t).cos() + self.m.beta * self.B * e

    def snap(self, t: arb) -> arb:
        e, _ = self._e(t)
        return self.m.alpha * (self.tau0 + t).sin() - self.m.beta**2 * self.B * e

    # gaps: wall 0 (upper, s = 0): -s ; wall -1 (lower, s = -1): s + 1
    def gap(self, wall: int, t: arb) -> arb:
        s = self.s(t)
        return -s if wall == 0 else s + 1

    def gap_rate(self, wall: int, t: arb) -> arb:
        v = self.v(t)
        return -v if wall == 0 else v

    def gap_enclosure(self, wall: int, ta: arb, tb: arb) -> arb:
        """Enclosure of the gap to ``wall`` over ``[ta, tb]``: second-order Taylor form about the exact
        midpoint ``m``, ``s(m) + s'(m) d + s''([ta, tb]) [0, |d|^2]/2`` with ``d`` enclosing ``t - m``."""
        m = ((ta + tb) / 2).mid()  # an exact point; d encloses t - m for every t in [ta, tb]
        d = span(ta, tb) - m
        q = span(arb(0), arb(d.abs_upper()) ** 2) / 2
        sign = -1 if wall == 0 else 1
        s_enc = self.s(m) + self.v(m) * d + self.a(span(ta, tb)) * q
        return sign * s_enc + (0 if wall == 0 else 1)


__all__ = [
    "parameter_ball",
    "Model",
    "Flight",
]
