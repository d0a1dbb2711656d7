"""The characteristic exponent at any precision: :func:`characteristic_exponent`.

Every method gives y = cos(pi lam) or u = (lam - e)^2; this module turns it
into lam, the multipliers and the verdict, and grows the working precision
until two precisions agree.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath

from pendulab.errors import InputError, PrecisionError
from pendulab.analyses.floquet._bands import _edge_count
from pendulab.analyses.floquet._cf import _cf_u
from pendulab.analyses.floquet._hill import _hill_y
from pendulab.analyses.floquet._inputs import (
    DOUBLE_DPS, GUARD, METHODS, SIZE_LIMITS, _check_dps, _check_size, _exact, _is_array,
    _is_int_square, _is_zero, _mp,
)
from pendulab.analyses.floquet._monodromy import _monodromy_y


def _u_from_y(y, count):
    """Band edge e and u = (lam - e)^2 from y = cos(pi lam) and the edge count."""
    if count % 2 == 1:
        k = (count - 1) // 2
        e = k if ((-1) ** k) * y >= 0 else k + 1
    else:
        e = count // 2
    eps = 1 - ((-1) ** e) * y  # = 2 sin^2(pi t / 2), t = lam - e
    if eps >= 0:
        t = 2 * mpmath.asin(mpmath.sqrt(eps / 2)) / mpmath.pi
        u = t * t
    else:
        t = 2 * mpmath.asinh(mpmath.sqrt(-eps / 2)) / mpmath.pi
        u = -t * t
    return e, u


# ---------------------------------------------------------------------------
# public scalar API
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class FloquetResult:
    """Characteristic exponent of theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0.

    lam          unfolded exponent (see module docstring); mpf/mpc, or float/complex
                 when the call had dps=None
    multipliers  (exp(i pi lam), exp(-i pi lam)), the Floquet multipliers
    stable       True when every solution is bounded
    on_boundary  True when theta0 lies on a characteristic curve a_n/b_n to all
                 the working precision available: theta1 = 0 and theta0 = k^2
                 exactly, or the side of the curve cannot be decided even at
                 max_dps (the distance is below ~10^-max_dps).  Then lam = e
                 exactly (true to 10^-dps absolute), the multipliers are
                 (-1)^e twice and ``stable`` is the verdict on the curve: unstable
                 (a solution grows linearly; no coexistence for theta1 != 0,
                 Ince), except theta1 = 0 with theta0 = k^2 > 0, where cos k tau
                 and sin k tau are both bounded.  A point merely close to a curve
                 is resolved (the working precision grows) and gets the verdict
                 of its side, so lam, multipliers and verdict always agree.
    depth        truncation depth used (cf: Fourier index |n| reached; hill: number
                 of truncated determinants extrapolated; monodromy: Taylor order)
    method, dps  as asked; working_dps is the precision finally used
    band_edge    the integer e nearest to Re(lam) that the computation was based on
    """

    lam: object
    multipliers: tuple
    stable: bool
    on_boundary: bool
    depth: int
    method: str
    dps: object
    working_dps: int
    band_edge: int

    @property
    def trace(self):
        """Trace of the monodromy matrix, 2 cos(pi lam)."""
        return self.multipliers[0] + self.multipliers[1]


def _core(method, X0, X1, w):
    """One evaluation at dps w: returns (count, e, u, depth)."""
    with mpmath.workdps(w):
        x0, x1 = _mp(X0), _mp(X1)
        count = _edge_count(x0, x1, w)
        if method == "cf":
            e, u, depth = _cf_u(x0, x1, count, w)
            return count, e, u, depth
    if method == "hill":
        y, depth = _hill_y(X0, X1, w)
    else:
        y, depth = _monodromy_y(X0, X1, w)
    with mpmath.workdps(w):
        e, u = _u_from_y(y, count)
    return count, e, u, depth


def _finish(lam, dps, out_dps):
    with mpmath.workdps(out_dps + 5):
        mults = (mpmath.expjpi(lam), mpmath.expjpi(-lam))
    if dps is None:
        def conv(z):
            z = complex(z)
            return z.real if z.imag == 0 else z
        return conv(lam), tuple(complex(m) for m in mults)
    with mpmath.workdps(out_dps):
        return +lam, tuple(+m for m in mults)


def characteristic_exponent(theta0, theta1, dps=None, method="hill", max_dps=None):
    """Floquet characteristic exponent lam of 000 eq. 7 with its multipliers and verdict.

    theta0, theta1 : real numbers; str ("-0.002", "1/5"), int, Fraction, float or
        mpf.  Strings and fractions are exact and rounded afresh at each working
        precision.
    dps : decimal digits wanted (None: double precision, plain float/complex out).
    method : "hill" (default), "cf" or "monodromy" -- three independent routes
        that agree to the digits asked.
    max_dps : ceiling for the automatic growth of the working precision near
        band edges (default 4*dps + 60).

    Raises InputError on bad arguments and PrecisionError when lam cannot be
    resolved to ``dps`` digits within ``max_dps``.

    >>> r = characteristic_exponent("-0.002", "0.2", dps=30, method="cf")
    >>> r.stable, r.on_boundary
    (True, False)
    >>> s = characteristic_exponent("-0.002", "0.2", dps=30, method="hill")
    >>> abs(r.lam - s.lam) < 1e-29
    True
    """
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if _is_array(theta0) or _is_array(theta1):
        raise InputError("characteristic_exponent takes scalars; for arrays use "
                         "exponent(theta0, theta1) (vectorised, double precision)")
    dps = _check_dps(dps)
    X0, X1 = _exact(theta0, "theta0"), _exact(theta1, "theta1")
    want = DOUBLE_DPS if dps is None else dps
    if max_dps is None:
        max_dps = 4 * want + 60
    else:
        max_dps = _check_dps(max_dps, "max_dps")

    _check_size(X0, X1, SIZE_LIMITS[method], f"method {method!r}")

    # theta1 = 0: lam = sqrt(theta0) exactly; on a curve only at theta0 = k^2 exactly
    if _is_zero(X1):
        with mpmath.workdps(want + GUARD):
            x0 = _mp(X0)
            lam = mpmath.sqrt(x0) if x0 >= 0 else mpmath.mpc(0, mpmath.sqrt(-x0))
        on_b = _is_int_square(X0) is not None
        stable = bool(X0 > 0)
        edge = int(mpmath.nint(mpmath.re(lam)))
        lam_out, mults = _finish(lam, dps, want)
        return FloquetResult(lam_out, mults, stable, bool(on_b), 0, method, dps,
                             want + GUARD, edge)

    # u = (lam - e)^2 is computed at two working precisions w < w2.  Its sign (the
    # verdict) is *decided* when both agree on the band, on the sign, with the
    # count, and differ by less than |u|/2; it is *resolved* when they also agree
    # to want + 3 digits.  Otherwise the working precision grows up to max_dps.
    # If even there the sign cannot be decided while |u| is below 10^-(2 want),
    # theta0 lies on the curve to all the digits available: on_boundary, lam = e.
    w = want + GUARD
    tiny = mpmath.mpf(10) ** (-(want + 3))
    on_b = False
    while True:
        c1, e1, u1, _ = _core(method, X0, X1, w)
        w2 = w + 12
        c2, e2, u2, depth = _core(method, X0, X1, w2)
        with mpmath.workdps(w2):
            err = abs(u1 - u2)
            decided = (c1 == c2 and e1 == e2 and u1 != 0 and u2 != 0
                       and (u1 > 0) == (u2 > 0) == (c2 % 2 == 1) and 2 * err < abs(u2))
            if decided and err <= tiny * abs(u2):
                count, e, u = c2, e2, u2
                break
            if w2 + 12 > max_dps:
                if not decided and abs(u2) + err <= mpmath.mpf(10) ** (-2 * want):
                    count, e, u, on_b = c2, e2, mpmath.mpf(0), True
                    break
                what = ("the digits of the exponent" if decided
                        else "on which side of a characteristic curve the point lies")
                raise PrecisionError(
                    f"dps={want} cannot resolve {what} at theta0={theta0}, "
                    f"theta1={theta1} with method {method!r} within max_dps={max_dps} "
                    f"(two working precisions differ by {mpmath.nstr(err, 3)} in "
                    f"u = (lam - {e2})^2 = {mpmath.nstr(u2, 3)}); raise max_dps")
        w = min(max(w + 12, 2 * w - want), max_dps - 12)

    with mpmath.workdps(w2):
        if on_b:
            # on the curve: lam = e to 10^-want absolute; for theta1 != 0 the
            # curve itself is unstable (no coexistence, Ince): a solution grows
            # linearly; multipliers (-1)^e twice
            lam, stable = mpmath.mpf(e), False
        elif u > 0:
            # lam above the edge when the count says band e (count = 2e+1)
            sign = 1 if count == 2 * e + 1 else -1
            lam, stable = e + sign * mpmath.sqrt(u), True
        else:
            lam, stable = mpmath.mpc(e, mpmath.sqrt(-u)), False
    lam_out, mults = _finish(lam, dps, want)
    return FloquetResult(lam_out, mults, bool(stable), bool(on_b), int(depth), method,
                         dps, int(w2), int(e))
