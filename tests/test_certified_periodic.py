"""Certified periodic orbits and bifurcation points (mapimpl/certified: jets, krawczyk, shooting,
periodic): the building blocks on problems with known answers, then the orbits of the paper
(Figs. 2, 4, 8-11) proven from 4-digit guesses."""

from fractions import Fraction

import pytest
from flint import acb, arb
from hypothesis import given, strategies as st

from gear_rattle.core.params import Params
from gear_rattle.mapimpl.certified import jets
from gear_rattle.mapimpl.certified.balls import CertificationError, decimal_interval, precision
from gear_rattle.mapimpl.certified.krawczyk import krawczyk, newton, refine, verify_box
from gear_rattle.mapimpl.certified.model import Model
from gear_rattle.mapimpl.certified.periodic import (
    certify_bifurcation,
    certify_periodic_orbit,
    closed_form_det,
    prove_flights,
    unwrap,
)
from gear_rattle.mapimpl.certified.shooting import Shape

FIG2 = Params(0.5, 0.1, 0.1, 0.9)
FIG4 = Params(3.0, 0.1, 0.1, 0.8)


def _exact(x: arb) -> Fraction:
    man, exp = x.man_exp()
    return Fraction(int(man)) * Fraction(2) ** int(exp)


# ---------------------------------------------------------------------------------------------
# jets


def test_jet_gradient_encloses_the_analytic_one():
    """Forward mode over balls: f = sin(x) exp(y) / (1 + x) - cos(x y) + expm1(y) / x at (0.7, -0.3);
    the jet's gradient must enclose the hand-derived one (same ball arithmetic), and be tight."""
    with precision(200):
        x, y = arb("0.7"), arb("-0.3")
        X, Y = jets.variables([x, y])
        f = jets.sin(X) * jets.exp(Y) / (1 + X) - jets.cos(X * Y) + jets.expm1(Y) / X
        dfx = x.cos() * y.exp() / (1 + x) - x.sin() * y.exp() / (1 + x) ** 2 + y * (x * y).sin() - y.expm1() / x**2
        dfy = x.sin() * y.exp() / (1 + x) + x * (x * y).sin() + y.exp() / x
        for got, want in zip(f.der, (dfx, dfy)):
            assert got.overlaps(want)
            assert float(got.rad()) < 1e-55
        assert (2 - X).val.overlaps(arb("1.3")) and (2 - X).der[0] == -1 and (X**3).der[0].overlaps(3 * x**2)
        with pytest.raises(ValueError, match="exponent=0 is out of range: allowed an integer 1 <= exponent"):
            X**0


# ---------------------------------------------------------------------------------------------
# the Krawczyk operator on a system with known zeros: x^2 + y^2 = 2, x = y  ->  (1, 1) and (-1, -1)


def _circle(v):
    x, y = v
    return [x * x + y * y - 2, x - y]


def test_krawczyk_proves_the_known_zero_and_refines_it():
    with precision(256):
        res = krawczyk(_circle, [0.9, 1.2])
        assert all(b.contains(1) for b in res.box)
        assert max(float(b.rad()) for b in res.box) < 1e-70
        assert res.contraction < 1e-30 and res.norm < 1e-30
        # a box of radius 0.1 around (1, 1): unique zero, proven; refining shrinks it to the precision
        box = [arb(1, 0.1) + arb("0.01"), arb(1, 0.1) - arb("0.02")]
        res = verify_box(_circle, box)
        assert 0 < res.contraction < 1 and res.norm < 1
        tight = refine(_circle, res.box, steps=12)
        assert all(b.contains(1) for b in tight) and max(float(b.rad()) for b in tight) < 1e-70


@pytest.mark.parametrize(
    "box",
    [
        [arb(2, 0.1), arb(2, 0.1)],  # no zero in the box
        [arb(0, 1.5), arb(0, 1.5)],  # both zeros in the box (and a singular Jacobian): no uniqueness
    ],
)
def test_krawczyk_refuses_boxes_without_a_unique_zero(box):
    with precision(128), pytest.raises(CertificationError):
        verify_box(_circle, box)


