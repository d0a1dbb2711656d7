"""The source's perturbation series to any order, and the integer-order series.

Mathieu's equation in the source's form (000 eq. 7)::

    theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0

is DLMF's w'' + (a - 2q cos 2z) w = 0 with a = theta0, q = -theta1.

**Non-integer nu** (000 sec. 3).  With theta0 = nu^2 + sum_n alpha_n theta1^n
(000 eq. 20) and theta_c = cos(nu tau) + sum_n c_n(tau) theta1^n (000 eq. 21),
the coefficient of theta1^n in the equation is (000 eq. 24)::

    c_n'' + nu^2 c_n + alpha_n cos(nu tau) + sum_{m=1}^{n-1} alpha_m c_{n-m}
        + 2 cos(2 tau) c_{n-1} = 0.

Write c_n = sum_k C[n][k] cos((nu + 2k) tau).  Since
(d^2/dtau^2 + nu^2) cos((nu + 2k) tau) = -4k(nu + k) cos((nu + 2k) tau) and
2 cos 2tau cos x = cos(x + 2 tau) + cos(x - 2 tau) (000 eq. 26), the
cos((nu + 2k) tau) component G_k of the known part of eq. 24,

    G_k = C[n-1][k-1] + C[n-1][k+1] + sum_{m=2}^{n-1} alpha_m C[n-m][k],

gives alpha_n = -G_0 (no secular term; the source's normalisation keeps
C[n][0] = 0 for n >= 1) and C[n][k] = G_k / (4k(nu + k)) for k != 0.  The sine
series (000 eq. 22) obeys the same recursion (2 cos 2tau sin x = sin(x + 2tau) +
sin(x - 2tau)), so s_n has the same coefficients with sines.  The equation is
unchanged by nu -> -nu, k -> -k, hence C[n][-k](nu) = C[n][k](-nu) and only
k > 0 is computed.  Coefficients are exact rational functions of nu
(:mod:`pendulab.analyses.series_ratfun`); the computed orders are kept and a
request for a higher order extends them.

**Integer order** (DLMF 28.6).  At nu = m the recursion divides by zero.  The
characteristic values a_m(q), b_m(q) are instead found on the Fourier basis
of each parity class (cos(2rz),
cos((2r+1)z), sin((2r+1)z), sin((2r+2)z), DLMF 28.4), where the unperturbed
value m^2 is simple: the action of 2 cos 2z on the basis is worked out from
the product formula (with cos(-x) = cos x, sin(-x) = -sin x, sin 0 = 0), and
a_m(q) or b_m(q) is the root of the truncated Hill determinant that starts at
m^2, lifted as an exact rational power series by Newton's iteration
(:class:`_CharEngine`).

Example (000 eq. 27 and c_1, found by the recursion):

>>> S = mathieu_series(2)
>>> S.alpha_raw[2].text()
'1/(2*(nu - 1)*(nu + 1))'
>>> [(k, v.text()) for k, v in S.c_raw[1]]
[(-1, '-1/(4*(nu - 1))'), (1, '1/(4*(nu + 1))')]
>>> str(characteristic_series("a0", 8).coefficients[8])   # DLMF 28.6.1
'68687/18874368'
"""

import functools
import math
import threading
import warnings
from fractions import Fraction

from pendulab.analyses.mathieu_radii import BRANCH_POINTS as _BRANCH_POINTS
from pendulab.analyses.series_ratfun import ONE, ZERO, linear_sum, reduce, reflect
from pendulab.errors import AccuracyWarning, InputError, SeriesDomainError

__all__ = [
    "MathieuSeries", "CharacteristicSeries", "mathieu_series", "characteristic_series",
    "theta0_of_nu", "theta_c", "theta_s", "stability_interval_series",
    "stability_interval_integer_series", "RADII", "MAX_ORDER", "INTEGER_TOLERANCE",
    "parity_rows",
]

#: Highest order accepted (the nu series: order 100 takes about 25 s, 150 a few minutes; docs/series.md).
MAX_ORDER = 400
#: nu closer than this to a nonzero integer is refused (the series has poles there).
INTEGER_TOLERANCE = 1e-6

# Radii of convergence of the series of a_m(q), b_m(q): the distance to the nearest
# branch point on each one's sheet, computed by pendulab.analyses.mathieu_branch and
# shipped (generated, checked by tests/test_mathieu_branch.py) as
# pendulab.analyses.mathieu_radii, rows n = 0 .. 15 of DLMF Table 28.6.1's layout:
# rho_n^(1) for a_{2n}, rho_n^(2) for b_{2n+2}, rho_n^(3) for a_{2n+1} and b_{2n+1}.
# DLMF Table 28.6.1 (from Meixner et al. 1980, sec. 2.4) tabulates rows 0 .. 9.
_DLMF_TABLE_ROWS = 10


def _radius_row(letter, m):
    """The row n of DLMF Table 28.6.1's layout that holds the radius of a_m or b_m."""
    if letter == "a" and m % 2 == 0:
        return m // 2
    if letter == "b" and m % 2 == 0:
        return m // 2 - 1
    return (m - 1) // 2


def _table_radius(letter, m, text=False):
    """Radius of convergence of the series of a_m or b_m, computed (None beyond the table):
    a float, or with ``text`` the table's decimal string."""
    entry = _BRANCH_POINTS.get(f"{letter}{m}")
    if entry is None:
        return None
    return entry[0] if text else float(entry[0])


def _radius_source(letter, m):
    if _table_radius(letter, m) is None:
        return "not computed (beyond the computed table of radii)"
    if _radius_row(letter, m) < _DLMF_TABLE_ROWS:
        return "computed branch point, DLMF Table 28.6.1"
    return "computed branch point, beyond DLMF Table 28.6.1"


#: kind -> radius of convergence (computed branch point) for every kind of the table
RADII = {kind: float(entry[0]) for kind, entry in _BRANCH_POINTS.items()}


def _check_order(order, minimum=1):
    if isinstance(order, bool) or not isinstance(order, int):
        raise InputError(f"series order must be an integer, got {order!r}")
    if not minimum <= order <= MAX_ORDER:
        raise InputError(f"series order must be between {minimum} and {MAX_ORDER}, got {order}")
    return order


def _check_on_domain(on_domain, allowed=("raise", "warn")):
    if on_domain not in allowed:
        names = " or ".join(", ".join(repr(a) for a in allowed).rsplit(", ", 1))
        raise InputError(f"on_domain must be {names}, got {on_domain!r}")
    return on_domain


# =====================================================================================
# Exact series for non-integer nu
# =====================================================================================

class _Growing:
    """Orders computed so far, appended to by ``_next`` on demand and never recomputed."""

    def __init__(self):
        self.lock = threading.Lock()

    def extend(self, order):
        with self.lock:
            while self.order < order:
                self._next()


