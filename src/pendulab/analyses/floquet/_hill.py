"""Method "hill": Hill's determinant with Richardson extrapolation in the depth."""

from __future__ import annotations

import math

import mpmath

from pendulab.analyses.floquet._inputs import _mp


def _hill_shift(theta0):
    """Shift s in {0, 1} keeping (2n + s)^2 - theta0 away from zero."""
    x = float(theta0)
    if x <= 0.25:
        return 1 if x > -1.0 else 0
    r = math.sqrt(x)
    k = int(round(r))
    return 1 if k % 2 == 0 else 0


def _richardson_terms(w, theta0, theta1):
    base = 2 * int(math.ceil(math.sqrt(abs(float(theta0)) + 2 * abs(float(theta1)))))
    return int(math.ceil((w + 12) / 0.6)) + base + 12


def _richardson_weight_digits(M):
    N = M // 2 - 1
    best = 0.0
    for k in range(N + 1):
        v = (N * math.log(N + k) - math.lgamma(k + 1) - math.lgamma(N - k + 1)) / math.log(10)
        best = max(best, v)
    return best


def continuants(g, steps, one, zero):
    """The truncated Hill determinants K(-N..N), N = 1 .. steps, of the normalised rows.

    Row n has diagonal 1 and off-diagonals g(n) (the symmetric continuant recurrence,
    widening the window [L, R] by one on each side per step; the four continuants kept
    are K(L..R), K(L+1..R), K(L..R-1), K(L+1..R-1)).  The same operations in the same
    order for mpmath scalars (:func:`_hill_y`) and NumPy arrays
    (:func:`pendulab.analyses.floquet._vectorised.trace_monodromy`): ``one`` and
    ``zero`` give the type.
    """
    klr, kl1r, klr1, kl1r1 = one, one, one, zero
    L = R = 0
    gR = gL = g(0)
    for _ in range(steps):
        gn = g(R + 1)
        c = gR * gn
        R += 1
        gR = gn
        klr, kl1r, klr1, kl1r1 = klr - c * klr1, kl1r - c * kl1r1, klr, kl1r
        gn = g(L - 1)
        c = gn * gL
        L -= 1
        gL = gn
        klr, klr1, kl1r, kl1r1 = klr - c * kl1r, klr1 - c * kl1r1, klr, klr1
        yield klr


def _hill_y(X0, X1, w):
    """cos(pi lam) from Hill's determinant at dps w; returns (y, depth)."""
    with mpmath.workdps(w):
        M = _richardson_terms(w, _mp(X0), _mp(X1))
    extra = int(_richardson_weight_digits(M)) + 10
    with mpmath.workdps(w + extra):
        x0, x1 = _mp(X0), _mp(X1)
        s = _hill_shift(x0)

        def g(n):
            return x1 / ((2 * n + s) ** 2 - x0)

        seq = list(continuants(g, M, mpmath.mpf(1), mpmath.mpf(0)))
        delta, _ = mpmath.richardson(seq)
        if x0 >= 0:
            cr = mpmath.cospi(mpmath.sqrt(x0))
        else:
            cr = mpmath.cosh(mpmath.pi * mpmath.sqrt(-x0))
        cs = 1 if s == 0 else -1
        y = cs + delta * (cr - cs)
    with mpmath.workdps(w):
        return +y, M
