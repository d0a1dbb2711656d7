"""The inverse: theta0 for a given exponent nu and theta1 (:func:`theta0_of_exponent`)."""

from __future__ import annotations

from fractions import Fraction

import mpmath

from pendulab.errors import ConvergenceError, InputError
from pendulab.analyses.floquet._cf import _CF, _illinois
from pendulab.analyses.floquet._charvalues import _char_value_mp, _family_of, mathieu_a
from pendulab.analyses.floquet._inputs import (
    DOUBLE_DPS, GUARD, SIZE_LIMITS, _check_dps, _check_size, _exact, _is_array, _mp,
)
from pendulab.analyses.floquet._precision import agree, autoprec
from pendulab.analyses.floquet._vectorised import (
    _theta0_of_exponent_array, _theta0_of_exponent_polished,
)


def theta0_of_exponent(nu, theta1, dps=None):
    """theta0 such that the characteristic exponent of 000 eq. 7 is nu.

    nu >= 0 real (lam and -lam describe the same solutions, so a negative nu is
    treated as |nu|).  For non-integer nu the answer lies in the stable band
    floor(nu) and is DLMF's lambda_nu(q), q = -theta1, an even function of q;
    it is the root of the continued-fraction characteristic function
    (000 eq. 10) in theta0 between the band edges.  For integer nu it is the
    characteristic value a_nu(q) with q = -theta1 (DLMF's convention: lambda_n
    = a_n); the other edge of that instability gap is b_nu(q).  As nu tends to
    an integer n from below (above) the answer tends to the lower (upper) edge
    of gap n, min(a_n, b_n) (max(a_n, b_n)) at |q|: the curve jumps by the gap
    width at integer nu, and lambda_n = a_n is one of the two one-sided limits.

    nu and theta1 may be numpy arrays (broadcast against each other) when
    dps=None: the result is then a float array computed by the vectorised
    double-precision routine (see :func:`exponent`).  Raises InputError when
    nu^2 + 2|theta1| exceeds ``SIZE_LIMITS["cf"]`` (``SIZE_LIMIT`` for arrays).

    >>> float(theta0_of_exponent(0.5, 0))
    0.25
    """
    if _is_array(nu) or _is_array(theta1):
        if dps is not None:
            raise InputError("theta0_of_exponent: arrays are handled in double precision "
                             "only (dps=None); loop over the points for dps digits")
        return _theta0_of_exponent_array(nu, theta1)
    dps = _check_dps(dps)
    NU, X1 = _exact(nu, "nu"), _exact(theta1, "theta1")
    if NU < 0:
        NU = -NU
    _check_size(NU * NU, X1, SIZE_LIMITS["cf"], "theta0_of_exponent",
                names=("nu^2", "theta1"))
    want = DOUBLE_DPS if dps is None else dps
    if X1 == 0:
        with mpmath.workdps(want + GUARD):
            v = _mp(NU) ** 2
        if dps is None:
            return float(v)
        with mpmath.workdps(want):
            return +v
    with mpmath.workdps(want + GUARD):
        nu_mp = _mp(NU)
        is_int = mpmath.isint(nu_mp) if not isinstance(NU, Fraction) else NU.denominator == 1
    if is_int:
        return mathieu_a(int(NU), -X1 if isinstance(X1, Fraction) else -X1, dps)
    if dps is None:  # double precision: the eigenvalue of J(nu), refined in mpmath
        v = _theta0_of_exponent_polished(NU, X1)
        if v is not None:
            return v

    absq = abs(X1)

    def accept(a, b, w2):
        with mpmath.workdps(w2):
            return agree(a, b, want)
    v, _ = autoprec(lambda ww: _theta0_of_exponent_mp(NU, X1, absq, ww), want, accept=accept,
                    what=f"theta0_of_exponent({nu}, {theta1})")
    if dps is None:
        return float(v)
    with mpmath.workdps(want):
        return +v


def _theta0_of_exponent_mp(NU, X1, absq, ww):
    """The root in theta0 of the cf function with u = (nu - e)^2 fixed, at dps ww.

    The root lies in the band [lo, hi] between the edges.  When nu is within
    ~10^-ww/2 of an integer, or the band is thinner than the rounding (|q| large,
    widths ~exp(-4 sqrt|q|), DLMF 28.8.2), the end values of the cf function are
    rounding noise and need not differ in sign; the bracket is then widened
    symmetrically about the edge E that nu approaches, by 10^-ww |E|, 10^-ww+1
    |E|, ...: the root found is within rounding of the true one, and the caller
    compares two working precisions.
    """
    with mpmath.workdps(ww):
        nu_m = _mp(NU)
        k = int(mpmath.floor(nu_m))
        qmp = _mp(absq)
        lo = _edge_value(k, qmp, ww, upper=True) if k > 0 else _char_value_mp("a_even", 0, qmp, ww)
        hi = _edge_value(k + 1, qmp, ww, upper=False)
        if lo > hi:  # a band thinner than the rounding
            lo, hi = hi, lo
        e = int(mpmath.nint(nu_m))
        t = nu_m - e
        u = t * t
        f = _CF(hi, _mp(X1), e, ww + 5)

        def g(th0):
            return f(u, x0=th0)

        scale = max(1, abs(hi))
        tol = mpmath.mpf(10) ** (-ww) * scale
        glo, ghi = g(lo), g(hi)
        if (glo > 0) != (ghi > 0) or glo == 0 or ghi == 0:
            root, _ = _illinois(g, lo, hi, glo, ghi, tol)
            return root
        E = hi if e == k + 1 else lo
        h = tol
        while h <= scale:
            a, b = E - h, E + h
            ga, gb = g(a), g(b)
            if (ga > 0) != (gb > 0) or ga == 0 or gb == 0:
                root, _ = _illinois(g, a, b, ga, gb, tol)
                return root
            h *= 10
        raise ConvergenceError(f"theta0_of_exponent: no root of the characteristic function "
                               f"near the band edge {mpmath.nstr(E, 8)} at {ww} digits")


def _edge_value(k, absq, w, upper):
    """max (upper=True) or min of a_k(|q|), b_k(|q|) at dps w (k >= 1)."""
    fa, ja = _family_of("a", k)
    fb, jb = _family_of("b", k)
    va = _char_value_mp(fa, ja, absq, w)
    vb = _char_value_mp(fb, jb, absq, w)
    return max(va, vb) if upper else min(va, vb)
