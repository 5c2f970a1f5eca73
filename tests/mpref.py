"""High-precision (mpmath) reference for Eqs. (7)-(8) as printed in the paper, for tests."""

import mpmath as mp

mp.mp.dps = 50


def s_and_v(t, tau0, s0, v0, alpha, beta, gamma):
    """Eqs. (7)-(8) verbatim at 50 digits."""
    t, tau0, s0, v0, a, b, g = (mp.mpf(x) for x in (t, tau0, s0, v0, alpha, beta, gamma))
    tau = tau0 + t
    c = v0 - a * mp.cos(tau0) - g / b
    e = mp.exp(-b * t)
    s = s0 + a * (mp.sin(tau) - mp.sin(tau0)) + g / b * t + (1 - e) / b * c
    v = a * mp.cos(tau) + c * e + g / b
    return s, v


def first_root(tau0, s0, v0, alpha, beta, gamma, t_hi=40.0, n=4000, t_lo=0.0):
    """First wall crossing in (t_lo, t_hi] by dense sampling + bisection at 50 digits.

    Returns (t, wall, v) as mpf. Only for cases where the sampling resolves the crossings.
    """
    prev = None
    for k in range(1, n + 1):
        t = mp.mpf(t_lo) + (mp.mpf(t_hi) - t_lo) * k / n
        s, _ = s_and_v(t, tau0, s0, v0, alpha, beta, gamma)
        if s >= 0 or s <= -1:
            wall = 0 if s >= 0 else -1
            lo = mp.mpf(t_lo) + (mp.mpf(t_hi) - t_lo) * (k - 1) / n if prev is None else prev
            hi = t
            f = lambda x: s_and_v(x, tau0, s0, v0, alpha, beta, gamma)[0] - wall  # noqa: E731
            for _ in range(200):
                mid = (lo + hi) / 2
                if (f(mid) < 0) == (wall == 0):
                    lo = mid
                else:
                    hi = mid
            return hi, wall, s_and_v(hi, tau0, s0, v0, alpha, beta, gamma)[1]
        prev = t
    return None


def map_jacobian(tau, sdot, alpha, beta, gamma, r, dt, h="1e-25"):
    """Jacobian of the impact map Eqs. (12)-(13) at the pre-impact state ``(tau, sdot)`` (wall 0 if
    ``sdot > 0``, wall -1 if ``sdot < 0``) by central differences of :func:`first_root` at 50+ digits
    (step ``h``; the truncation error is ~h^2, far below float64).  ``dt`` is the float64 flight time
    (the sampling of :func:`first_root` is sized from it).  Returns ``[[dtau1/dtau, dtau1/dsdot],
    [dsdot1/dtau, dsdot1/dsdot]]`` as mpf."""
    wall = 0 if sdot > 0 else -1
    h = mp.mpf(h)
    t_hi = 1.5 * float(dt) + 0.5

    def f(t0, v):
        t, _, v1 = first_root(t0, wall, -r * v, alpha, beta, gamma, t_hi=t_hi, n=max(400, int(400 * t_hi)))
        return t0 + t, v1

    t0, v0 = mp.mpf(tau), mp.mpf(sdot)
    a, b, c, d = f(t0 + h, v0), f(t0 - h, v0), f(t0, v0 + h), f(t0, v0 - h)
    return [[(a[i] - b[i]) / (2 * h), (c[i] - d[i]) / (2 * h)] for i in (0, 1)]