class _Engine(_Growing):
    """The computed orders of 000 eqs. 20-24."""

    def __init__(self):
        super().__init__()
        self.alpha = [ZERO, ZERO]          # alpha[n]; alpha_0 is unused, alpha_1 = 0
        self.c = [{0: ONE}]                # c[n][k] for k > 0 (and c[0][0] = 1)

    @property
    def order(self):
        return len(self.c) - 1

    def coefficient(self, n, k):
        """C[n][k] for any integer k (reflection for k < 0)."""
        if k >= 0:
            return self.c[n].get(k, ZERO)
        value = self.c[n].get(-k)
        return ZERO if value is None else reflect(value)

    def _next(self):
        n = self.order + 1
        alpha, c = self.alpha, self.c
        if n >= 2:
            # alpha_n = -G_0 = -(C[n-1][-1] + C[n-1][1]); the alpha_m C[n-m][0] vanish.
            g0 = reduce(linear_sum([(self.coefficient(n - 1, -1),), (self.coefficient(n - 1, 1),)]))
            alpha.append(g0.negated())
        row = {}
        for k in range(2 - n % 2, n + 1, 2):
            terms = [(self.coefficient(n - 1, k - 1),), (self.coefficient(n - 1, k + 1),)]
            # C[n][k] != 0 only for k of the parity of n, so alpha_n = -(C[n-1][-1] + C[n-1][1])
            # vanishes for odd n: only even m contribute (and C[n-m][k] needs |k| <= n - m).
            for m in range(2, n - k + 1, 2):
                if not alpha[m].is_zero() and k in c[n - m]:
                    terms.append((alpha[m], c[n - m][k]))
            g = linear_sum(terms)
            if not g.is_zero():
                row[k] = reduce(g.divided_by_linear(4 * k, k))
        c.append(row)


_ENGINE = _Engine()


class MathieuSeries:
    """The series of 000 eqs. 20-22 truncated at ``order`` (exact, symbolic).

    Attributes (n = 1 .. order):

    * ``alpha[n]`` - SymPy rational function of ``nu`` (000 eq. 20); zero for odd n;
    * ``c[n]`` - list of ``(k, coeff)``, k != 0 increasing: c_n(tau) =
      sum coeff * cos((nu + 2k) tau) (000 eq. 21);
    * ``s[n]`` - the same list for s_n(tau) = sum coeff * sin((nu + 2k) tau) (000 eq. 22);
    * ``alpha_raw``, ``c_raw`` - the same data as :class:`~pendulab.analyses.series_ratfun.RatFun`.

    SymPy expressions are built on first access and kept.
    """

    def __init__(self, order, engine):
        self.order = order
        self._engine = engine
        self.alpha_raw = {n: engine.alpha[n] for n in range(1, order + 1)}
        self.c_raw = {n: sorted([(k, v) for k, v in engine.c[n].items()]
                                + [(-k, reflect(v)) for k, v in engine.c[n].items()])
                      for n in range(1, order + 1)}
        self._alpha = None
        self._c = None

    @property
    def alpha(self):
        if self._alpha is None:
            from pendulab.symbols import nu
            self._alpha = {n: v.to_sympy(nu) for n, v in self.alpha_raw.items()}
        return self._alpha

    @property
    def c(self):
        if self._c is None:
            from pendulab.symbols import nu
            self._c = {n: [(k, v.to_sympy(nu)) for k, v in row] for n, row in self.c_raw.items()}
        return self._c

    @property
    def s(self):
        # Same recursion with sines (000 eq. 22): identical coefficients.
        return self.c

    def _repr_latex_(self):
        """The coefficients alpha_n and C_{n,k} as the product "series" prints them
        (:func:`pendulab.latex.mathieu_series_blocks`), for a notebook; None (no LaTeX, the
        notebook shows the plain repr) beyond the order a LaTeX fragment goes to
        (``pendulab.limits.LIMITS["latex.nu_order"]``: order 30 is about 560 pages)."""
        from pendulab.latex import align, mathieu_series_blocks
        from pendulab.limits import LIMITS
        if self.order > LIMITS["latex.nu_order"][2]:
            return None
        head = align([
            rf"\theta_0 &= \nu^2 + \sum_{{n=1}}^{{{self.order}}} \alpha_n \theta_1^n"
            r" + O(\theta_1^{" + str(self.order + 1) + "})",
            r"c_n(\tau) &= \sum_k C_{n,k} \cos((\nu + 2k)\tau)",
            r"s_n(\tau) &= \sum_k C_{n,k} \sin((\nu + 2k)\tau)"])
        return "\n".join([head] + mathieu_series_blocks(self))

    def theta0_expr(self, theta1=None):
        """nu^2 + sum_n alpha_n theta1^n as one SymPy expression (000 eq. 20 truncated)."""
        from pendulab import symbols as S
        t1 = S.theta1 if theta1 is None else theta1
        return S.nu**2 + sum((a * t1**n for n, a in self.alpha.items() if a != 0), 0)

    def solution_expr(self, kind="cos", theta1=None, tau=None):
        """theta_c (kind "cos", 000 eq. 21) or theta_s ("sin", 000 eq. 22) truncated, as SymPy."""
        import sympy as sp
        from pendulab import symbols as S
        t1 = S.theta1 if theta1 is None else theta1
        t = S.tau if tau is None else tau
        f = {"cos": sp.cos, "sin": sp.sin}[kind]
        out = f(S.nu * t)
        for n, row in self.c.items():
            out += t1**n * sp.Add(*[v * f((S.nu + 2 * k) * t) for k, v in row])
        return out


def mathieu_series(order):
    """alpha_n, c_n, s_n of 000 eqs. 20-22 for n <= ``order``, exact (see :class:`MathieuSeries`).

    The computation is cached: a later call with a higher order extends the
    orders already computed instead of starting again.
    """
    _check_order(order)
    _ENGINE.extend(order)
    return MathieuSeries(order, _ENGINE)


# =====================================================================================
# Integer-order characteristic series a_m(q), b_m(q)  (DLMF 28.6)
# =====================================================================================

def _parse_kind(kind):
    from pendulab.limits import ascii_digits
    if not isinstance(kind, str) or len(kind) < 2 or kind[0] not in "ab" or not ascii_digits(kind[1:]):
        raise InputError(f"kind must be 'a<m>' (m >= 0) or 'b<m>' (m >= 1), e.g. 'a0' or 'b1'; got {kind!r}")
    letter, m = kind[0], int(kind[1:])
    if letter == "b" and m == 0:
        raise InputError("kind 'b0' does not exist: b_m is defined for m >= 1 (DLMF 28.2(v))")
    if m > 200 or kind[1:] != str(m):
        raise InputError(f"kind {kind!r}: m must be written plainly and be at most 200")
    return letter, m


def _action(letter, s):
    """2 cos 2z phi_s = sum_t V[t] phi_t for phi_s = cos(s z) ("a") or sin(s z) ("b"), s >= 0.

    From 2 cos 2z cos sz = cos(s+2)z + cos(s-2)z and the same with sines, with
    cos(-x) = cos x, sin(-x) = -sin x and sin 0 = 0.
    """
    out = {}
    for t in (s + 2, s - 2):
        sign = 1
        if t < 0:
            t, sign = -t, (1 if letter == "a" else -1)
        if letter == "b" and t == 0:
            continue
        out[t] = out.get(t, 0) + sign
    return out


