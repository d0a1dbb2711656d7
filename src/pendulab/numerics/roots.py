"""Brent's root finder and Brent's bounded minimiser on plain Python floats.

pendulab brackets roots and minima itself (sign changes on a scan, the step of
an event); what is left is the one-dimensional refinement, which SciPy offers
in ``scipy.optimize`` (``brentq``, ``minimize_scalar(method="bounded")``).
Importing ``scipy.optimize`` costs about 0.3 s (it pulls in ``scipy.special``,
``scipy.fft`` and the linear-programming code), more than every refinement of
a build together, and each process of a parallel build would pay it.  These
are the two algorithms of R. P. Brent, *Algorithms for Minimization without
Derivatives* (Prentice-Hall, 1973): chapter 4 (a zero of a function that
changes sign, by bisection, the secant rule and inverse quadratic
interpolation) and chapter 5 (a local minimum on an interval, by golden
section and successive parabolic interpolation), written here from the
book's description with the tolerances SciPy's callers of this project used.

* :func:`brent_root` - a root of f in [a, b] where f(a), f(b) differ in sign;
* :func:`brent_minimum` - a local minimum of f on [a, b].

Both call ``f`` with Python floats only and never return a point outside
[a, b].  tests/test_roots.py checks them against mpmath's roots and minima at
50 digits and against SciPy's routines.
"""

import math

from pendulab.errors import ConvergenceError, InputError

EPS = 2.220446049250313e-16  # spacing of doubles at 1 (2**-52)
_GOLDEN = (3.0 - math.sqrt(5.0)) / 2.0  # 0.381966...: the golden-section fraction


class NoConvergence(ConvergenceError):
    """The iteration limit was reached before the tolerance (a pendulab error: one line)."""


class NotANumber(ConvergenceError):
    """The function gave NaN where a root is refined: no sign can be read off."""


def _value(f, x):
    v = float(f(x))
    if v != v:
        raise NotANumber(f"brent_root: the function is NaN at x = {x!r}")
    return v


def brent_root(f, a, b, xtol=2e-12, rtol=4 * EPS, maxiter=100):
    """A root of ``f`` in [a, b] to within xtol + rtol |root| (Brent 1973, ch. 4).

    ``f(a)`` and ``f(b)`` must differ in sign (or one of them be 0): an
    InputError says so otherwise; a NaN value of ``f`` anywhere raises
    :class:`NotANumber` (as SciPy's brentq raises), never a false root.  Each step takes the inverse quadratic (or
    secant) estimate when it falls well inside the bracket and shrinks it
    fast enough, else bisects, so the bracket always contains a sign change.

    >>> r = brent_root(lambda x: x * x - 2.0, 0.0, 2.0, xtol=1e-15, rtol=1e-15)
    >>> abs(r - 2 ** 0.5) < 4e-15
    True
    """
    a, b = float(a), float(b)
    if not (math.isfinite(a) and math.isfinite(b)):
        raise InputError(f"brent_root: the bracket [{a!r}, {b!r}] is not finite")
    if xtol <= 0 or rtol < 4 * EPS:
        raise InputError(f"brent_root: xtol {xtol!r} must be > 0 and rtol {rtol!r} >= 4 eps")
    fa, fb = _value(f, a), _value(f, b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise InputError(f"brent_root: f({a!r}) = {fa!r} and f({b!r}) = {fb!r} have the same sign")
    c, fc = a, fa
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):  # keep the sign change between b and c
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):  # b is the best estimate so far
            a, fa = b, fb
            b, fb = c, fc
            c, fc = a, fa
        tol = 0.5 * (xtol + rtol * abs(b))
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) < tol or abs(fa) <= abs(fb):
            d = e = m  # bisection
        else:
            s = fb / fa
            if a == c:  # secant
                p, q = 2.0 * m * s, 1.0 - s
            else:  # inverse quadratic interpolation through a, b, c
                q, r = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < 3.0 * m * q - abs(tol * q) and p < abs(0.5 * e * q):
                e, d = d, p / q  # interpolation accepted
            else:
                d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0 else -tol)
        fb = _value(f, b)
    raise NoConvergence(f"brent_root: no convergence in {maxiter} iterations (bracket [{b!r}, {c!r}])")


def brent_minimum(f, a, b, xatol=1e-5, maxiter=500):
    """(x, f(x)) at a local minimum of ``f`` on [a, b] to within about 3 xatol (Brent 1973, ch. 5).

    Golden-section steps, replaced by the minimum of the parabola through the
    three best points when that falls inside the interval and the step
    shrinks; the relative part of the tolerance is sqrt(eps) |x|, as the
    function's own rounding allows no better.  The end points themselves are
    never evaluated.

    >>> x, fx = brent_minimum(lambda x: (x - 1.0) ** 2 + 3.0, 0.0, 4.0, xatol=1e-10)
    >>> abs(x - 1.0) < 1e-8, fx == 3.0 or abs(fx - 3.0) < 1e-15
    (True, True)
    """
    a, b = float(a), float(b)
    if not (math.isfinite(a) and math.isfinite(b)) or not a < b:
        raise InputError(f"brent_minimum: [{a!r}, {b!r}] is not a finite interval with a < b")
    if xatol <= 0:
        raise InputError(f"brent_minimum: xatol {xatol!r} must be > 0")
    sqrt_eps = math.sqrt(EPS)
    x = w = v = a + _GOLDEN * (b - a)
    fx = fw = fv = float(f(x))
    d = e = 0.0
    for _ in range(maxiter):
        mid = 0.5 * (a + b)
        tol = sqrt_eps * abs(x) + xatol / 3.0
        tol2 = 2.0 * tol
        if abs(x - mid) <= tol2 - 0.5 * (b - a):
            return x, fx
        golden = True
        if abs(e) > tol:  # try the parabola through x, w, v
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            else:
                q = -q
            if abs(p) < abs(0.5 * q * e) and q * (a - x) < p < q * (b - x):
                e, d = d, p / q
                u = x + d
                if u - a < tol2 or b - u < tol2:  # not too close to the ends
                    d = tol if x < mid else -tol
                golden = False
        if golden:
            e = (b - x) if x < mid else (a - x)
            d = _GOLDEN * e
        u = x + (d if abs(d) >= tol else (tol if d >= 0 else -tol))
        fu = float(f(u))
        if fu <= fx:
            if u < x:
                b = x
            else:
                a = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    raise NoConvergence(f"brent_minimum: no convergence in {maxiter} iterations (x = {x!r})")
