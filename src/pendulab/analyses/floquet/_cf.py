"""Method "cf": the source's continued fractions (000 sec. 2.2, eqs. 8-10)."""

from __future__ import annotations

import mpmath

from pendulab.errors import ConvergenceError
from pendulab.analyses.floquet._bands import _edge_index, _tail_steps


class _CF:
    """The characteristic function of 000 eq. 10 closed by continued fractions.

    Frequencies are indexed by m = 2n + e (e the band edge), so that
    C(m) = theta0 - (m + t)^2 with t = lam - e.  The block |m| <= M is kept
    exactly; beyond it the ratios b_{m+2}/b_m (and b_{m-2}/b_m) are the
    minimal-solution continued fractions of the source, truncated ``tail``
    levels out.  The block determinant is even in t, i.e. a function of u = t^2.
    """

    def __init__(self, theta0, theta1, e, digits, size_theta0=None):
        self.x0, self.x1, self.e = theta0, theta1, e
        sz = theta0 if size_theta0 is None else size_theta0
        m0 = _edge_index(sz, theta1)
        M = max(m0, e + 2)
        if (M - e) % 2:
            M += 1
        self.M = M
        self.tail = _tail_steps(sz, theta1, M, digits)
        self.depth = M // 2 + self.tail

    def __call__(self, u, x0=None):
        x0 = self.x0 if x0 is None else x0
        x1 = self.x1
        t = mpmath.sqrt(u) if u >= 0 else mpmath.mpc(0, mpmath.sqrt(-u))

        def C(m):
            return x0 - (m + t) ** 2

        M, T = self.M, self.tail
        # right tail: rho = b_{m}/b_{m-2} = -x1 / (C_m + x1 rho_{m+2})
        rho = 0
        for m in range(M + 2 * T, M, -2):
            rho = -x1 / (C(m) + x1 * rho)
        sig = 0
        for m in range(-M - 2 * T, -M, 2):
            sig = -x1 / (C(m) + x1 * sig)
        # block continuant from m = -M to m = M (step 2)
        ms = list(range(-M, M + 1, 2))
        d = [C(m) for m in ms]
        d[0] += x1 * sig
        d[-1] += x1 * rho
        x12 = x1 * x1
        p_prev, p = 1, d[0]
        for j in range(1, len(d)):
            p_prev, p = p, d[j] * p - x12 * p_prev
        # scale away the (harmless) magnitude of the leading products
        return mpmath.re(p)


def _illinois(f, a, b, fa, fb, tol, maxit=2000):
    """Bracketed root of f in [a, b] by Brent's method (inverse quadratic
    interpolation, secant and bisection steps; Brent 1973, ch. 4).
    Returns (root, final bracket width)."""
    if fa == 0:
        return a, 0
    if fb == 0:
        return b, 0
    if (fa > 0) == (fb > 0):
        raise ConvergenceError("root is not bracketed")
    if abs(fa) < abs(fb):
        a, b, fa, fb = b, a, fb, fa
    c, fc = a, fa
    d = e = b - a
    for _ in range(maxit):
        if (fb > 0) == (fc > 0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        m = (c - b) / 2
        tol1 = 4 * mpmath.eps * abs(b) + tol / 2
        if abs(m) <= tol1 or fb == 0:
            return b, abs(c - b)
        if abs(e) < tol1 or abs(fa) <= abs(fb):
            d = e = m
        else:
            sfrac = fb / fa
            if a == c:
                p = 2 * m * sfrac
                qq = 1 - sfrac
            else:
                qa = fa / fc
                r = fb / fc
                p = sfrac * (2 * m * qa * (qa - r) - (b - a) * (r - 1))
                qq = (qa - 1) * (r - 1) * (sfrac - 1)
            if p > 0:
                qq = -qq
            else:
                p = -p
            if 2 * p < min(3 * m * qq - abs(tol1 * qq), abs(e * qq)):
                e, d = d, p / qq
            else:
                d = e = m
        a, fa = b, fb
        b = b + (d if abs(d) > tol1 else (tol1 if m > 0 else -tol1))
        fb = f(b)
    raise ConvergenceError("root finder did not converge")


def _widen_below(f, f0, w):
    """A bracket [-h, 0] of the root of f in u when that root lies at or below 0
    by rounding: h = 10^-w, 10^-(w-3), ... up to 1.  Returns (lo, f(lo)) or None."""
    h = mpmath.mpf(10) ** (-w)
    while h <= 1:
        fh = f(-h)
        if (fh > 0) != (f0 > 0) or fh == 0:
            return -h, fh
        h *= 1000
    return None


def _cf_u(theta0, theta1, count, w):
    """u = (lam - e)^2 by the continued-fraction method at dps w; returns (e, u, depth).

    The characteristic function f_e(u) of edge e has, for u < 4, only the real
    roots u = t^2 and (2 - t)^2 (t = lam - e; the others are (t + 2j)^2, j != 0,
    -1).  Inside band k (odd count) lam = k + t, 0 < t < 1: the root t^2 of f_k
    lies in (0, 1/4] when t <= 1/2, otherwise the root (1 - t)^2 of f_{k+1}
    lies in (0, 1/4).  In gap k (even count) the only real root of f_k is
    u = -mu^2 <= 0.  A point on (or within rounding of) an edge has its root at
    u = 0 up to rounding, possibly on the "wrong" side: the bracket is then
    widened past 0, and the caller sees the sign disagree with the count and
    raises the working precision.
    """
    tol = mpmath.mpf(10) ** (-w)
    quarter = mpmath.mpf(1) / 4
    zero = mpmath.mpf(0)
    if count % 2 == 1:  # inside band k: lam - k in (0, 1)
        k = (count - 1) // 2
        fs = []
        for e, top in ((k, quarter), (k + 1, 2 * quarter)):
            f = _CF(theta0, theta1, e, w + 5)
            f0, ft = f(zero), f(top)
            if f0 == 0:
                return e, zero, f.depth
            if (f0 > 0) != (ft > 0):
                u, _ = _illinois(f, zero, top, f0, ft, tol)
                return e, u, f.depth
            fs.append((e, f, f0))
        # neither: the root is at u <= 0 within rounding for one of the two edges
        for e, f, f0 in fs:
            lo = _widen_below(f, f0, w)
            if lo is not None:
                u, _ = _illinois(f, lo[0], zero, lo[1], f0, tol)
                return e, u, f.depth
        raise ConvergenceError(f"cf: no root of the characteristic function in band {k} "
                               f"at {w} digits")
    k = count // 2
    f = _CF(theta0, theta1, k, w + 5)
    f0 = f(zero)
    if f0 == 0:
        return k, zero, f.depth
    one = mpmath.mpf(1)
    f1 = f(one)
    if (f1 > 0) != (f0 > 0):  # root at u > 0 by rounding next to an edge
        u, _ = _illinois(f, zero, one, f0, f1, tol)
        return k, u, f.depth
    U = one
    fU = f(-U)
    while (fU > 0) == (f0 > 0):
        U *= 4
        if U > mpmath.mpf(10) ** 12:
            raise ConvergenceError("cf: could not bracket the characteristic exponent "
                                   f"in gap {k} (|mu| > 10^6)")
        fU = f(-U)
    u, _ = _illinois(f, -U, zero, fU, f0, tol)
    return k, u, f.depth