def parity_rows(kind, size):
    """The first ``size`` rows of the Hill matrix of a_m or b_m's parity class (DLMF 28.4).

    On the basis phi_s (cos(sz) for "a", sin(sz) for "b"; s = s_0, s_0 + 2, ...
    with s_0 = m mod 2 for a_m, 1 or 2 for b_m) the equation
    w'' + (a - 2q cos 2z) w = 0 reads a w = (D + qV) w, D = diag(s^2), V the
    action of 2 cos 2z (:func:`_action`).  Row i is (s_i^2, V[s_i, s_i],
    V[s_{i-1}, s_i] V[s_i, s_{i-1}]) with 0 for the last entry of row 0: the
    diagonal is s_i^2 + q V[s_i, s_i] and the product of the two off-diagonal
    entries between rows i - 1 and i is q^2 times the last entry, so the
    truncated determinant is the continuant
    f_i = (s_i^2 + q V_ii - a) f_{i-1} - q^2 W_i f_{i-2}.

    >>> parity_rows("a0", 3)          # cos 0z, cos 2z, cos 4z: 2 cos 2z * 1 = 2 cos 2z
    [(0, 0, 0), (4, 0, 2), (16, 0, 1)]
    >>> parity_rows("b1", 2)          # sin z: 2 cos 2z sin z = sin 3z - sin z
    [(1, -1, 0), (9, 0, 1)]
    """
    letter, m = _parse_kind(kind)
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise InputError(f"size must be a positive integer, got {size!r}")
    s0 = m % 2 if letter == "a" else (1 if m % 2 else 2)
    rows, prev = [], None
    for i in range(size):
        s = s0 + 2 * i
        action = _action(letter, s)
        w = 0 if prev is None else _action(letter, prev).get(s, 0) * action.get(prev, 0)
        rows.append((s * s, action.get(s, 0), w))
        prev = s
    return rows


class _CharEngine(_Growing):
    """The exact coefficients of a_m(q) or b_m(q); grows on demand, the computed orders are final.

    On span{phi_s} (the frequencies s of m's parity class, DLMF 28.4) the
    equation w'' + (a - 2q cos 2z) w = 0 reads a w = D w + q V w with D =
    diag(s^2) and V the action of 2 cos 2z (:func:`_action`), a tridiagonal
    matrix.  a_m(q) is the eigenvalue that starts at m^2, i.e. the root
    delta(q) = a - m^2 with delta(0) = 0 of the Hill determinant
    det(D + qV - (m^2 + delta) I), a simple root at q = 0.  Truncating the
    basis at a frequency T changes the eigenvalue only at order q^(T - m + 2)
    and beyond (a path from phi_m to the first omitted frequency and back
    takes T - m + 2 steps of V), so T = m + p + 2 makes the root exact modulo
    q^p.  The root is lifted by Newton's iteration on power series, each step
    doubling the number of exact coefficients,

        delta <- delta - det / (d det / d delta)   (mod q^p, p = 2k),

    with the determinant and its delta-derivative evaluated at the power
    series delta(q) by the three-term continuant recurrence (exact rational
    power series: python-flint fmpq_poly, truncated products).  A request for
    a higher order lifts the coefficients already known; they are never
    recomputed.  ``_next`` appends one order of the lifted series (the test
    of the cache counts its calls).
    """

    def __init__(self, letter, m):
        super().__init__()
        self.letter, self.m = letter, m
        self.lam = [Fraction(m * m)]
        self._lifted = []          # exact orders computed by the last lift, not yet appended

    @property
    def order(self):
        return len(self.lam) - 1

    def extend(self, order):
        with self.lock:
            if order > self.order + len(self._lifted):
                self._lifted = _lift_characteristic(self.letter, self.m, self.lam, order)[self.order + 1:]
            while self.order < order:
                self._next()

    def _next(self):
        if not self._lifted:
            self._lifted = _lift_characteristic(self.letter, self.m, self.lam, self.order + 1)[self.order + 1:]
        self.lam.append(self._lifted.pop(0))


def _series_inverse(g, prec):
    """1/g modulo q^prec for an fmpq_poly g with g(0) != 0 (Newton: y <- y + y (1 - g y))."""
    from flint import fmpq_poly
    y = fmpq_poly([1 / g.coeffs()[0]])
    k = 1
    while k < prec:
        k = min(2 * k, prec)
        e = fmpq_poly([1]) - g.mul_low(y, k)
        y = y + y.mul_low(e, k)
    return y


def _lift_characteristic(letter, m, known, order):
    """Coefficients 0 .. ``order`` of a_m(q) ("a") or b_m(q) ("b") from the exact ones in ``known``.

    Newton's iteration on the truncated Hill determinant (see :class:`_CharEngine`):
    the continuant f_i = (s_i^2 - m^2 + q V_ii - delta) f_{i-1} - q^2 V_{i-1,i} V_{i,i-1} f_{i-2}
    over the basis frequencies s_0 < s_1 < ... <= T, and its delta-derivative
    g_i (needed only modulo q^(p - k), since det = O(q^k)).
    """
    from flint import fmpq, fmpq_poly
    s0 = m % 2 if letter == "a" else (1 if m % 2 else 2)
    delta = fmpq_poly([0] + [fmpq(c.numerator, c.denominator) for c in known[1:]])
    k = len(known)
    while k < order + 1:
        p = min(2 * k, order + 1)
        h = p - k
        f1, f2, g1, g2 = fmpq_poly([1]), fmpq_poly([]), fmpq_poly([]), fmpq_poly([])
        prev = None
        for s in range(s0, m + p + 3, 2):
            action = _action(letter, s)
            c, v = s * s - m * m, action.get(s, 0)
            f = c * f1 - delta.mul_low(f1, p)
            g = c * g1 - delta.mul_low(g1, h) - f1.truncate(h)
            if v:
                f += v * f1.left_shift(1).truncate(p)
                g += v * g1.left_shift(1).truncate(h)
            if prev is not None:
                w = _action(letter, prev).get(s, 0) * action.get(prev, 0)
                if w:
                    f -= w * f2.left_shift(2).truncate(p)
                    g -= w * g2.left_shift(2).truncate(h)
            f2, f1, g2, g1 = f1, f, g1, g
            prev = s
        # det = f1 = O(q^k): delta -= (f1 / q^k) / g1 * q^k  (mod q^p)
        delta = delta - f1.right_shift(k).mul_low(_series_inverse(g1, h), h).left_shift(k)
        k = p
    coeffs = delta.coeffs() + [fmpq(0)] * (order + 1)
    return [Fraction(m * m)] + [Fraction(int(c.p), int(c.q)) for c in coeffs[1:order + 1]]


