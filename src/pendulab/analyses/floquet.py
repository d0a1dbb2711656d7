"""Exact Floquet analysis of Mathieu's equation in the source's form.

The linearised inverted pendulum in dimensionless time is (000 eq. 7)

    theta'' + (theta0 + 2 theta1 cos 2 tau) theta = 0,

which is DLMF 28.2.1, w'' + (a - 2 q cos 2z) w = 0, with a = theta0 and
q = -theta1.  With the Floquet ansatz theta = exp(i lam tau) sum_n b_n
exp(2 i n tau) (000 eq. 8) the coefficients obey (000 eqs. 9-10)

    theta1 b_{n-1} + C_n b_n + theta1 b_{n+1} = 0,   C_n = theta0 - (2n + lam)^2,

and lam is DLMF's characteristic exponent nu (DLMF 28.2.16-28.2.17).  The
coefficient has period pi in tau, so the Floquet multipliers are
exp(+- i pi lam) and the trace of the monodromy matrix is 2 cos(pi lam)
(DLMF 28.2.21: cos(pi nu) = w_I(pi)).

Conventions used throughout
---------------------------
* lam is the *unfolded* exponent: in the k-th stable band (k = 0, 1, ...)
  lam is real in (k, k + 1); in the k-th instability gap lam = k + i mu with
  mu > 0; below a_0 lam = i mu.  With theta1 = 0 this gives lam = sqrt(theta0)
  exactly (imaginary for theta0 < 0).
* The band index comes from counting the characteristic values (a_n and b_n
  of all orders, DLMF 28.2(v)) below theta0 with a Sturm sequence on the four
  tridiagonal matrices of DLMF 28.4.5-28.4.8: an odd count means the interior
  of a stable band, an even count an instability gap.
* Every method computes u = (lam - e)^2 for the nearest band edge e (an
  integer), which is a well-conditioned quantity even when lam sits at an
  edge; lam = e +- sqrt(u).  u > 0: stable, u < 0: unstable.

Three independent methods (``method=``)
---------------------------------------
"cf"        the source's continued fractions (000 sec. 2.2): the recurrence is
            closed by the minimal-solution continued fractions on both sides
            of a central block and the determinant of that block, an even
            function of lam - e, is solved for u.
"hill"      Hill's determinant (Whittaker & Watson sec. 19.42, after dividing
            row n by (2n + s)^2 - theta0): cos(pi lam) = cos(pi s)
            + Delta_s (cos(pi sqrt(theta0)) - cos(pi s)), where Delta_s is the
            normalised infinite determinant.  s = 0 gives the classical
            sin^2(pi lam/2) = Delta(0) sin^2(pi sqrt(theta0)/2); s = 1 is used
            when theta0 is near an even square, where the s = 0 normalisation
            divides by zero.  The truncated determinants converge only
            algebraically (error ~ N^-3), so the limit is taken by Richardson
            extrapolation in the truncation depth N.
"monodromy" integrates the even and odd solutions over half a period with a
            Taylor method at the working precision and uses
            w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1 (a consequence of the even,
            pi-periodic coefficient; DLMF 28.2(iv)).

Precision: mpmath precision is set per call with ``mpmath.workdps``; each
answer is computed at two working precisions and accepted only when they
agree to the digits asked; otherwise the working precision grows (up to
``max_dps``), and :class:`~pendulab.errors.PrecisionError` is raised if that
is not enough.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass
from fractions import Fraction

import mpmath

from pendulab.errors import AccuracyWarning, ConvergenceError, InputError, PrecisionError

__all__ = [
    "FloquetResult",
    "characteristic_exponent",
    "theta0_of_exponent",
    "mathieu_a",
    "mathieu_b",
    "stability_limits",
    "is_stable",
    "trace_monodromy",
    "stability_map",
    "map_stability",
    "map_limits",
    "first_band",
    "exponent",
    "METHODS",
    "SIZE_LIMITS",
    "SIZE_LIMIT",
]

METHODS = ("hill", "cf", "monodromy")

#: extra decimal digits carried beyond the precision asked for
GUARD = 10
#: precision used when ``dps=None`` (the result is then returned as float/complex)
DOUBLE_DPS = 16
MAX_DPS_LIMIT = 20000

#: Largest size S = |theta0| + 2|theta1| each method accepts.  The work of all
#: three grows with sqrt(S) (cf: block and tail length; hill: number of truncated
#: determinants and the Richardson guard digits; monodromy: Taylor steps and the
#: growth digits).  Measured in double precision (one run, 2-core machine):
#: hill 1.8 s at S = 2e6 (theta1 = 1e6), 9.7 s at S = 8e6; cf 3.2 s at S = 2e4,
#: 6.1 s at S = 3e4, and a PrecisionError after 18 s at S = 2e5; monodromy
#: 3.5 s at S = 2e3, 10 s at S = 6e3, 41 s at S = 2e4.
SIZE_LIMITS = {"hill": 4e6, "cf": 3e4, "monodromy": 5e3}
#: The same bound for the characteristic values (S = 2|q|), the stability limits
#: (S = 4 ratio^2) and the vectorised functions (the largest S of the arrays).
SIZE_LIMIT = 4e6


# ---------------------------------------------------------------------------
# input handling
# ---------------------------------------------------------------------------

_DEC = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def _exact(x, name):
    """Return ``x`` as an exact number (Fraction or mpf), or raise InputError.

    Strings may be decimals ("-0.002", "1e-3") or fractions ("1/5"); they are
    kept exact so that they can be rounded afresh at every working precision.
    """
    if isinstance(x, bool):
        raise InputError(f"{name} must be a real number, not a bool")
    if isinstance(x, (int, Fraction)):
        return Fraction(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            raise InputError(f"{name} must be finite, got {x!r}")
        return Fraction(x)
    if isinstance(x, mpmath.mpf):
        if not mpmath.isfinite(x):
            raise InputError(f"{name} must be finite, got {x}")
        return x
    if isinstance(x, str):
        s = x.strip()
        try:
            if "/" in s:
                num, den = s.split("/")
                num, den = num.strip(), den.strip()
                if not (_DEC.match(num) and _DEC.match(den)):
                    raise ValueError
                val = Fraction(num) / Fraction(den)
            else:
                if not _DEC.match(s):
                    raise ValueError
                val = Fraction(s)
        except (ValueError, ZeroDivisionError):
            raise InputError(f"{name} must be a real number such as -0.002 or 1/5, "
                             f"got {x!r}") from None
        return val
    try:  # numpy scalars, sympy numbers
        import numbers
        if isinstance(x, numbers.Rational):
            return Fraction(int(x.numerator), int(x.denominator))
        if isinstance(x, numbers.Real):
            return _exact(float(x), name)
    except (TypeError, ValueError):
        pass
    raise InputError(f"{name} must be a real number, got {type(x).__name__} {x!r}")


def _mp(v):
    """An exact value rounded to the current mpmath precision."""
    if isinstance(v, Fraction):
        if v.denominator == 1:
            return mpmath.mpf(v.numerator)
        return mpmath.mpf(v.numerator) / v.denominator
    return +v


def _check_dps(dps, name="dps"):
    if dps is None:
        return None
    if isinstance(dps, bool) or not isinstance(dps, int):
        raise InputError(f"{name} must be a positive integer or None, got {dps!r}")
    if dps < 1 or dps > MAX_DPS_LIMIT:
        raise InputError(f"{name} must be between 1 and {MAX_DPS_LIMIT}, got {dps}")
    return dps


def _size_text(v, above=None):
    """Short text of an exact value that may be far beyond the float range.

    With ``above`` (a limit that ``v`` exceeds) the text has as many digits (3 to 30) as
    it takes to read as more than the limit: 4000000.5, not 4.0e+6 next to 4e+06.
    """
    for digits in range(3, 31):
        with mpmath.workdps(digits + 5):
            text = mpmath.nstr(_mp(v), digits)
            if above is None or mpmath.mpf(text) > above:
                return text
    return text + " (just above)"


def _check_size(X0, X1, limit, what, names=("theta0", "theta1")):
    """InputError when S = |X0| + 2|X1| exceeds ``limit`` (exact comparison, so
    values beyond the float range such as 1e400 are refused, not overflowed)."""
    size = abs(X0) + 2 * abs(X1)
    if size > limit:
        raise InputError(f"|{names[0]}| + 2|{names[1]}| = {_size_text(size, limit)} is too large for "
                         f"{what} (limit {limit:g}; the work grows like its square root)")


def _is_zero(v):
    return v == 0


def _is_int_square(v):
    """Return k if the exact value v equals k**2 for an integer k >= 0, else None."""
    if isinstance(v, Fraction):
        if v.denominator != 1 or v < 0:
            return None
        k = math.isqrt(v.numerator)
        return k if k * k == v.numerator else None
    if v < 0 or not mpmath.isint(v):
        return None
    k = math.isqrt(int(v))
    return k if k * k == int(v) else None


# ---------------------------------------------------------------------------
# depth rules
# ---------------------------------------------------------------------------

def _edge_index(theta0, theta1):
    """Smallest even m0 >= 2 beyond which |C_m| > 2|theta1| (tails are minimal)."""
    m = math.sqrt(max(float(theta0), 0.0) + 2.0 * abs(float(theta1))) + 2.0
    m0 = int(math.ceil(m))
    return m0 + (m0 % 2)


def _tail_steps(theta0, theta1, m0, digits):
    """Number of continued-fraction levels (step 2 in the frequency index) past m0
    after which the neglected tail is below 10**-digits.

    Each level multiplies the tail by about theta1^2 / (C_m C_{m+2}) (000 eq. 10),
    so the count follows from a running product of those ratios.
    """
    t0, t1 = float(theta0), abs(float(theta1))
    if t1 == 0.0:
        return 1
    logsum, steps, m = 0.0, 0, m0
    target = -digits * math.log(10.0)
    while logsum > target:
        c1 = abs(t0 - m * m)
        c2 = abs(t0 - (m + 2) * (m + 2))
        logsum += 2.0 * math.log(t1) - math.log(c1) - math.log(c2)
        steps += 1
        m += 2
        if steps > 10 ** 6:  # pragma: no cover - unreachable for finite input
            raise ConvergenceError("continued-fraction tail did not converge")
    return steps + 2


# ---------------------------------------------------------------------------
# Sturm counts of the characteristic values (DLMF 28.4.5-28.4.8)
# ---------------------------------------------------------------------------

def _family_diagonals(family, q, n, one):
    """Diagonal and squared off-diagonal of the symmetric tridiagonal matrix whose
    eigenvalues are a_{2j} ("a_even"), a_{2j+1} ("a_odd"), b_{2j+1} ("b_odd") or
    b_{2j+2} ("b_even"), truncated to n rows (DLMF 28.4.5-28.4.8; the a_even
    matrix is symmetrised by scaling A_0 by sqrt 2)."""
    if family == "a_even":
        d = [one * (2 * j) ** 2 for j in range(n)]
        e2 = [q * q * (2 if j == 0 else 1) for j in range(n - 1)]
    elif family == "a_odd":
        d = [one * (2 * j + 1) ** 2 for j in range(n)]
        d[0] = d[0] + q
        e2 = [q * q for _ in range(n - 1)]
    elif family == "b_odd":
        d = [one * (2 * j + 1) ** 2 for j in range(n)]
        d[0] = d[0] - q
        e2 = [q * q for _ in range(n - 1)]
    elif family == "b_even":
        d = [one * (2 * j + 2) ** 2 for j in range(n)]
        e2 = [q * q for _ in range(n - 1)]
    else:  # pragma: no cover
        raise AssertionError(family)
    return d, e2


FAMILIES = ("a_even", "a_odd", "b_odd", "b_even")


def _sturm_count(d, e2, x):
    """Number of eigenvalues < x of the symmetric tridiagonal (d, e2) (LDL^T inertia)."""
    count = 0
    p = d[0] - x
    tiny = mpmath.mpf(2) ** (-mpmath.mp.prec - 20) if isinstance(x, mpmath.mpf) else 1e-300
    for i in range(len(d)):
        if i:
            p = d[i] - x - e2[i - 1] / p
        if p == 0:
            p = -tiny
        if p < 0:
            count += 1
    return count


def _edge_count(theta0, theta1, w):
    """Number of characteristic values a_n, b_n (all n) below theta0, at dps w."""
    q = -theta1
    m0 = _edge_index(theta0, theta1)
    n = m0 // 2 + _tail_steps(theta0, theta1, m0, w) + 2
    one = mpmath.mpf(1)
    total = 0
    for fam in FAMILIES:
        d, e2 = _family_diagonals(fam, q, n, one)
        total += _sturm_count(d, e2, theta0)
    return total


# ---------------------------------------------------------------------------
# method "cf": continued fractions (000 eqs. 8-10)
# ---------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------
# method "hill": Hill's determinant with Richardson extrapolation
# ---------------------------------------------------------------------------

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

        # continuants of the window [L, R]: K(L..R), K(L+1..R), K(L..R-1), K(L+1..R-1)
        klr, kl1r, klr1, kl1r1 = mpmath.mpf(1), mpmath.mpf(1), mpmath.mpf(1), mpmath.mpf(0)
        L = R = 0
        gR, gL = g(0), g(0)
        seq = []
        for _ in range(M):
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
            seq.append(klr)
        delta, _ = mpmath.richardson(seq)
        if x0 >= 0:
            cr = mpmath.cospi(mpmath.sqrt(x0))
        else:
            cr = mpmath.cosh(mpmath.pi * mpmath.sqrt(-x0))
        cs = 1 if s == 0 else -1
        y = cs + delta * (cr - cs)
    with mpmath.workdps(w):
        return +y, M


# ---------------------------------------------------------------------------
# method "monodromy": Taylor integration of the fundamental matrix
# ---------------------------------------------------------------------------

def _monodromy_y(X0, X1, w):
    """cos(pi lam) = w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1 by a Taylor method at dps w.

    Returns (y, order)."""
    omega = math.sqrt(abs(float(X0)) + 2 * abs(float(X1))) + 2.0
    nsteps = max(1, int(math.ceil((math.pi / 2) * omega / 1.5)))
    growth = math.exp(omega * math.pi / 2) ** 2  # bound on |fundamental matrix|^2
    wl = w + int(math.log10(growth)) + 5
    K = 0  # largest Taylor order used (reported as the depth)
    with mpmath.workdps(wl):
        x0, x1 = _mp(X0), _mp(X1)
        h = mpmath.pi / 2 / nsteps
        h2 = h * h
        states = [[mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(0), mpmath.mpf(1)]]
        for step in range(nsteps):
            tau0 = step * h
            c, s = mpmath.cos(2 * tau0), mpmath.sin(2 * tau0)
            cyc = (c, -s, -c, s)
            # P_j = p_j h^(j+2): Taylor coefficients of theta0 + 2 theta1 cos(2 tau);
            # the series is extended until two successive terms of both
            # solutions fall below 10^-(wl+5) (a posteriori truncation)
            P = []
            tol = mpmath.mpf(10) ** (-(wl + 5))

            def coef(j):
                while len(P) <= j:
                    i = len(P)
                    f = mpmath.mpf(1)
                    for r in range(1, i + 1):
                        f = f * 2 * h / r
                    P.append(2 * x1 * f * cyc[i % 4] * h2 + (x0 * h2 if i == 0 else 0))
                return P[j]

            zs = [[y0, yp * h] for y0, yp in states]
            k = 0
            while True:
                for z in zs:
                    acc = mpmath.fsum(coef(j) * z[k - j] for j in range(k + 1))
                    z.append(-acc / ((k + 1) * (k + 2)))
                k += 1
                if k > 8 and all(abs(z[-1]) + abs(z[-2]) < tol * (1 + abs(z[0]) + abs(z[1]))
                                 for z in zs):
                    break
                if k > 100000:  # pragma: no cover
                    raise ConvergenceError("Taylor series of the monodromy did not converge")
            K = max(K, k + 2)
            new = []
            for z in zs:
                yv = mpmath.fsum(z)
                ypv = mpmath.fsum(i * z[i] for i in range(1, len(z))) / h
                new.append([yv, ypv])
            states = new
        wI, wIp = states[0]
        wII, wIIp = states[1]
        y = 2 * wI * wIIp - 1
    with mpmath.workdps(w):
        return +y, K


# ---------------------------------------------------------------------------
# from cos(pi lam) to u = (lam - e)^2
# ---------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------
# characteristic values a_m(q), b_m(q) (DLMF notation)
# ---------------------------------------------------------------------------

def _family_of(kind, m):
    """(family, index within the family) of a_m or b_m (DLMF 28.4.5-28.4.8)."""
    if kind == "a":
        return ("a_even", m // 2) if m % 2 == 0 else ("a_odd", (m - 1) // 2)
    return ("b_odd", (m - 1) // 2) if m % 2 == 1 else ("b_even", m // 2 - 1)


def _family_size(j, q, digits):
    m0 = _edge_index(0, q)
    return j + 2 + m0 // 2 + _tail_steps(0, q, m0, digits) + _tail_steps(0, q, 2 * j + m0, digits)


def _double_char_value(family, j, qf):
    """Double-precision eigenvalue (and eigenvector peak) of the truncated matrix."""
    import numpy as np
    from scipy.linalg import eigh_tridiagonal

    n = _family_size(j, qf, 18)
    d, e2 = _family_diagonals(family, qf, n, 1.0)
    d = np.array(d, dtype=float)
    e = np.sqrt(np.array(e2, dtype=float))
    if n == 1:
        return float(d[0]), 0
    vals, vecs = eigh_tridiagonal(d, e, select="i", select_range=(j, j))
    return float(vals[0]), int(np.argmax(np.abs(vecs[:, 0])))


def _char_value_mp(family, j, q, w, guess=None):
    """Characteristic value at dps w (inside an active workdps): the root of the
    two-sided continued fraction centred on the dominant Fourier coefficient
    (the recurrences DLMF 28.4.5-28.4.8), bracketed around a double estimate."""
    qf = float(q)
    a0, centre = _double_char_value(family, j, qf)
    n = _family_size(j, qf, w + 5)
    n = max(n, centre + 3)
    d, e2 = _family_diagonals(family, q, n, mpmath.mpf(1))

    def G(a):
        # continued fraction from row 0 up to the centre, and from the
        # truncation depth down to the centre
        low = 0
        for i in range(centre):
            denom = d[i] - a - low
            low = e2[i] / denom
        up = 0
        for i in range(n - 1, centre, -1):
            up = e2[i - 1] / (d[i] - a - up)
        return d[centre] - a - low - up

    scale = max(1.0, abs(a0))
    delta = mpmath.mpf(1e-11 * scale)
    A = mpmath.mpf(a0)
    for _ in range(40):
        lo, hi = A - delta, A + delta
        glo, ghi = G(lo), G(hi)
        if (glo > 0) != (ghi > 0):
            break
        delta *= 8
    else:
        raise ConvergenceError(f"could not bracket the characteristic value ({family}, {j}, q={qf})")
    root, _ = _illinois(G, lo, hi, glo, ghi, mpmath.mpf(10) ** (-w) * scale)
    return root


def _char_value(kind, m, q, dps):
    name = f"mathieu_{kind}"
    if isinstance(m, bool) or not isinstance(m, int):
        raise InputError(f"{name}: order m must be an integer, got {m!r}")
    if kind == "a" and m < 0:
        raise InputError(f"{name}: order m must be >= 0, got {m}")
    if kind == "b" and m < 1:
        raise InputError(f"{name}: order m must be >= 1, got {m}")
    dps = _check_dps(dps)
    Q = _exact(q, "q")
    _check_size(m * m, Q, SIZE_LIMIT, name, names=("m^2", "q"))
    want = DOUBLE_DPS if dps is None else dps
    family, j = _family_of(kind, m)
    if Q == 0:
        val = mpmath.mpf(m * m)
        return float(val) if dps is None else val
    w = want + GUARD
    while True:
        with mpmath.workdps(w):
            v1 = _char_value_mp(family, j, _mp(Q), w)
        with mpmath.workdps(w + 10):
            v2 = _char_value_mp(family, j, _mp(Q), w + 10)
            ok = abs(v1 - v2) <= mpmath.mpf(10) ** (-(want + 2)) * max(1, abs(v2))
        if ok:
            break
        if w > 4 * want + 100:
            raise PrecisionError(f"{name}({m}, {q}) not resolved to {want} digits")
        w = 2 * w
    if dps is None:
        return float(v2)
    with mpmath.workdps(want):
        return +v2


def mathieu_a(m, q, dps=None):
    """Characteristic value a_m(q) of w'' + (a - 2q cos 2z) w = 0 (DLMF 28.2(v)).

    Eigenvalue of the tridiagonal recurrence DLMF 28.4.5 (m even) or 28.4.6
    (m odd), truncated at a depth that grows like sqrt(q) plus what the digits
    need, refined by the continued fraction at the working precision.  Works for
    q < 0 directly (it reproduces a_{2n}(-q) = a_{2n}(q) and
    a_{2n+1}(-q) = b_{2n+1}(q), DLMF 28.2.26-28.2.27) and for |q| up to 1e4
    and beyond.  dps=None returns a float; otherwise an mpf with dps digits.

    >>> round(mathieu_a(0, 1), 10)   # A&S Table 20.1: a_0(1) = -0.4551386041
    -0.4551386041
    """
    return _char_value("a", m, q, dps)


def mathieu_b(m, q, dps=None):
    """Characteristic value b_m(q), m >= 1 (DLMF 28.2(v); recurrences 28.4.7-28.4.8).

    See :func:`mathieu_a`; b_{2n+1}(-q) = a_{2n+1}(q) and b_{2n+2}(-q) = b_{2n+2}(q).
    """
    return _char_value("b", m, q, dps)


# ---------------------------------------------------------------------------
# inverse: theta0 for a given exponent nu
# ---------------------------------------------------------------------------

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

    absq = abs(X1)
    w = want + GUARD
    while True:
        vals = [_theta0_of_exponent_mp(NU, X1, absq, ww) for ww in (w, w + 10)]
        with mpmath.workdps(w + 10):
            if abs(vals[0] - vals[1]) <= mpmath.mpf(10) ** (-(want + 2)) * max(1, abs(vals[1])):
                break
        if w > 4 * want + 100:
            raise PrecisionError(f"theta0_of_exponent({nu}, {theta1}) not resolved to "
                                 f"{want} digits within {w + 10} working digits")
        w *= 2
    if dps is None:
        return float(vals[1])
    with mpmath.workdps(want):
        return +vals[1]


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


# ---------------------------------------------------------------------------
# stability limits of the inverted pendulum
# ---------------------------------------------------------------------------

def stability_limits(ratio, inertia_ratio=1, dps=None):
    """Exact limits (lower, upper) of a/l for the inverted pendulum to be stable.

    ratio = omega0/omega >= 0, inertia_ratio = I/(m l^2) > 0 (point mass 1,
    uniform rod pivoted at an end 4/3), for the source's drive a cos(omega t).
    theta0 and theta1 come from the derivation
    (:func:`pendulab.analyses.stability.body_map`: theta0 = -4 ratio^2, 000
    eq. 5, and theta1 = 2 (a/l)/inertia_ratio, 000 eq. 6); the first stable
    band of the Mathieu plane at that theta0 is :func:`first_band` (theta1
    from a_0(q) = theta0 to b_1(|q|) = theta0), divided by theta1/(a/l).
    Only this first band is reported; for large ratio further, exponentially
    thin bands exist at much larger a/l.

    >>> lo, up = stability_limits(0, 1)
    >>> lo, round(up, 6)
    (0.0, 0.454...)
    """
    from pendulab.analyses.stability import body_map

    R, IR = _exact(ratio, "ratio"), _exact(inertia_ratio, "inertia_ratio")
    if R < 0:
        raise InputError(f"ratio = omega0/omega must be >= 0, got {ratio}")
    if IR <= 0:
        raise InputError(f"inertia_ratio = I/(m l^2) must be > 0, got {inertia_ratio}")
    if 4 * R * R > SIZE_LIMIT:
        raise InputError(f"ratio = omega0/omega must be <= {math.sqrt(SIZE_LIMIT / 4):g} "
                         f"(|theta0| = 4 ratio^2 <= {SIZE_LIMIT:g}), got {ratio}")
    return map_limits(body_map(), {"w0_over_w": R, "inertia_ratio": IR}, dps,
                      what=f"stability_limits({ratio})")


def map_limits(pmap, point, dps=None, what="the limits"):
    """(lower, upper) of a/l in the first stable band for a ParameterMap at ``point``.

    ``pmap`` is a :class:`pendulab.analyses.stability.ParameterMap` of a
    Mathieu drive whose theta1 is proportional to a/l; ``point`` gives the
    other groups ({"w0_over_w": ..., "inertia_ratio": ...}; exact values such
    as Fraction or decimal text are rounded afresh at each working precision).
    theta0 and the scale (a/l)/theta1 are evaluated with the map's mpmath
    function at the working precision, the band by :func:`first_band`.
    """
    dps = _check_dps(dps)
    exact = {k: (v if isinstance(v, (Fraction, mpmath.mpf)) else _exact(v, k))
             for k, v in point.items()}

    def band(ww):
        args = {k: _mp(v) for k, v in exact.items()}
        th0 = pmap.evaluate("theta0", args, "mpmath")
        scale = abs(pmap.evaluate("scale", args, "mpmath"))
        lo, up = _first_band_mp(th0, ww)
        return lo * scale, up * scale
    return _band_at_two_precisions(band, dps, what)


def first_band(theta0, dps=None):
    """(lower, upper) |theta1| of the first stable band of 000 eq. 7 at a given theta0 < 1.

    The band is a_0(q) < theta0 < b_1(|q|) with |q| = |theta1| (DLMF 28.2(v);
    a_0 is even in q, b_1(|q|) = a_1(-|q|)): the lower end solves
    a_0(q) = theta0 (0 when theta0 >= 0), the upper one b_1(q) = theta0, each
    by Brent's method on the exact characteristic values.

    >>> lo, up = first_band(-0.01)
    >>> round(lo, 10), round(up, 10)
    (0.1415759161, 0.9164371642)
    >>> round(mathieu_a(0, lo), 12), round(mathieu_b(1, up), 12)   # on the two curves
    (-0.01, -0.01)
    """
    dps = _check_dps(dps)
    X0 = _exact(theta0, "theta0")
    if X0 >= 1:
        raise InputError(f"theta0 = {theta0} >= 1: the first stable band at theta0 >= 1 "
                         "is not the one that starts at theta1 = 0")
    if abs(X0) > SIZE_LIMIT:
        raise InputError(f"|theta0| = {_size_text(abs(X0), SIZE_LIMIT)} is too large (limit {SIZE_LIMIT:g})")
    return _band_at_two_precisions(lambda ww: _first_band_mp(_mp(X0), ww), dps,
                                   f"first_band({theta0})")


def _band_at_two_precisions(band, dps, what):
    """``band(ww)`` (a pair, computed at working precision ww) resolved to ``dps`` digits.

    Computed at w and w + 10 digits (w = dps + GUARD, doubled until both agree
    to dps + 2 digits); a float pair when ``dps`` is None.
    """
    want = DOUBLE_DPS if dps is None else dps
    w = want + GUARD
    while True:
        res = []
        for ww in (w, w + 10):
            with mpmath.workdps(ww):
                res.append(band(ww))
        with mpmath.workdps(w + 10):
            ok = all(abs(a - b) <= mpmath.mpf(10) ** (-(want + 2)) * max(1, abs(b))
                     for a, b in zip(res[0], res[1]))
        if ok:
            break
        if w > 4 * want + 100:
            raise PrecisionError(f"{what} not resolved to {want} digits")
        w *= 2
    lower, upper = res[1]
    if dps is None:
        return float(lower), float(upper)
    with mpmath.workdps(want):
        return +lower, +upper


def _first_band_mp(th0, w):
    """|q| at the ends of the first band at theta0 = th0 (an mpf, th0 < 1), at dps w."""
    if th0 >= 1:
        raise InputError(f"theta0 = {mpmath.nstr(th0, 8)} >= 1: the first stable band at "
                         "theta0 >= 1 is not the one that starts at theta1 = 0")
    with mpmath.workdps(w):
        out = []
        for family in ("a_even", "b_odd"):
            if family == "a_even" and th0 >= 0:
                out.append(mpmath.mpf(0))
                continue

            def h(q, family=family):
                return _char_value_mp(family, 0, q, w) - th0

            Q = mpmath.mpf(1)
            while h(Q) > 0:
                Q *= 2
            lo = Q / 2 if Q > 1 else mpmath.mpf(0)
            if family == "a_even":
                lo = mpmath.mpf(0)
                hlo = -th0
            else:
                hlo = h(lo) if lo > 0 else 1 - th0
            root, _ = _illinois(h, lo, Q, hlo, h(Q), mpmath.mpf(10) ** (-w) * Q)
            out.append(root)
        return tuple(out)


# ---------------------------------------------------------------------------
# vectorised double precision
# ---------------------------------------------------------------------------

def _edges_double(absq, theta0_max):
    """Sorted characteristic values a_n(absq), b_n(absq) up to beyond theta0_max."""
    import numpy as np
    from scipy.linalg import eigvalsh_tridiagonal

    top = max(float(theta0_max), 0.0) + 2.0 * absq
    m0 = _edge_index(top, absq)
    n = m0 // 2 + _tail_steps(top, absq, m0, 18) + 3
    out = []
    for fam in FAMILIES:
        d, e2 = _family_diagonals(fam, absq, n, 1.0)
        vals = eigvalsh_tridiagonal(np.asarray(d, float), np.sqrt(np.asarray(e2, float)))
        out.append(vals[vals <= top + 1.0])
    return np.sort(np.concatenate(out))


def _real_arrays(x, y, names):
    """Two finite float arrays broadcast together; one-line InputError otherwise."""
    import numpy as np

    a, b = names
    try:
        xa = np.asarray(x, dtype=float)
        ya = np.asarray(y, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{a} and {b} must be real numbers or arrays of them") from None
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ya))):
        raise InputError(f"{a} and {b} must be finite (no nan or inf)")
    try:
        return np.broadcast_arrays(xa, ya)
    except ValueError:
        raise InputError(f"{a} and {b} cannot be broadcast together "
                         f"(shapes {xa.shape} and {ya.shape})") from None


def _check_arrays(theta0, theta1):
    import numpy as np

    x0, x1 = _real_arrays(theta0, theta1, ("theta0", "theta1"))
    if x0.size:
        size = float(np.max(np.abs(x0) + 2.0 * np.abs(x1)))
        if size > SIZE_LIMIT:
            raise InputError(f"|theta0| + 2|theta1| = {size:.3g} is too large for the "
                             f"vectorised functions (limit {SIZE_LIMIT:g})")
    return x0, x1


def _is_array(x):
    """True for inputs the vectorised routines take (numpy arrays, lists, tuples)."""
    import numpy as np
    return isinstance(x, (np.ndarray, list, tuple))


def _bands_double(f0, f1):
    """For flat float arrays theta0, theta1: the number of characteristic values
    below each theta0 and the values just below and above it (-inf/inf at the
    ends), from one eigenproblem per distinct |theta1| (see :func:`is_stable`)."""
    import numpy as np

    absq = np.abs(f1)
    cnt = np.zeros(f0.shape, dtype=int)
    below = np.full(f0.shape, -np.inf)
    above = np.full(f0.shape, np.inf)
    if f0.size == 0:
        return cnt, below, above
    qs, inverse = np.unique(absq, return_inverse=True)
    for i, q in enumerate(qs):
        idx = np.nonzero(inverse == i)[0]
        th = f0[idx]
        # reach beyond the next edge above every theta0 (edges near n^2 lie
        # within ~2|q| + 2n of it)
        reach = (math.sqrt(max(float(th.max()), 0.0) + 2.0 * float(q)) + 3.0) ** 2
        edges = _edges_double(float(q), reach)
        c = np.searchsorted(edges, th, side="left")
        cnt[idx] = c
        below[idx] = np.where(c > 0, edges[np.clip(c - 1, 0, edges.size - 1)], -np.inf)
        above[idx] = np.where(c < edges.size, edges[np.clip(c, 0, edges.size - 1)], np.inf)
    return cnt, below, above


def exponent(theta0, theta1):
    """Vectorised characteristic exponent lam of 000 eq. 7 in double precision.

    theta0, theta1 broadcast against each other; returns a complex array of the
    broadcast shape with the same unfolded lam as :func:`characteristic_exponent`
    (real in (k, k+1) in the k-th stable band, k + i mu in the k-th gap, i mu
    below a_0; ``.real`` is the exponent in the bands).

    The band index comes from the count of characteristic values below theta0
    (eigenvalues of the DLMF 28.4 matrices, as in :func:`is_stable`) and fixes
    the branch; the trace y = cos(pi lam) comes from Hill's determinant
    (:func:`trace_monodromy`).  Near a band edge E with exponent e, lam - e
    would follow from 1 - (-1)^e y, which cancels; it is taken instead as
    d = (-1)^e (y(E) - y(theta0)) with y(E) computed by the same routine, so
    that the (smooth) truncation error of the trace cancels too:
    d = 2 sin^2(pi (lam - e)/2) in a band, -2 sinh^2(pi mu/2) in a gap.
    Accuracy (measured against 25-digit characteristic_exponent on random
    points, tests/test_floquet_vectorised.py): about 1e-9 absolute in lam for
    |theta0|, |theta1| <= 20, also next to the edges (where lam itself depends
    on theta0 like a square root: an input error of 1e-16 moves it by ~1e-8).
    Points whose trace overflows a double (|Im lam| > ~200) are computed one by
    one with characteristic_exponent (double precision, method "hill").
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    out = np.zeros(f0.shape, dtype=complex)
    if f0.size == 0:
        return out.reshape(shape)
    cnt, below, above = _bands_double(f0, f1)
    y = trace_monodromy(f0, f1) / 2.0
    band = cnt % 2 == 1
    k = np.where(band, (cnt - 1) // 2, cnt // 2)
    # edge e and its theta0-value E: in band k the lower edge (e = k) when
    # (-1)^k y >= 0 (lam - k <= 1/2), else the upper one (e = k + 1); in gap k
    # (e = k) the nearer of its two edges
    sk = np.where(k % 2 == 0, 1.0, -1.0)
    lower_half = sk * y >= 0
    e = np.where(band, np.where(lower_half, k, k + 1), k)
    near_below = np.abs(f0 - below) <= np.abs(above - f0)
    E = np.where(band, np.where(lower_half, below, above), np.where(near_below, below, above))
    E = np.where(np.isfinite(E), E, f0)  # below a_0 with no edge below: any finite value
    yE = trace_monodromy(E, f1) / 2.0
    se = np.where(e % 2 == 0, 1.0, -1.0)
    with np.errstate(invalid="ignore", over="ignore"):
        d = se * (yE - y)
        t = 2.0 / np.pi * np.arcsin(np.sqrt(np.clip(d, 0.0, 2.0) / 2.0))
        mu = 2.0 / np.pi * np.arcsinh(np.sqrt(np.maximum(-d, 0.0) / 2.0))
    sign = np.where(e == k, 1.0, -1.0)
    out = np.where(band, e + sign * t + 0j, e + 1j * mu)
    bad = ~(np.isfinite(y) & np.isfinite(yE) & (np.abs(y) < 1e300))
    for i in np.nonzero(bad)[0]:
        out[i] = complex(characteristic_exponent(float(f0[i]), float(f1[i])).lam)
    return out.reshape(shape)


def _char_values_double(theta1_values, kind_order):
    """a_n(q) or b_n(q), q = -theta1, for each distinct theta1 (double precision).

    kind_order: list of ("a"|"b", n); returns dict (theta1, kind, n) -> value."""
    import numpy as np
    from scipy.linalg import eigvalsh_tridiagonal

    out = {}
    top = max(n for _, n in kind_order) if kind_order else 0
    for th1 in np.unique(theta1_values):
        q = -float(th1)
        size = float(top * top) + 2.0 * abs(q)
        m0 = _edge_index(size, q)
        n = m0 // 2 + top // 2 + _tail_steps(size, q, m0, 18) + 3
        vals = {}
        for fam in FAMILIES:
            d, e2 = _family_diagonals(fam, q, n, 1.0)
            vals[fam] = np.sort(eigvalsh_tridiagonal(np.asarray(d, float),
                                                     np.sqrt(np.asarray(e2, float))))
        for kind, m in kind_order:
            fam, j = _family_of(kind, m)
            out[(float(th1), kind, m)] = float(vals[fam][j])
    return out


def _theta0_of_exponent_array(nu, theta1):
    """Vectorised theta0_of_exponent in double precision (see its docstring).

    Non-integer nu: bisection in the band [lo, hi] (edges from :func:`_bands_double`
    at the band's midpoint count) on d(theta0) = d*, with d the edge-referenced
    trace difference of :func:`exponent` and d* = 2 sin^2(pi (nu - e)/2) for the
    integer e nearest nu; d is monotone in the band.  Integer nu: a_nu(q), q = -theta1.
    """
    import numpy as np

    n_arr, t_arr = _real_arrays(nu, theta1, ("nu", "theta1"))
    n_arr = np.abs(n_arr)
    shape = n_arr.shape
    fn, f1 = n_arr.ravel().copy(), t_arr.ravel().copy()
    out = np.empty(fn.shape)
    if fn.size == 0:
        return out.reshape(shape)
    size = float(np.max(fn * fn + 2.0 * np.abs(f1)))
    if size > SIZE_LIMIT:
        raise InputError(f"|nu^2| + 2|theta1| = {size:.3g} is too large for the "
                         f"vectorised functions (limit {SIZE_LIMIT:g})")
    zero_q = f1 == 0
    is_int = (fn == np.floor(fn)) & ~zero_q
    out[zero_q] = fn[zero_q] ** 2
    if np.any(is_int):
        ii = np.nonzero(is_int)[0]
        orders = sorted({("a", int(v)) for v in fn[ii]})
        vals = _char_values_double(f1[ii], orders)
        out[ii] = [vals[(float(t), "a", int(v))] for t, v in zip(f1[ii], fn[ii])]
    todo = np.nonzero(~zero_q & ~is_int)[0]
    if todo.size:
        nu_t, q_t = fn[todo], f1[todo]
        k = np.floor(nu_t).astype(int)
        e = np.rint(nu_t).astype(int)
        # band edges: the (2k+1)-th and (2k+2)-th characteristic values at |q|
        lo = np.empty(todo.size)
        hi = np.empty(todo.size)
        for q in np.unique(np.abs(q_t)):
            idx = np.nonzero(np.abs(q_t) == q)[0]
            top = float((k[idx].max() + 1) ** 2) + 2.0 * q + 1.0
            edges = _edges_double(float(q), top)
            lo[idx] = edges[2 * k[idx]]
            hi[idx] = edges[2 * k[idx] + 1]
        E = np.where(e == k, lo, hi)
        se = np.where(e % 2 == 0, 1.0, -1.0)
        yE = trace_monodromy(E, q_t) / 2.0
        target = 2.0 * np.sin(np.pi * (nu_t - e) / 2.0) ** 2
        # d(theta0) - target is > 0 on the side of E's far end: orient so that
        # phi = (d - target) * orient is increasing in theta0
        orient = np.where(e == k, 1.0, -1.0)
        a, b = lo.copy(), hi.copy()
        for _ in range(200):
            mid = 0.5 * (a + b)
            d = se * (yE - trace_monodromy(mid, q_t) / 2.0)
            phi = (d - target) * orient
            a = np.where(phi < 0, mid, a)
            b = np.where(phi < 0, b, mid)
            if np.all(b - a <= 4e-16 * np.maximum(1.0, np.abs(mid))):
                break
        out[todo] = 0.5 * (a + b)
    return out.reshape(shape)


def is_stable(theta0, theta1, rtol=1e-12):
    """Vectorised stable/unstable verdict for 000 eq. 7 in double precision.

    theta0, theta1 broadcast against each other (numpy arrays or scalars); the
    result is a bool array of the broadcast shape.  A point is stable when an
    odd number of characteristic values a_n(|theta1|), b_n(|theta1|) lie below
    theta0, i.e. inside a stable band.  The characteristic values are
    eigenvalues of the DLMF 28.4 tridiagonal matrices, computed once for each
    distinct |theta1| (so a grid costs one small eigenproblem per row), then
    compared with all theta0 at once.  Points closer than rtol (relative) to a
    characteristic value cannot be classified reliably in double precision: an
    AccuracyWarning says how many; use characteristic_exponent with dps there.
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel(), np.abs(x1.ravel())
    out = np.zeros(f0.shape, dtype=bool)
    close = 0
    if f0.size == 0:
        return out.reshape(shape)
    qs, inverse = np.unique(f1, return_inverse=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.searchsorted(inverse[order], np.arange(len(qs) + 1))
    for i, q in enumerate(qs):
        idx = order[bounds[i]:bounds[i + 1]]
        th = f0[idx]
        edges = _edges_double(float(q), th.max())
        cnt = np.searchsorted(edges, th, side="left")
        out[idx] = (cnt % 2) == 1
        if edges.size and q != 0:  # at q = 0 the edges k^2 are exact
            lo = edges[np.clip(cnt - 1, 0, edges.size - 1)]
            hi = edges[np.clip(cnt, 0, edges.size - 1)]
            dist = np.minimum(np.abs(th - lo), np.abs(th - hi))
            close += int(np.count_nonzero(dist <= rtol * np.maximum(1.0, np.abs(th)) * (1 + q)))
    if close:
        warnings.warn(f"is_stable: {close} point(s) lie within double-precision "
                      f"resolution of a characteristic curve; their verdict is not "
                      f"reliable (use characteristic_exponent with dps)",
                      AccuracyWarning, stacklevel=2)
    return out.reshape(shape)


def trace_monodromy(theta0, theta1):
    """Vectorised trace of the monodromy matrix, 2 cos(pi lam), in double precision.

    Hill's determinant (see the module docstring) evaluated for all points at
    once by the symmetric continuant recurrence; the algebraic truncation error
    (N^-3, N^-4, ...) is removed by Richardson extrapolation over the depths
    N0, 2 N0, 4 N0, 8 N0.  Accurate to about 1e-11 relative to
    max(1, |trace|) for moderate parameters; overflows to inf for very large q.
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    # shift s per point (vectorised form of _hill_shift)
    r = np.sqrt(np.maximum(f0, 0.0))
    s = np.where(f0 <= 0.25, np.where(f0 > -1.0, 1, 0), np.where(np.rint(r) % 2 == 0, 1, 0))
    N0 = int(2 * math.ceil(math.sqrt(float(np.max(np.abs(f0)) + 2 * np.max(np.abs(f1)))))) + 24
    checkpoints = {N0 * 2 ** j: j for j in range(4)}
    one = np.ones_like(f0)

    def g(n):
        return f1 / ((2 * n + s) ** 2 - f0)

    klr, kl1r, klr1, kl1r1 = one.copy(), one.copy(), one.copy(), np.zeros_like(f0)
    L = R = 0
    gR = gL = g(0)
    D = [None] * 4
    with np.errstate(over="ignore", invalid="ignore"):
        for N in range(1, N0 * 8 + 1):
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
            if N in checkpoints:
                D[checkpoints[N]] = klr.copy()
        # remove N^-3, N^-4, N^-5 terms
        T = D
        for p in (3, 4, 5):
            fac = 2.0 ** p
            T = [(fac * T[i + 1] - T[i]) / (fac - 1) for i in range(len(T) - 1)]
        delta = T[0]
        cr = np.where(f0 >= 0, np.cos(np.pi * r), np.cosh(np.pi * np.sqrt(np.maximum(-f0, 0.0))))
        cs = np.where(s == 0, 1.0, -1.0)
        y = cs + delta * (cr - cs)
    return (2.0 * y).reshape(shape)


def stability_map(al_values, ratio_values, inertia_ratio=1.0):
    """Stable/unstable map of the inverted pendulum on a grid.

    Returns a bool array of shape (len(ratio_values), len(al_values)):
    entry [i, j] is True when a/l = al_values[j] stabilises the inverted
    position at omega0/omega = ratio_values[i] (theta0 = -4 ratio^2,
    theta1 = 2 (a/l)/inertia_ratio; 000 eqs. 5-6).
    """
    import numpy as np

    from pendulab.analyses.stability import body_map

    if not (isinstance(inertia_ratio, (int, float)) and inertia_ratio > 0):
        raise InputError(f"inertia_ratio must be a positive number, got {inertia_ratio!r}")
    al = np.asarray(al_values, dtype=float)
    ra = np.asarray(ratio_values, dtype=float)
    if al.ndim != 1 or ra.ndim != 1:
        raise InputError("al_values and ratio_values must be one-dimensional")
    return map_stability(body_map(), al, ra, inertia_ratio=float(inertia_ratio))


def map_stability(pmap, al_values, ratio_values, **groups):
    """Stable/unstable map [ratio, a/l] of a Mathieu drive's ParameterMap (vectorised).

    theta0, theta1 from the map's NumPy function at every grid point (the other
    groups, e.g. inertia_ratio, fixed by ``groups``), then :func:`is_stable`.
    """
    import numpy as np

    al = np.asarray(al_values, dtype=float)[None, :]
    ra = np.asarray(ratio_values, dtype=float)[:, None]
    point = dict(groups, a_over_l=al, w0_over_w=ra)
    th0 = np.broadcast_to(pmap.evaluate("theta0", point), (ra.shape[0], al.shape[1]))
    th1 = np.broadcast_to(pmap.evaluate("theta1", point), (ra.shape[0], al.shape[1]))
    return is_stable(th0, th1)
