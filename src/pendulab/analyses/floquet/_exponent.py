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
    DOUBLE_DPS, MAX_DPS_LIMIT, METHODS, SIZE_LIMITS, _check_dps, _check_size, _exact, _is_array,
    _is_int_square, _is_zero, _mp,
)
from pendulab.analyses.floquet._monodromy import _monodromy_y
from pendulab.analyses.floquet._precision import GUARD, autoprec


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
    method, dps  as asked (method "arb" when dps was given and no method); working_dps
                 is the precision finally used
    band_edge    the integer e nearest to Re(lam) that the computation was based on
    certified_digits  method "arb": the number of significant digits of lam (of its
                 imaginary part in a gap, whose real part e is exact) proved by ball
                 arithmetic -- every one of them is the correctly rounded digit of
                 the exact exponent; None for the mpmath routes, for double
                 precision and on a boundary that is not decided exactly (lam = e
                 by convention, not proved).  With theta1 = 0, lam = sqrt(theta0)
                 is exact, so its digits count as proved, on the curve
                 theta0 = k^2 too (on_boundary True, lam = k exactly).
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
    certified_digits: object = None

    @property
    def trace(self):
        """Trace of the monodromy matrix, 2 cos(pi lam)."""
        return self.multipliers[0] + self.multipliers[1]

    def _repr_latex_(self):
        """lam and the multipliers (an ``align*``), the verdict below, for a notebook; the numbers
        in full (:func:`pendulab.analyses.floquet_format.number_text`, what the floquet
        command and product print) and, for method "arb", how many digits are proved."""
        from pendulab.analyses.floquet_format import number_text
        from pendulab.latex import align, gather, number_rows, number_tex, text
        lam = number_tex(number_text(self.lam, self.dps))
        up, down = (number_tex(number_text(m, self.dps)) for m in self.multipliers)
        verdict = "on a characteristic curve, " if self.on_boundary else ""
        verdict += "stable" if self.stable else "unstable"
        if self.certified_digits is None:
            proof = text(f"{verdict}; method {self.method}, no digit proved")
        else:
            # in a gap lam = e + i mu with e exact: the digits proved are mu's
            part = "" if mpmath.im(self.lam) == 0 else "the imaginary part of "
            proof = (text(f"{verdict}; {self.certified_digits} significant digits of {part}")
                     + r"\lambda" + text(f" proved (method {self.method})"))
        return (align(number_rows(r"\lambda", lam) + number_rows(r"e^{i \pi \lambda}", up)
                      + number_rows(r"e^{-i \pi \lambda}", down)) + "\n" + gather([proof]))


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