class CharacteristicSeries:
    """a_m(q) or b_m(q) to a given order in q (DLMF 28.6), exact rational coefficients.

    ``coefficients`` maps each power of q (0 .. order) to a Fraction;
    ``radius`` is the radius of convergence, the distance to the nearest branch
    point of the kind (computed, :mod:`pendulab.analyses.mathieu_branch`; None
    beyond the computed table); ``radius_source`` says so.
    """

    def __init__(self, kind, order, coefficients):
        self.kind = kind
        self.order = order
        self.coefficients = dict(coefficients)
        self.radius = _table_radius(kind[0], int(kind[1:]))
        self._radius_text = _table_radius(kind[0], int(kind[1:]), text=True)
        self.radius_source = _radius_source(kind[0], int(kind[1:]))

    def _repr_latex_(self):
        """a_m(q) (or b_m(q)) and its exact coefficients as the product "series" prints them
        (:func:`pendulab.latex.characteristic_series_block`), and the radius, for a notebook."""
        from pendulab.latex import align, characteristic_series_block, text
        radius = (text("radius of convergence not computed") if self.radius is None else
                  r"\text{radius of convergence } |q| < " + str(self._radius_text))
        return align([r"&" + radius]) + "\n" + characteristic_series_block(self)

    def as_expr(self, q=None):
        import sympy as sp
        from pendulab import symbols as S
        qq = S.q if q is None else q
        return sp.Add(*[sp.Rational(c.numerator, c.denominator) * qq**p
                        for p, c in sorted(self.coefficients.items()) if c])

    def evaluate(self, q, dps=None, on_domain="raise"):
        """(value, truncation estimate) at ``q`` (float/array, or mpmath at ``dps`` digits).

        As for :func:`theta0_of_nu`, the orders N+1 .. K (K = :func:`_lookahead` (N))
        are evaluated too (from the cached exact coefficients) and the estimate
        is the larger of what they add and the largest of them.  |q| at or
        beyond the radius (computed branch point) raises SeriesDomainError (or,
        with ``on_domain="warn"``, returns the truncated sum with an
        AccuracyWarning); for kinds the table does not cover, growth of those
        further terms is taken as the sign of a q beyond the radius.
        """
        _check_on_domain(on_domain)
        N, K = self.order, _lookahead(self.order)
        coeffs = _char_coefficients(self.kind[0], int(self.kind[1:]), K)
        table = (f"{self.kind}: |q| = {{}} is beyond the radius of convergence {self.radius} "
                 f"({self.radius_source})")
        if dps is None:
            import numpy as np
            try:
                qa = np.asarray(q, dtype=float)
            except (TypeError, ValueError):
                raise InputError(f"q must be a real number or an array of them, got {q!r}") from None
            if not np.all(np.isfinite(qa)):
                raise InputError("q must be finite")
            if self.radius is not None and np.any(np.abs(qa) >= self.radius):
                _domain(table.format(f"{float(np.max(np.abs(qa))):g}"), on_domain)
            with np.errstate(all="ignore"):
                value = np.zeros_like(qa)
                for p in range(N, -1, -1):
                    value = value * qa + float(coeffs[p])
                further = [float(coeffs[p]) * qa**p for p in range(N + 1, K + 1)]
                est = np.maximum(np.abs(sum(further, np.zeros_like(qa))), np.max(np.abs(further), axis=0))
                if self.radius is None:
                    self._growth_check(np.maximum(abs(further[0]), abs(further[1])),
                                       np.maximum(abs(further[-2]), abs(further[-1])), qa, K, on_domain)
            if np.ndim(q) == 0:
                return float(value), float(est)
            return value, est
        import mpmath
        _check_dps(dps)
        with mpmath.workdps(dps + 10):
            qm = _mpf(q, "q")
            # the table's decimal and its double both count as the radius, so that q given
            # as the table's text ("1.46876861378514") or as that double is refused on both
            # routes
            if self.radius is not None and abs(qm) >= min(mpmath.mpf(self.radius),
                                                          mpmath.mpf(self._radius_text)):
                _domain(table.format(mpmath.nstr(abs(qm), 8)), on_domain)
            value = mpmath.mpf(0)
            for p in range(N, -1, -1):
                value = value * qm + mpmath.mpf(coeffs[p].numerator) / coeffs[p].denominator
            further = [mpmath.mpf(coeffs[p].numerator) / coeffs[p].denominator * qm**p
                       for p in range(N + 1, K + 1)]
            est = max(abs(mpmath.fsum(further)), max(abs(t) for t in further))
            if self.radius is None:
                self._growth_check(float(max(abs(further[0]), abs(further[1]))),
                                   float(max(abs(further[-2]), abs(further[-1]))), float(qm), K, on_domain)
        with mpmath.workdps(dps):   # rounded to the dps asked, not to the caller's precision
            return +value, +est

    def _growth_check(self, first, last, q, K, on_domain):
        import numpy as np
        bad = _growing(first, last)
        if np.any(bad):
            idx, where = _first_bad(bad)
            _domain(f"{self.kind}: q = {float(np.asarray(q)[idx]):.6g}{where} is beyond the radius of "
                    f"convergence (not in the computed table of radii): the terms of the series grow "
                    f"from orders {self.order + 1}-{self.order + 2} (size {float(np.asarray(first)[idx]):.2g}) "
                    f"to orders {K - 1}-{K} (size {float(np.asarray(last)[idx]):.2g}); lower |q|",
                    on_domain, stacklevel=4)


_CHAR_ENGINES = {}
_CHAR_ENGINES_LOCK = threading.Lock()


def characteristic_series(kind, order):
    """a_m(q) ("a<m>") or b_m(q) ("b<m>") to q^order, exact (DLMF 28.6; see :class:`CharacteristicSeries`).

    Cached per kind: a later call with a higher order extends the orders
    already computed instead of starting again.

    >>> s = characteristic_series("b1", 3)       # DLMF 28.6.3: 1 - q - q^2/8 + q^3/64
    >>> [str(s.coefficients[p]) for p in range(4)], s.radius
    (['1', '-1', '-1/8', '1/64'], 3.76995749401036)
    """
    letter, m = _parse_kind(kind)
    _check_order(order)
    lam = _char_coefficients(letter, m, order)
    return CharacteristicSeries(f"{letter}{m}", order, {p: lam[p] for p in range(order + 1)})


def _char_coefficients(letter, m, order):
    """The cached engine's list of exact coefficients of a_m or b_m, extended to at least ``order``."""
    with _CHAR_ENGINES_LOCK:
        engine = _CHAR_ENGINES.setdefault((letter, m), _CharEngine(letter, m))
    engine.extend(order)
    return engine.lam


# =====================================================================================
# Numbers from the series
# =====================================================================================

def _domain(message, on_domain, stacklevel=3):
    """Raise SeriesDomainError, or warn (AccuracyWarning) pointing at the user's call."""
    if on_domain == "raise":
        raise SeriesDomainError(message)
    warnings.warn(message, AccuracyWarning, stacklevel=stacklevel)


def _check_dps(dps):
    if isinstance(dps, bool) or not isinstance(dps, int) or not 5 <= dps <= 10000:
        raise InputError(f"dps must be an integer between 5 and 10000, got {dps!r}")


def _numeric_recursion(nu, order, zero, one):
    """alpha_n(nu) and C[n][k](nu), evaluated by running the recursion on numbers.

    ``nu`` is a float array or an mpf; the same recursion as the exact one
    (module docstring), so the values equal the exact coefficients at nu up to
    rounding.
    """
    alpha = [zero, zero]
    c = [{0: one}]
    for n in range(1, order + 1):
        if n >= 2:
            alpha.append(-(c[n - 1].get(-1, zero) + c[n - 1].get(1, zero)))
        row = {}
        for k in range(-n, n + 1, 2):
            if k == 0:
                continue
            g = c[n - 1].get(k - 1, zero) + c[n - 1].get(k + 1, zero)
            for m in range(2, n - abs(k) + 1, 2):
                if k in c[n - m]:
                    g = g + alpha[m] * c[n - m][k]
            row[k] = g / (4 * k * (nu + k))
        c.append(row)
    return alpha, c


def _mpf(value, name):
    """An mpf at the current working precision from int, Fraction, float, mpf or decimal text."""
    import mpmath
    if isinstance(value, bool):
        raise InputError(f"with dps, {name} must be a single real number, got {value!r}")
    try:
        if isinstance(value, Fraction):
            return mpmath.mpf(value.numerator) / value.denominator
        if isinstance(value, str) and "/" in value:
            f = Fraction(value.strip())
            return mpmath.mpf(f.numerator) / f.denominator
        result = mpmath.mpf(value)
    except (TypeError, ValueError, ZeroDivisionError):
        raise InputError(f"with dps, {name} must be a single real number, got {value!r}") from None
    if not mpmath.isfinite(result):
        raise InputError(f"{name} must be finite, got {value!r}")
    return result


