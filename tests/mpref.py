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