def characteristic_exponent(theta0, theta1, dps=None, method=None, max_dps=None):
    """Floquet characteristic exponent lam of 000 eq. 7 with its multipliers and verdict.

    theta0, theta1 : real numbers; str ("-0.002", "1/5"), int, Fraction, float or
        mpf.  Strings and fractions are exact and rounded afresh at each working
        precision.
    dps : decimal digits wanted (None: double precision, plain float/complex out).
    method : None (default: "arb" when |theta0| + 2|theta1| is within
        SIZE_LIMITS["arb"], else "hill"), "arb" (ball
        arithmetic: every digit of lam proved, ``certified_digits`` says how
        many), or one of the independent mpmath routes "hill", "cf",
        "monodromy" -- all four agree to the digits asked.
    max_dps : ceiling for the automatic growth of the working precision near
        band edges (default 4*dps + 60, and for 0 < |theta1| < 1 except with
        "monodromy" another 2k (-log10|theta1|) + 2k + 1 digits, k = max(2,
        round(sqrt theta0)), at most 2000: the curves there are |theta1|^k apart).

    Raises InputError on bad arguments and PrecisionError when lam cannot be
    resolved to ``dps`` digits within ``max_dps``.

    >>> r = characteristic_exponent("-0.002", "0.2", dps=30, method="cf")
    >>> r.stable, r.on_boundary
    (True, False)
    >>> s = characteristic_exponent("-0.002", "0.2", dps=30, method="hill")
    >>> abs(r.lam - s.lam) < 1e-29
    True
    >>> characteristic_exponent("-0.002", "0.2", dps=30).certified_digits
    30
    """
    if method is not None and method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if _is_array(theta0) or _is_array(theta1):
        raise InputError("characteristic_exponent takes scalars; for arrays use "
                         "exponent(theta0, theta1) (vectorised, double precision)")
    dps = _check_dps(dps)
    X0, X1 = _exact(theta0, "theta0"), _exact(theta1, "theta1")
    if method is None:
        method = default_method(X0, X1, dps)
    want = DOUBLE_DPS if dps is None else dps
    if max_dps is None:
        # the Taylor monodromy's cost grows steeply with the digits: it keeps 4 dps + 60
        extra = 0 if method == "monodromy" else _small_theta1_digits(X0, X1)
        max_dps = min(4 * want + 60 + extra, MAX_DPS_LIMIT)
    else:
        max_dps = _check_dps(max_dps, "max_dps")

    _check_size(X0, X1, SIZE_LIMITS[method], f"method {method!r}")

    # theta1 = 0: lam = sqrt(theta0) exactly; on a curve only at theta0 = k^2 exactly
    if _is_zero(X1):
        return _free(X0, dps, want, method)
    if method == "arb":
        # in double precision: 17 digits proved, then rounded (16 would round twice)
        return _arb_exponent(X0, X1, dps, want if dps is not None else DOUBLE_DPS + 1,
                             max_dps, theta0, theta1)

    # u = (lam - e)^2 is computed at two working precisions w < w2.  Its sign (the
    # verdict) is *decided* when both agree on the band, on the sign, with the
    # count, and differ by less than |u|/2; it is *resolved* when they also agree
    # to want + 3 digits.  Otherwise the working precision grows up to max_dps
    # (the rule of _precision.autoprec).  If even there the sign cannot be decided
    # while |u| is below 10^-(2 want), theta0 lies on the curve to all the digits
    # available: on_boundary, lam = e.
    tiny = mpmath.mpf(10) ** (-(want + 3))

    def decided(a, b):
        c1, e1, u1, _ = a
        c2, e2, u2, _ = b
        err = abs(u1 - u2)
        return (c1 == c2 and e1 == e2 and u1 != 0 and u2 != 0
                and (u1 > 0) == (u2 > 0) == (c2 % 2 == 1) and 2 * err < abs(u2)), err

    def accept(a, b, w2):
        with mpmath.workdps(w2):
            ok, err = decided(a, b)
            return ok and err <= tiny * abs(b[2])

    def exhausted(a, b, w2):
        with mpmath.workdps(w2):
            ok, err = decided(a, b)
            c2, e2, u2, depth = b
            if not ok and abs(u2) + err <= mpmath.mpf(10) ** (-2 * want):
                return (c2, e2, mpmath.mpf(0), depth, True), w2
            what = ("the digits of the exponent" if ok
                    else "on which side of a characteristic curve the point lies")
            raise PrecisionError(
                f"dps={want} cannot resolve {what} at theta0={theta0}, "
                f"theta1={theta1} with method {method!r} within max_dps={max_dps} "
                f"(two working precisions differ by {mpmath.nstr(err, 3)} in "
                f"u = (lam - {e2})^2 = {mpmath.nstr(u2, 3)}); raise max_dps")

    res, w2 = autoprec(lambda w: _core(method, X0, X1, w), want, max_dps, accept, exhausted)
    if len(res) == 5:
        count, e, u, depth, on_b = res
    else:
        (count, e, u, depth), on_b = res, False

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


def _small_theta1_digits(X0, X1):
    """Digits the default ceiling adds for 0 < |theta1| < 1: near theta0 = k^2 the curves
    vary on the scale |theta1|^max(k, 2) (a_0 = -q^2/2 + ..., DLMF 28.6.1; a_k - b_k ~
    2 q^k/(2^(k-1) (k-1)!)^2, DLMF 28.6.15), and inside such a gap u = (lam - k)^2, the
    product of the distances to its two edges, on the square of it; so deciding a side at
    theta1 = 2e-300 takes some 600 digits more than at theta1 = 0.2, and theta0 = 4 at
    theta1 = 1e-100 some 400.  Only the ceiling grows: a point decided earlier costs
    nothing more.  At most 2000 digits."""
    if X1 == 0 or abs(X1) >= 1:
        return 0
    with mpmath.workdps(20):
        x0, x1 = _mp(X0), abs(_mp(X1))
        k = max(2, int(mpmath.nint(mpmath.sqrt(x0)))) if x0 > 4 else 2
        if k > 2000:
            return 2000
        return min(int(2 * k * -mpmath.log10(x1)) + 2 * k + 1, 2000)