def _prepare(nu, theta1, dps, on_domain, order, allow_zero=True, depth=1):
    _check_order(order)
    _check_on_domain(on_domain)
    if dps is None:
        import numpy as np
        try:
            nu_a = np.asarray(nu, dtype=float)
            t1_a = np.asarray(theta1, dtype=float)
        except (TypeError, ValueError):
            raise InputError("nu and theta1 must be real numbers or arrays of them") from None
        if not (np.all(np.isfinite(nu_a)) and np.all(np.isfinite(t1_a))):
            raise InputError("nu and theta1 must be finite")
        nu_b, t1_b = np.broadcast_arrays(nu_a, t1_a)
        dist = np.abs(nu_b - np.round(nu_b))
        bad = (dist < INTEGER_TOLERANCE) & ((np.round(nu_b) != 0) | (not allow_zero))
        if np.any(bad):
            v = float(nu_b[bad].flat[0])
            _domain(f"nu = {v!r} is within {INTEGER_TOLERANCE:g} of the integer {round(v)}: the "
                    f"series (000 sec. 3) is singular there; use the integer-order series "
                    f"(characteristic_series)", on_domain, stacklevel=3 + depth)
        return nu_b.astype(float), t1_b.astype(float)
    import mpmath
    _check_dps(dps)
    with mpmath.workdps(dps + 15):
        nu_m, t1_m = _mpf(nu, "nu"), _mpf(theta1, "theta1")
    k = mpmath.nint(nu_m)
    if abs(nu_m - k) < INTEGER_TOLERANCE and (k != 0 or not allow_zero):
        _domain(f"nu = {mpmath.nstr(nu_m, 15)} is within {INTEGER_TOLERANCE:g} of the integer "
                f"{int(k)}: the series (000 sec. 3) is singular there; use the integer-order "
                f"series (characteristic_series)", on_domain, stacklevel=3 + depth)
    return nu_m, t1_m