def test_newton_refuses_a_singular_start_and_a_non_square_system():
    with precision(128):
        with pytest.raises(CertificationError, match="singular"):
            newton(_circle, [0.0, 0.0])
        with pytest.raises(ValueError, match="square"):
            verify_box(lambda v: [v[0] - 1], [arb(1, 0.1), arb(1, 0.1)])


# ---------------------------------------------------------------------------------------------
# decimal intervals


@given(st.floats(-1e6, 1e6, allow_nan=False), st.floats(0, 1e-3), st.integers(1, 40))
def test_decimal_interval_contains_the_ball(mid, rad, digits):
    """The decimal ends, read exactly, enclose the ball's exact ends (outward rounding), and they are
    no further out than one unit of the last digit."""
    with precision(256):
        x = arb(mid, rad) * arb(3).sqrt()
        lo, hi = decimal_interval(x, digits)
        a, b = _exact(x.lower()), _exact(x.upper())
        assert Fraction(lo) <= a and b <= Fraction(hi)
        if a != 0:
            assert a - Fraction(lo) <= abs(a) / Fraction(10) ** (digits - 1)
        if b != 0:
            assert Fraction(hi) - b <= abs(b) / Fraction(10) ** (digits - 1)


def test_decimal_interval_exact_values_and_bad_input():
    with precision(128):
        assert decimal_interval(arb(0)) == ("0", "0")
        assert decimal_interval(arb(1) / 4) == ("0.25", "0.25")
        assert decimal_interval(-arb(2).sqrt(), 5) == ("-1.4143", "-1.4142")
        with pytest.raises(ValueError, match="digits"):
            decimal_interval(arb(1), 0)
        with pytest.raises(ValueError, match="finite"):
            decimal_interval(arb("inf"))


# ---------------------------------------------------------------------------------------------
# the paper's orbits


def test_fig2_orbit_from_a_4_digit_guess():
    """Fig. 2 (alpha = 0.5, r = 0.9): the regular motion is a 3-impact period-1 orbit (one impact on
    the lower wall, two on the upper), stable, with a complex pair of multipliers whose product is
    r^6 exp(-2 pi beta) (closed form); proven with radii below 1e-80 (measured ~1e-93)."""
    o = certify_periodic_orbit(FIG2, [2.034, 4.110, 6.087], [-0.7343, 0.6229, 0.4421])
    assert o.walls == (-1, 0, 0)
    assert o.max_radius < 1e-80 and o.krawczyk.contraction < 1e-30
    with precision(320):
        assert sum(o.durations).overlaps(2 * arb.pi())
        z0, z1 = o.multipliers
        assert z0.imag < 0 < z1.imag and (z0 * z1).real.overlaps(closed_form_det(o.model, o.shape))
        assert all(abs(z) < 1 for z in o.multipliers)
        assert all(abs(float(t) - float(th)) < 1e-70 for t, th in zip(o.tau, o.theta))  # 0 <= tau < 2 pi


def test_fold_r2_from_a_4_digit_guess():
    """Figs. 4-5: r2, the fold of the 6-impact orbit, proven on the extended system from a guess with 4
    digits; its multipliers enclose +1 and r^12 exp(-2 pi beta) (the other one, since the product is det M)."""
    b = certify_bifurcation(
        "fold",
        FIG4,
        "r",
        [1.055, 2.017, 3.013, 4.172, 5.141, 6.102],
        [-1.614, -1.343, -0.709, 1.734, 1.448, 0.829],
        0.8214,
    )
    assert b.kind == "fold" and b.name == "r"
    with precision(320):
        assert float(b.value.rad()) < 1e-80
        assert abs(float(b.value) - 0.82144044758015) < 1e-15
        one = [z for z in b.orbit.multipliers if z.contains(acb(1))]
        other = [z for z in b.orbit.multipliers if not z.contains(acb(1))]
        assert len(one) == 1 and other[0].real.overlaps(closed_form_det(b.orbit.model, b.orbit.shape))


