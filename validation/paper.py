"""Every value the paper states that the report compares with, as data, with the paper's own words.

de Souza, Caldas, Viana and Balthazar, Chaos, Solitons & Fractals 21 (2004) 763-772.  Each
:class:`PaperValue` holds the number as printed (``printed``, so that the rounding of its last digit
is known), the error the paper states (``error``, ``None`` where it states none), what kind of
statement it is (:data:`KINDS`), where it stands (section, figure caption or equation; the text
has no page numbers) and the quoted words, verbatim from the paper's text (``tests/test_report.py``
checks every quote against that text, ``../shared/paper.txt`` beside the repository or
``$GEAR_RATTLE_PAPER_TXT``; math is quoted in the LaTeX of that text).

Report sections take the paper's numbers from here and nowhere else: ``PAPER["kappa"].value``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: What a paper statement says about the quantity ``q`` it names:
#:
#: * ``"value"``: ``q = printed`` (with ``error`` where the paper states one);
#: * ``"count"``: an exact integer ``q = printed`` (e.g. impacts per driving period);
#: * ``"approx"``: ``q ≈ printed``;
#: * ``"upper_bound"``: ``q <= printed`` (the paper ran the printed parameter and says it is ``≳ q``
#:   or ``≥ q``: the parameter value is above the critical one);
#: * ``"lower_bound"``: ``q >= printed`` (the printed parameter is ``≲ q`` or ``≤ q``);
#: * ``"theory"``: the value the paper's named mechanism predicts (e.g. the type-I intermittency
#:   exponent -1/2 of a saddle-node); exact, no rounding;
#: * ``"derived"``: computed from other paper values (its error propagated from theirs);
#: * ``"qualitative"``: a category (``printed`` is a word such as ``"regular"``).
KINDS = ("value", "count", "approx", "upper_bound", "lower_bound", "theory", "derived", "qualitative")

#: Symbols of the kinds, for one-line renderings ``q <= 0.82144``.
_REL = {
    "value": "=",
    "count": "=",
    "approx": "≈",
    "upper_bound": "<=",
    "lower_bound": ">=",
    "theory": "=",
    "derived": "=",
    "qualitative": ":",
}


@dataclass(frozen=True)
class PaperValue:
    """One statement of the paper about a quantity the report computes.

    ``printed`` is the number exactly as the paper prints it (a word for ``kind="qualitative"``);
    ``error`` the paper's stated one-sigma error (``None`` where none is stated); ``where`` the
    section, figure or equation; ``quote`` the paper's words, verbatim.
    """

    key: str
    printed: str
    error: float | None
    kind: str
    where: str
    quote: str
    note: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind={self.kind!r} is out of range: allowed one of {', '.join(KINDS)}")

    @property
    def numeric(self) -> bool:
        return self.kind != "qualitative"

    @property
    def value(self) -> float | str:
        """The printed value as a float (the word itself for a qualitative statement)."""
        return float(self.printed) if self.numeric else self.printed

    @property
    def printed_unit(self) -> float | None:
        """One unit of the last digit the paper printed (``1e-05`` for ``0.82144``): the precision of a
        printed value or bound (``None`` for the kinds whose printed digits carry no precision: a count,
        a theory value, a derived value, a word)."""
        if self.kind not in ("value", "approx", "upper_bound", "lower_bound"):
            return None
        s = self.printed.lower().split("e")[0]
        decimals = len(s.split(".")[1]) if "." in s else 0
        exp = int(self.printed.lower().split("e")[1]) if "e" in self.printed.lower() else 0
        return 10.0 ** (exp - decimals)

    @property
    def resolution(self) -> float | None:
        """The rounding unit of a printed *result*: :attr:`printed_unit`, or ``None`` where the printed
        value is exact (a bound is the parameter the paper ran, a count an integer, a theory value exact;
        and for derived and qualitative ones)."""
        return None if self.kind in ("upper_bound", "lower_bound") else self.printed_unit

    @property
    def rounding_sd(self) -> float:
        """Standard uncertainty of a value known only to its last printed digit: half a unit, uniformly
        distributed, i.e. ``resolution / sqrt(12)`` (0 for exact values)."""
        res = self.resolution
        return 0.0 if res is None else res / math.sqrt(12.0)

    @property
    def sigma(self) -> float:
        """The paper-side standard error used in a comparison: the stated error where the paper states
        one, otherwise the rounding of the last printed digit (:attr:`rounding_sd`)."""
        if self.error is not None:
            return float(self.error)
        return self.rounding_sd

    def text(self) -> str:
        """Short rendering, e.g. ``0.893 +- 0.001`` or ``<= 0.82144``."""
        if self.kind == "qualitative":
            return self.printed
        if self.kind == "derived":
            return f"{float(self.printed):.1f} +- {self.error:.1f} ({self.note.split(' from ')[0]})"
        rel = _REL[self.kind]
        err = f" +- {self.error:.3g}" if self.error is not None else ""
        return (f"{rel} {self.printed}" if rel != "=" else self.printed) + err

    def as_dict(self) -> dict:
        return {
            "key": self.key,
            "value": self.value,
            "error": self.error,
            "kind": self.kind,
            "printed": self.printed,
            "where": self.where,
            "quote": self.quote,
            "note": self.note,
        }


def _decay_time() -> PaperValue:
    """The decay time ``<n>/kappa`` of N(n) (Eq. 14), derived from the paper's ``<n> = 2272`` and
    ``kappa = 0.893 +- 0.001``: its error propagates the rounding of 2272 (:attr:`PaperValue.rounding_sd`)
    and the stated error of kappa."""
    n, k = _VALUES["mean_n"], _VALUES["kappa"]
    n_v, k_v = float(n.value), float(k.value)
    tau = n_v / k_v
    err = tau * math.hypot(n.sigma / n_v, k.sigma / k_v)
    return PaperValue(
        "decay_time",
        f"{tau:.10g}",
        err,
        "derived",
        "Section 4, Eq. (14)",
        n.quote,
        note=f"{n.printed}/{k.printed} from the paper's <n> (rounding of its last digit) and kappa (stated error)",
    )


_VALUES: dict[str, PaperValue] = {
    v.key: v
    for v in (
        PaperValue(
            "fig2_motion",
            "regular",
            None,
            "qualitative",
            "Section 2, Fig. 2",
            "revealing a regular oscillation which follows the regular driving of the first gear",
        ),
        PaperValue(
            "fig3_motion",
            "chaotic",
            None,
            "qualitative",
            "Section 3, Fig. 3",
            "is clearly seen as a chaotic attractor (the maximal Lyapunov exponent λ_1 is positive)",
        ),
        PaperValue(
            "r2",
            "0.82144",
            None,
            "upper_bound",
            "Fig. 5 caption",
            r"for $\alpha = 3.0$ and $r = 0.82144 \gtrsim r_2$",
            note="the r the paper ran for Fig. 5, stated to be at or above r2",
        ),
        PaperValue(
            "r2_fig6",
            "0.82145",
            None,
            "upper_bound",
            "Fig. 6 caption",
            r"for $\alpha = 3.0$ and $r = 0.82145 \gtrsim r_2$",
            note="the r the paper ran for Fig. 6, stated to be at or above r2",
        ),
        PaperValue(
            "r2_impacts_per_period",
            "6",
            None,
            "count",
            "Section 3",
            "suddenly jumps into a stable period-1 orbit with six impacts during a cycle corresponding to an "
            "entire driving period",
        ),
        PaperValue(
            "intermittency_slope",
            "-0.5",
            None,
            "theory",
            "Section 3, ref. [19]",
            "This is the typical scenario of type-I intermittency",
            note="type-I intermittency: mean laminar length ~ (r - r2)^(-1/2)",
        ),
        PaperValue(
            "r1",
            "0.74001",
            None,
            "lower_bound",
            "Fig. 7 caption",
            r"for $\alpha = 3.0$ and $r = 0.74001 \leq r_1$",
            note="the r the paper ran for Fig. 7, stated to be at or below r1",
        ),
        PaperValue(
            "alpha1",
            "1.24370",
            None,
            "approx",
            "Section 4, Fig. 8",
            r"At the critical value $\alpha_1 \approx 1.24370$ there occurs a crisis",
        ),
        PaperValue(
            "alpha1_fig9",
            "1.24500",
            None,
            "upper_bound",
            "Fig. 9 caption",
            r"Fig. 9. Basins of transient motion for $\alpha = 1.24500 \ge \alpha_1$",
            note="the alpha of Figs. 9-11, stated to be at or above alpha1",
        ),
        PaperValue(
            "alpha1_impacts_per_period",
            "4",
            None,
            "count",
            "Section 4",
            "a stable period-1 orbit (with four impacts per period) emerges out",
        ),
        PaperValue(
            "phi_500",
            "0.010",
            0.001,
            "value",
            "Section 4, Fig. 10",
            r"The uncertainty exponents were obtained as $\varpi = 0.010 \pm 0.001$ and 0.003 ± 0.002 "
            "for these two cases, respectively",
        ),
        PaperValue(
            "phi_1000",
            "0.003",
            0.002,
            "value",
            "Section 4, Fig. 10",
            r"The uncertainty exponents were obtained as $\varpi = 0.010 \pm 0.001$ and 0.003 ± 0.002 "
            "for these two cases, respectively",
        ),
        PaperValue(
            "mean_n",
            "2272",
            None,
            "value",
            "Section 4, Eq. (14)",
            r"where $\langle n \rangle = 2272$ is the average transient duration, and slope "
            r"$\kappa = 0.893 \pm 0.001$",
        ),
        PaperValue(
            "kappa",
            "0.893",
            0.001,
            "value",
            "Section 4, Eq. (14)",
            r"where $\langle n \rangle = 2272$ is the average transient duration, and slope "
            r"$\kappa = 0.893 \pm 0.001$",
        ),
    )
}

#: Every paper value by key (the keys are those of the report's summary rows that compare with it).
PAPER: dict[str, PaperValue] = {**_VALUES, "decay_time": _decay_time()}


@dataclass(frozen=True)
class Scan:
    """One of the paper's parameter scans (Section 3): ``param`` from ``lo`` to ``hi`` with the other
    parameters ``fixed`` (alpha, beta, gamma, r, the varied one at its value in the figure's caption)."""

    figure: str
    param: str
    lo: float
    hi: float
    fixed: tuple[float, float, float, float]


#: The paper's two scans, defined once (the bifurcation command's default ranges, the report's Figs. 4
#: and 8, the atlas's lines): Fig. 4 varies r in [0.70, 0.95] at alpha = 3, Fig. 8 alpha in [1.10, 1.40]
#: at r = 0.9 (beta = gamma = 0.1).  ``fixed``: the parameters the report starts from.
PAPER_SCANS: dict[str, Scan] = {
    "Fig. 4": Scan("Fig. 4", "r", 0.70, 0.95, (3.0, 0.1, 0.1, 0.9)),
    "Fig. 8": Scan("Fig. 8", "alpha", 1.10, 1.40, (1.2, 0.1, 0.1, 0.9)),
}
#: The scan of each parameter: r -> Fig. 4, alpha -> Fig. 8.
SCAN_OF = {s.param: s for s in PAPER_SCANS.values()}


__all__ = [
    "KINDS",
    "PaperValue",
    "PAPER",
    "Scan",
    "PAPER_SCANS",
    "SCAN_OF",
]