def _lookahead(order):
    """Order K up to which the evaluators compute terms beyond the requested ``order``.

    The extra orders are evaluated numerically only (never symbolically) and
    serve two purposes: the truncation estimate is the size of what orders
    order+1 .. K add, and the series is refused where those terms grow.
    """
    return order + min(40, max(8, order // 2, 16 - order))


def _first_bad(bad):
    """(index, text) of the first True entry of ``bad``: () and "" for a scalar."""
    import numpy as np
    if not np.ndim(bad):
        return (), ""
    idx = tuple(int(i[0]) for i in np.nonzero(np.asarray(bad)))
    return idx, f" (element {idx[0] if len(idx) == 1 else idx})"


def _growing(first, last):
    """True where the later terms (``last``) are not smaller than the earlier (``first``), or overflow."""
    import numpy as np
    first = np.asarray(first, dtype=float)
    last = np.asarray(last, dtype=float)
    with np.errstate(invalid="ignore"):
        return ~np.isfinite(first) | ~np.isfinite(last) | ((last >= first) & (last > 0))


def _divergence_check(first, last, order, K, what, nu, theta1, on_domain, depth=1):
    """Refuse (or warn) where the omitted terms grow: theta1 beyond the radius of convergence.

    ``first`` is the larger of the sizes of the orders order+1 and order+2
    (one of each parity, since even and odd orders differ in size), ``last``
    the same for K-1 and K.  Inside the radius the terms fall geometrically,
    so ``last`` < ``first``; growth (or an overflow) over the K - order
    further orders means the sum diverges.  The radius itself is not
    tabulated for non-integer nu and shrinks to 0 as nu nears an integer.
    """
    import numpy as np
    bad = _growing(first, last)
    if not np.any(bad):
        return
    idx, where = _first_bad(bad)
    f, l_ = float(np.asarray(first, dtype=float)[idx]), float(np.asarray(last, dtype=float)[idx])
    nu_v = float(np.broadcast_to(np.asarray(nu, dtype=float), np.shape(bad))[idx])
    t1_v = float(np.broadcast_to(np.asarray(theta1, dtype=float), np.shape(bad))[idx])
    _domain(f"{what}: theta1 = {t1_v:.6g} is beyond the radius of convergence at nu = {nu_v:.6g}"
            f"{where}: the terms of the series grow from orders {order + 1}-{order + 2} (size "
            f"{f:.2g}) to orders {K - 1}-{K} (size {l_:.2g}); lower theta1", on_domain, stacklevel=3 + depth)


def theta0_of_nu(nu, theta1, order, dps=None, on_domain="raise"):
    """theta0 = nu^2 + sum_{n<=order} alpha_n theta1^n (000 eq. 20) and a truncation estimate.

    ``dps=None``: numpy, vectorised over (broadcast) arrays ``nu``, ``theta1``;
    otherwise mpmath at ``dps`` digits (scalars).  Returns ``(value,
    estimate)``.  The terms of orders N+1 .. K (K = :func:`_lookahead` (N),
    e.g. 16 for N <= 8, 36 for N = 24) are evaluated numerically as well; the
    estimate is the larger of what they add together and the largest of them.

    nu within 1e-6 of a nonzero integer (poles of the alpha_n), and a theta1
    at which those further terms grow (beyond the radius of convergence),
    raise :class:`~pendulab.errors.SeriesDomainError`; with
    ``on_domain="warn"`` an :class:`~pendulab.errors.AccuracyWarning` is
    issued instead and the truncated value returned.

    >>> v, est = theta0_of_nu(0.5, 0.1, 2)      # 000 eq. 27: 0.25 + 0.01/(2*(0.25-1))
    >>> round(v, 12), est < 2e-5                # the next term, alpha_4 theta1^4, is -1.4e-5
    (0.243333333333, True)
    """
    nu_v, t1_v = _prepare(nu, theta1, dps, on_domain, order)
    K = _lookahead(order)
    if dps is None:
        import numpy as np
        with np.errstate(all="ignore"):
            alpha, _ = _numeric_recursion(nu_v, K, np.zeros_like(nu_v), np.ones_like(nu_v))
            terms = [alpha[n] * t1_v**n for n in range(K + 1)]
            value = nu_v**2 + sum(terms[2:order + 1], np.zeros_like(nu_v))
            further = terms[order + 1:]
            est = np.maximum(np.abs(sum(further, np.zeros_like(nu_v))),
                             np.max(np.abs(further), axis=0))
            _divergence_check(np.maximum(abs(terms[order + 1]), abs(terms[order + 2])),
                              np.maximum(abs(terms[K - 1]), abs(terms[K])),
                              order, K, "theta0_of_nu", nu_v, t1_v, on_domain)
        if np.ndim(value) == 0:
            return float(value), float(est)
        return value, est
    import mpmath
    with mpmath.workdps(dps + 15):
        alpha, _ = _numeric_recursion(nu_v, K, mpmath.mpf(0), mpmath.mpf(1))
        terms = [alpha[n] * t1_v**n for n in range(K + 1)]
        value = nu_v**2 + mpmath.fsum(terms[2:order + 1])
        further = terms[order + 1:]
        est = max(abs(mpmath.fsum(further)), max(abs(t) for t in further))
        _divergence_check(float(max(abs(terms[order + 1]), abs(terms[order + 2]))),
                          float(max(abs(terms[K - 1]), abs(terms[K]))),
                          order, K, "theta0_of_nu", float(nu_v), float(t1_v), on_domain)
    with mpmath.workdps(dps):
        return +value, +est


def _solution(kind, tau, nu, theta1, order, dps, on_domain):
    nu_v, t1_v = _prepare(nu, theta1, dps, on_domain, order, allow_zero=(kind == "cos"), depth=2)
    K = _lookahead(order)
    what = f"theta_{kind[0]}"
    if dps is None:
        import numpy as np
        try:
            tau_a = np.asarray(tau, dtype=float)
        except (TypeError, ValueError):
            raise InputError("tau must be a real number or an array of them") from None
        if not np.all(np.isfinite(tau_a)):
            raise InputError("tau must be finite")
        nu_b, t1_b, tau_b = np.broadcast_arrays(nu_v, t1_v, tau_a)
        f = np.cos if kind == "cos" else np.sin
        with np.errstate(all="ignore"):
            _, c = _numeric_recursion(nu_b, K, np.zeros_like(nu_b), np.ones_like(nu_b))
            value = f(nu_b * tau_b)
            for n in range(1, order + 1):
                value = value + t1_b**n * sum((v * f((nu_b + 2 * k) * tau_b) for k, v in c[n].items()),
                                              np.zeros_like(nu_b))
            # sizes[n]: |theta1|^n sum_k |C[n][k]|, a bound of order n's contribution at every tau
            sizes = {n: np.abs(t1_b)**n * sum((np.abs(v) for v in c[n].values()), np.zeros_like(nu_b))
                     for n in range(order + 1, K + 1)}
            est = sum(sizes.values(), np.zeros_like(nu_b))
            _divergence_check(np.maximum(sizes[order + 1], sizes[order + 2]),
                              np.maximum(sizes[K - 1], sizes[K]), order, K, what, nu_b, t1_b, on_domain, 2)
        if np.ndim(value) == 0:
            return float(value), float(est)
        return value, est
    import mpmath
    with mpmath.workdps(dps + 15):
        tau_m = _mpf(tau, "tau")
        f = mpmath.cos if kind == "cos" else mpmath.sin
        _, c = _numeric_recursion(nu_v, K, mpmath.mpf(0), mpmath.mpf(1))
        value = f(nu_v * tau_m)
        for n in range(1, order + 1):
            value += t1_v**n * mpmath.fsum(v * f((nu_v + 2 * k) * tau_m) for k, v in c[n].items())
        sizes = {n: abs(t1_v)**n * mpmath.fsum(abs(v) for v in c[n].values())
                 for n in range(order + 1, K + 1)}
        est = mpmath.fsum(sizes.values())
        _divergence_check(float(max(sizes[order + 1], sizes[order + 2])), float(max(sizes[K - 1], sizes[K])),
                          order, K, what, float(nu_v), float(t1_v), on_domain, 2)
    with mpmath.workdps(dps):
        return +value, +est


def theta_c(tau, nu, theta1, order, dps=None, on_domain="raise"):
    """theta_c(tau) = cos(nu tau) + sum_{n<=order} c_n(tau) theta1^n (000 eq. 21), with an estimate.

    Same conventions as :func:`theta0_of_nu`; the estimate is
    sum_{order < n <= K} |theta1|^n sum_k |C[n][k]|, which bounds what the
    orders order+1 .. K add at any tau.
    """
    return _solution("cos", tau, nu, theta1, order, dps, on_domain)


def theta_s(tau, nu, theta1, order, dps=None, on_domain="raise"):
    """theta_s(tau) = sin(nu tau) + sum s_n(tau) theta1^n (000 eq. 22), with an estimate.

    As :func:`theta_c`; nu near 0 is refused too (theta_s vanishes identically at nu = 0).
    """
    return _solution("sin", tau, nu, theta1, order, dps, on_domain)


# =====================================================================================
# Stability interval of the inverted pendulum from the series
# =====================================================================================

def _check_body(ratio, inertia_ratio):
    problems = []
    values = []
    for name, v in (("omega0/omega", ratio), ("I/(m l^2)", inertia_ratio)):
        try:
            if isinstance(v, bool):
                raise TypeError
            x = float(v)
        except (TypeError, ValueError):
            problems.append(f"{name} must be a number, got {v!r}")
            continue
        if not math.isfinite(x) or x < 0:
            problems.append(f"{name} must be finite and >= 0, got {v!r}")
        values.append(x)
    if not problems and values[1] < 1:
        # I = m l^2 + I0 with I0 >= 0 about the centre of mass (000 sec. 2.1): 1 for a point mass
        problems.append(f"I/(m l^2) must be >= 1 (I = m l^2 + I0, I0 >= 0), got {inertia_ratio!r}")
    if problems:
        raise InputError("; ".join(problems))
    return values


def _first_root(f, lo, hi, steps=400):
    """Smallest root of f in (lo, hi] by a scan and Brent's method (None if no sign change)."""
    from pendulab.numerics.roots import brent_root
    xs = [lo + (hi - lo) * i / steps for i in range(steps + 1)]
    prev_x, prev_f = xs[0], f(xs[0])
    if prev_f == 0:
        return prev_x
    for x in xs[1:]:
        fx = f(x)
        if fx == 0:
            return x
        if (fx > 0) != (prev_f > 0):
            return brent_root(f, prev_x, x, xtol=1e-15, maxiter=200)
        prev_x, prev_f = x, fx
    return None


@functools.lru_cache(maxsize=64)
def _alpha_polys_in_x(order):
    """For each even n <= order: alpha_n as numpy polynomials (numerator, denominator) in x = nu^2.

    Kept per order for the process (the arrays are never written to): the
    stability comparison asks for the same order at every omega0/omega.

    alpha_n is even in nu (the nu -> -nu symmetry), so its numerator holds even
    powers only and its denominator factors pair into (nu - j)(nu + j) = x - j^2.
    Numerator and denominator are scaled by the same power of two to stay in
    double range.
    """
    import numpy as np
    S = mathieu_series(order)
    out = []
    for n in range(2, order + 1, 2):
        a = S.alpha_raw[n]
        if any(a.num[1::2]):
            raise AssertionError(f"alpha_{n} is not even in nu")
        exps = dict(a.exps)
        shift = max(0, max(abs(c).bit_length() for c in a.num) - 900)
        numx = np.array([float(Fraction(c, 1 << shift)) for c in a.num[0::2]][::-1])
        den = np.array([float(Fraction(a.den, 1 << shift))])
        for j, e in sorted(exps.items()):
            if j > 0:
                if exps.get(-j) != e:
                    raise AssertionError(f"alpha_{n}: unpaired factor nu + {j}")
                for _ in range(e):
                    den = np.polymul(den, [1.0, -float(j * j)])
        out.append((n, numx, den))
    return tuple(out)


def _horner(p, x):
    """numpy.polyval(p, x) for a scalar x, on Python floats: the same Horner steps
    (y = y x + c from y = 0), so the same double, without numpy's per-call work.
    ``p``: the coefficients as a list of floats, highest power first."""
    y = 0.0
    for c in p:
        y = y * x + c
    return y


def _branch_theta1(polys, x, target):
    """Smallest theta1 > 0 with theta0_N(x, theta1) = target (None if there is none).

    theta0_N(x, theta1) - target = (x - target) + sum alpha_n(x) theta1^n is a
    polynomial in theta1 with real coefficients at fixed x.
    """
    import numpy as np
    coeffs = np.zeros(polys[-1][0] + 1)
    coeffs[0] = x - target
    with np.errstate(all="ignore"):  # an overflow is answered below (no branch), not warned
        for n, num, den in polys:
            # numpy's division (inf or nan at a pole, not ZeroDivisionError)
            coeffs[n] = np.float64(_horner(num.tolist(), x)) / _horner(den.tolist(), x)
    if not np.all(np.isfinite(coeffs)):
        return None
    if coeffs[0] == 0:
        return 0.0
    roots = np.roots(coeffs[::-1])
    real = [r.real for r in roots if abs(r.imag) <= 1e-9 * max(1.0, abs(r)) and r.real > 0]
    if not real:
        return None
    return _polished(coeffs, min(real))


def _polished(coeffs, t):
    """The root t of the polynomial ``coeffs`` (lowest power first, t > 0) polished by Brent's
    method in [t (1 - 1e-6), t (1 + 1e-6)] when the polynomial changes sign there; else t."""
    from pendulab.numerics.roots import brent_root
    highest_first = coeffs[::-1].tolist()

    def f(s):
        return _horner(highest_first, s)

    a, b = t * (1 - 1e-6), t * (1 + 1e-6)
    if f(a) * f(b) < 0:
        return brent_root(f, a, b, xtol=1e-16, maxiter=200)
    return t


#: Points of x per batch of :func:`_branch_batches` (the scan usually ends within the first few hundred).
SCAN_BATCH = 128


class _Batch:
    """The branch at a batch of points x, as arrays (see :func:`_branch_batches`).

    * ``x`` - the points (floats);
    * ``t`` - the root before polishing: the smallest positive real root of the
      companion matrix's eigenvalues, as :func:`_branch_theta1` picks it; NaN
      where there is none (the branch has ended);
    * ``exact`` - True where ``t`` is already :func:`_branch_theta1`'s value
      (zero constant term, or a point done by the scalar function);
    * ``lo``, ``hi`` - the bracket Brent's method polishes in (``t`` itself where exact);
    * ``coeffs`` - the polynomial in theta1 at each point, lowest power first.
    """

    __slots__ = ("x", "t", "exact", "lo", "hi", "coeffs")

    def root(self, i):
        """The :class:`_Root` of point ``i`` (None where the branch has ended)."""
        t = float(self.t[i])
        if t != t:
            return None
        if self.exact[i]:
            return _Root.exact(t)
        return _Root(self.coeffs[i], t)


def _branch_batches(polys, xs, target):
    """Yield a :class:`_Batch` per SCAN_BATCH points of ``xs``.

    The work of :func:`_branch_theta1` is done for the whole batch at once:
    the coefficients by the same Horner steps on arrays, the roots as the
    eigenvalues of the same companion matrices that numpy.roots builds, in one
    batched LAPACK call, and the choice of the smallest positive real root by
    the same tests on arrays.  The polishing of a root by Brent's method (the
    costly part) is left until a comparison needs it (:meth:`_Root.less`).  A point
    whose leading coefficient is zero (numpy.roots would trim it) goes through
    the scalar function.
    """
    import numpy as np
    degree = polys[-1][0]
    for start in range(0, len(xs), SCAN_BATCH):
        x = np.asarray(xs[start:start + SCAN_BATCH], dtype=float)
        coeffs = np.zeros((len(x), degree + 1))
        coeffs[:, 0] = x - target
        with np.errstate(all="ignore"):
            for n, num, den in polys:
                coeffs[:, n] = np.polyval(num, x) / np.polyval(den, x)
        finite = np.all(np.isfinite(coeffs), axis=1)
        zero = finite & (coeffs[:, 0] == 0)
        rows = np.flatnonzero(finite & ~zero & (coeffs[:, degree] != 0))
        t = np.full(len(x), np.nan)
        exact = np.ones(len(x), dtype=bool)
        t[zero] = 0.0
        if rows.size:
            p = coeffs[rows, ::-1]
            companion = np.zeros((rows.size, degree, degree))
            sub = np.arange(1, degree)
            companion[:, sub, sub - 1] = 1.0
            companion[:, 0, :] = -p[:, 1:] / p[:, :1]
            roots = np.linalg.eigvals(companion)
            # abs(r.imag) <= 1e-9 max(1, |r|) and r.real > 0, as _branch_theta1 tests each root
            # (fmax: Python's max(1.0, nan) is 1.0)
            real = (np.abs(roots.imag) <= 1e-9 * np.fmax(1.0, np.abs(roots))) & (roots.real > 0)
            smallest = np.where(real, roots.real, np.inf).min(axis=1)
            smallest[~real.any(axis=1)] = np.nan
            t[rows] = smallest
            exact[rows] = False
        for i in np.flatnonzero(finite & ~zero & (coeffs[:, degree] == 0)):
            value = _branch_theta1(polys, float(x[i]), target)
            t[i] = np.nan if value is None else value
        lo, hi = t * (1 - 1e-6), t * (1 + 1e-6)
        lo[exact], hi[exact] = t[exact], t[exact]
        batch = _Batch()
        batch.x, batch.t, batch.exact, batch.lo, batch.hi, batch.coeffs = x, t, exact, lo, hi, coeffs
        yield batch


def _branch_scan(polys, xs, target):
    """Yield (x, root) for x in ``xs``: root None where :func:`_branch_theta1` (polys, x, target)
    is None, else a :class:`_Root` whose ``value()`` is that function's value bit for bit
    (computed a batch at a time by :func:`_branch_batches`)."""
    for batch in _branch_batches(polys, xs, target):
        for i in range(len(batch.x)):
            yield float(batch.x[i]), batch.root(i)


def _first_descent(polys, xs, target):
    """The first point of ``xs`` where the branch phi(x) ends or decreases.

    Returns (k, ended, previous): ``k`` the index of the first point whose
    root is None (``ended``) or less than the previous point's (the branch
    starts at (target, 0)), ``previous`` the :class:`_Root` of the point
    before it; (None, False, None) when neither happens.  Two neighbours are
    compared by their brackets on arrays where the brackets do not overlap
    (:meth:`_Root.less` decides the same way, and agrees with the polished
    values); where they overlap, by :meth:`_Root.less` itself.  Only the roots
    that a comparison or the caller needs are made.
    """
    import numpy as np
    prev_lo = prev_hi = 0.0
    prev_root = _Root.exact(0.0)
    offset = 0
    for batch in _branch_batches(polys, xs, target):
        n = len(batch.x)
        ended = np.isnan(batch.t)
        lo_prev = np.concatenate([[prev_lo], batch.lo[:-1]])
        hi_prev = np.concatenate([[prev_hi], batch.hi[:-1]])
        less = batch.hi < lo_prev
        unsure = ~ended & ~less & ~(batch.lo >= hi_prev)
        made = {-1: prev_root}

        def root(i):
            if i not in made:
                made[i] = batch.root(i)
            return made[i]

        for j in np.flatnonzero(ended | less | unsure).tolist():
            if ended[j]:
                return offset + j, True, root(j - 1)
            if less[j] or root(j).less(root(j - 1)):
                return offset + j, False, root(j - 1)
        prev_lo, prev_hi, prev_root = float(batch.lo[-1]), float(batch.hi[-1]), root(n - 1)
        offset += n
    return None, False, None


class _Root:
    """The root t of :func:`_branch_theta1` before Brent's polishing, which is done on demand.

    The polished value lies in the bracket [t (1 - 1e-6), t (1 + 1e-6)] that
    Brent's method searches (t > 0), or is t itself; :meth:`less` compares two roots
    by their brackets and polishes only when the brackets overlap.
    """

    __slots__ = ("coeffs", "t", "lo", "hi", "polished")

    def __init__(self, coeffs, t):
        self.coeffs, self.t, self.polished = coeffs, t, False
        self.lo, self.hi = t * (1 - 1e-6), t * (1 + 1e-6)

    @classmethod
    def exact(cls, t):
        root = cls(None, t)
        root.lo = root.hi = t
        root.polished = True
        return root

    def value(self):
        """The value of :func:`_branch_theta1` at this point (the polished root)."""
        if not self.polished:
            self.t = _polished(self.coeffs, self.t)  # in the bracket [lo, hi] of __init__
            self.lo = self.hi = self.t
            self.polished = True
        return self.t

    def less(self, other):
        """value() < other.value(), polishing only where the brackets cannot tell."""
        if self.hi < other.lo:
            return True
        if self.lo >= other.hi:
            return False
        return self.value() < other.value()


def stability_interval_series(order, ratio, inertia_ratio):
    """(lower, upper) limits of a/l from the source's series at ``order`` (000 eq. 28 at order 2).

    With theta0 and theta1 from the derivation (for the source's drive
    theta0 = -4 ratio^2, 000 eq. 5, and theta1 = 2 (a/l) / inertia_ratio,
    000 eq. 6; :func:`pendulab.analyses.stability.body_map`) and theta0 = nu^2 + sum_{n<=order} alpha_n theta1^n (000 eqs.
    20, 27), solve for x = nu^2 as the source does after eq. 27.  The branch of
    roots x that starts at x = theta0 for theta1 = 0 (the inverted position,
    minus sign in the source's formula for nu^2) is followed as theta1 grows,
    parametrised by x: theta1 = phi(x).

    * lower: nu^2 = 0 is a root, i.e. the smallest theta1 > 0 with
      theta0_N(0, theta1) = theta0;
    * upper: the branch ends in a fold (two real roots x meet and turn
      complex; the source's "term under the root" condition), i.e. the first
      local maximum of phi(x) for x below the first pole x = 1.

    At order 2 this is exactly 000 eq. 28:

    >>> lo, up = stability_interval_series(2, 0.1, 1)
    >>> abs(lo - 2**0.5 * 0.1) < 1e-12, abs(up - 2**0.5 * (0.25 + 0.01)) < 1e-12
    (True, True)

    ``upper`` is None when the truncated branch has no fold before the pole
    (for orders N = 4, 8, 12, ... the term alpha_N theta1^N drives theta0 to
    +infinity as nu -> 1, so a real root always exists); see docs/series.md for
    why the non-integer series cannot reach the exact upper limit, which lies
    at nu = 1, and :func:`stability_interval_integer_series` for one that can.
    """
    _check_order(order, minimum=2)
    if order > 120:
        raise InputError(f"stability_interval_series: order {order} > 120 is not supported in double precision")
    rho, iota = _check_body(ratio, inertia_ratio)
    target, scale = _map_point(rho, iota)
    lower_t1, upper_t1 = interval_series_theta1(order, target)
    lower = None if lower_t1 is None else float(lower_t1) * scale
    upper = None if upper_t1 is None else float(upper_t1) * scale
    return lower, upper


def _map_point(rho, iota):
    """theta0 and (a/l)/theta1 of the source's drive for this body, from the derivation."""
    from pendulab.analyses.stability import map_point
    target, scale = map_point(rho, iota)
    return target, abs(scale)


def interval_series_theta1(order, target):
    """(lower, upper) theta1 of the stable interval at theta0 = ``target`` from the series.

    The Mathieu-plane engine of :func:`stability_interval_series` (same
    branch-following; None where the truncated branch has no such point).
    """
    import numpy as np
    _check_order(order, minimum=2)
    polys = _alpha_polys_in_x(order)

    # lower: the branch crosses nu^2 = 0
    lower_t1 = _branch_theta1(polys, 0.0, target) if target < 0 else 0.0
    # upper: first local maximum of phi(x) along the branch from x = target to the pole at x = 1
    xs = np.unique(np.concatenate([np.linspace(target, 0.0, 400),
                                   1.0 - np.geomspace(1.0, 1e-7, 3000)]))
    xs = xs[xs > target]
    upper_t1 = None
    k, ended, previous = _first_descent(polys, xs, target)
    if k is not None and not ended:
        from pendulab.numerics.roots import brent_minimum
        lo_x = float(xs[k - 2]) if k >= 2 else target
        _, low = brent_minimum(lambda s: -(_branch_theta1(polys, s, target) or 0.0),
                               lo_x, float(xs[k]), xatol=1e-13, maxiter=500)
        upper_t1 = max(-low, previous.value())
    return lower_t1, upper_t1


def stability_interval_integer_series(order, ratio, inertia_ratio, on_domain="warn"):
    """(lower, upper) limits of a/l from the series of a_0(q) and b_1(q) at ``order`` (DLMF 28.6).

    The inverted pendulum (theta0 = -4 ratio^2 < 0) is stable for
    a_0(Q) < theta0 < b_1(Q), Q = |q| = theta1 = 2 (a/l)/inertia_ratio (the
    first stability region of Mathieu's equation; it is symmetric in q, DLMF
    28.2.26 a_{2n+1}(-q) = b_{2n+1}(q)).  The lower limit is the smallest Q with
    a_0(Q) = theta0, the upper the smallest Q with b_1(Q) = theta0, each with
    the truncated series.  A limit beyond the series' radius of convergence
    (the computed branch point, DLMF Table 28.6.1) is returned with an AccuracyWarning
    (``on_domain="warn"``), raises SeriesDomainError (``"raise"``) or is
    replaced by None (``"omit"``, used by the stability comparison table).

    >>> lo, up = stability_interval_integer_series(2, 0.1, 1)   # a_0 ~ -Q^2/2: lower = sqrt(2)*0.1
    >>> round(lo, 12) == round(2**0.5 * 0.1, 12)
    True
    """
    _check_order(order)
    _check_on_domain(on_domain, ("raise", "warn", "omit"))
    rho, iota = _check_body(ratio, inertia_ratio)
    target, scale = _map_point(rho, iota)
    return tuple(None if q is None else q * scale
                 for q in interval_integer_series_theta1(order, target, on_domain))


def interval_integer_series_theta1(order, target, on_domain="warn"):
    """(lower, upper) |theta1| with a_0 = target and b_1 = target from the DLMF 28.6 series.

    The Mathieu-plane engine of :func:`stability_interval_integer_series`.
    """
    _check_on_domain(on_domain, ("raise", "warn", "omit"))
    limits = []
    for kind in ("a0", "b1"):
        s = characteristic_series(kind, order)
        coeffs = [float(s.coefficients[p]) for p in range(order + 1)]

        def f(Q, coeffs=coeffs):
            v = 0.0
            for c in reversed(coeffs):
                v = v * Q + c
            return v - target

        if kind == "a0" and target == 0:
            root = 0.0
        else:
            root = _first_root(f, 0.0, 3.0 * s.radius + 2 * abs(target), 6000)
        if root is not None and root >= s.radius:
            if on_domain == "omit":
                root = None
            else:
                _domain(f"{kind}: the limit Q = {root:g} lies beyond the radius of convergence "
                        f"{s.radius} ({s.radius_source}); the truncated series is unreliable there",
                        on_domain)
        limits.append(root)
    return limits[0], limits[1]