def default_method(X0, X1, dps):
    """The route used when none is named: "arb" up to its size limit
    |theta0| + 2|theta1| <= SIZE_LIMITS["arb"], "hill" beyond.

    Also in double precision (``dps=None``: arb proves 17 digits and the result is
    rounded to a float): docs/tradeoffs.md measures arb many times cheaper than Hill's
    determinant there, with the same worst error against 40 digits (1e-16)."""
    if abs(X0) + 2 * abs(X1) <= SIZE_LIMITS["arb"]:
        return "arb"
    return "hill"


def _free(X0, dps, want, method):
    """theta1 = 0: lam = sqrt(theta0) exactly (imaginary for theta0 < 0); on a curve
    only at theta0 = k^2; method "arb" proves the digits of sqrt(theta0)."""
    with mpmath.workdps(want + GUARD):
        x0 = _mp(X0)
        lam = mpmath.sqrt(x0) if x0 >= 0 else mpmath.mpc(0, mpmath.sqrt(-x0))
    on_b = _is_int_square(X0) is not None
    stable = bool(X0 > 0)
    edge = int(mpmath.nint(mpmath.re(lam)))
    certified = None
    if method == "arb" and dps is not None:
        from pendulab.analyses.floquet import _arb
        for w in (want + GUARD, 2 * want + GUARD, 4 * want + GUARD):
            with _arb._Prec(_arb.bits_of(w)):
                root = abs(_arb.to_ball(X0)).sqrt()
                text = _arb.lam_text(root, want)
            if text is not None:
                with mpmath.workdps(want + GUARD):
                    r = mpmath.mpf(text)
                    lam = r if X0 >= 0 else mpmath.mpc(0, r)
                certified = want
                break
    lam_out, mults = _finish(lam, dps, want)
    return FloquetResult(lam_out, mults, stable, bool(on_b), 0, method, dps, want + GUARD,
                         edge, certified)


def _arb_exponent(X0, X1, dps, want, max_dps, theta0, theta1):
    """Method "arb" (module _arb): certified lam; the verdict at the ceiling as above."""
    from pendulab.analyses.floquet import _arb

    info = {}

    def exhausted(w):
        if "e" in info and _arb.is_tiny(info.get("u"), 2 * want):
            return None, w
        raise PrecisionError(
            f"dps={want} cannot prove the digits of the exponent (or the side of the "
            f"characteristic curve) at theta0={theta0}, theta1={theta1} with method 'arb' "
            f"within max_dps={max_dps}; raise max_dps")

    res, w = autoprec(lambda ww: _arb.exponent_at(X0, X1, want, ww, info), want, max_dps,
                      exhausted=exhausted, two=False)
    if res is None:  # on the curve to all the precision available
        e = info["e"]
        lam_out, mults = _finish(mpmath.mpf(e), dps, want)
        return FloquetResult(lam_out, mults, False, True, 0, "arb", dps, int(w), int(e))
    e, text = res["e"], res["text"]
    with mpmath.workdps(want + GUARD):
        part = mpmath.mpf(text)
        lam = part if res["band"] else mpmath.mpc(e, part)
    # the multipliers exp(+-i pi lam) from the ball (arb), at want + GUARD digits, read
    # through their midpoints (as the mpmath routes do, from lam at the working precision)
    m1, m2 = _arb.multipliers(res["part"], e, res["band"], want + GUARD)
    if dps is None:
        lam_out = float(lam) if res["band"] else complex(lam)
        mults = (complex(m1), complex(m2))
    else:
        with mpmath.workdps(want):
            lam_out, mults = +lam, (+m1, +m2)
    return FloquetResult(lam_out, mults, res["band"], False, int(res["depth"]), "arb", dps,
                         int(w), int(e), want if dps is not None else None)