def test_flight_proof_rejects_a_duration_past_the_first_contact():
    """The orbit equations say nothing about earlier contacts: a 'period' of two turns makes the last
    flight 2 pi longer than its first wall contact, and the flight proof must refuse it."""
    o = certify_periodic_orbit(FIG2, [2.034, 4.110, 6.087], [-0.7343, 0.6229, 0.4421])
    with precision(320):
        prove_flights(o.model, o.shape, o.tau, o.sdot, 320)  # the true orbit passes
        with pytest.raises(CertificationError, match="first contact"):
            prove_flights(o.model, Shape(o.walls, 2), o.tau, o.sdot, 320)
        with pytest.raises(CertificationError, match="sign"):
            prove_flights(o.model, Shape((0, 0, 0)), o.tau, o.sdot, 320)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: certify_periodic_orbit(FIG2, [1.0, 2.0], [0.5]), "equal length"),
        (lambda: certify_periodic_orbit(FIG2, [1.0], [0.0]), "nonzero"),
        (lambda: certify_periodic_orbit(FIG2, [1.0], [0.5], turns=0), "turns"),
        (lambda: certify_bifurcation("cusp", FIG4, "r", [1.0], [0.5], 0.8), "kind"),
        (lambda: certify_bifurcation("fold", FIG4, "beta", [1.0], [0.5], 0.8), "name='beta'"),  # the argument's name
        (lambda: unwrap([0.0, 3.0, 6.0, 2.0]), "driving period"),
        (lambda: Shape(()), "walls"),
    ],
)
def test_bad_inputs(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_the_guess_is_named_theta_and_the_old_name_tau_warns():
    """The guess is p pre-impact phases (issue 32: tau is absolute time, the phase is theta): the argument
    is ``theta``; the old keyword ``tau=`` still works with a DeprecationWarning and proves the same orbit
    (every enclosure equal); both at once, or neither, is a TypeError naming the argument."""
    guess, sdot = [2.034, 4.110, 6.087], [-0.7343, 0.6229, 0.4421]
    new = certify_periodic_orbit(FIG2, theta=guess, sdot=sdot)
    with pytest.warns(DeprecationWarning, match="tau= is deprecated: use theta="):
        old = certify_periodic_orbit(FIG2, tau=guess, sdot=sdot)
    assert [b.mid().str(40) for b in old.tau + old.sdot] == [b.mid().str(40) for b in new.tau + new.sdot]
    assert [b.rad() for b in old.tau + old.sdot] == [b.rad() for b in new.tau + new.sdot]
    with pytest.raises(TypeError, match="not both"):
        certify_periodic_orbit(FIG2, guess, sdot, tau=guess)
    with pytest.raises(TypeError, match="theta is missing"):
        certify_periodic_orbit(FIG2, sdot=sdot)
    with pytest.warns(DeprecationWarning, match="tau= is deprecated"), pytest.raises(CertificationError):
        certify_bifurcation("fold", FIG4, "r", tau=[5.0], sdot=[1.4], mu=0.82)  # the old name reaches the proof
    with pytest.raises(TypeError, match="mu is missing"):
        certify_bifurcation("fold", FIG4, "r", [5.0], [1.4])


def test_a_guess_that_leads_nowhere_raises_certification_error():
    """A guess far from any orbit: Newton leaves the model's range or fails; never a wrong certificate."""
    with pytest.raises(CertificationError):
        certify_bifurcation("fold", FIG4, "r", [5.0], [1.4], 0.82)


def test_model_from_balls_keeps_the_balls():
    with precision(128):
        m = Model.from_balls(arb(3), arb("0.1"), arb("0.1"), arb("0.8", 1e-20))
        assert m.r.rad() > 0 and m.params.r == 0.8 and m.params.alpha == 3.0
