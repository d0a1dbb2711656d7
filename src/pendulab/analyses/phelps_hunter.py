"""Phelps–Hunter's Floquet analysis of Mathieu's equation, derived with SymPy (000 sec. 2.2).

Every result here is formed by the code from Mathieu's equation (000 eq. 7)

    theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0

and the Floquet ansatz theta = e^{i lam tau} sum_n b_n e^{2 i n tau} (000 eq. 8);
nothing printed in the source is typed in (the tests compare with it):

* :func:`recurrence` - substitutes the ansatz, collects e^{i(2n+lam)tau} and
  finds theta1 b_{n-1} + C_n b_n + theta1 b_{n+1} = 0 with
  C_n = theta0 - (2n + lam)^2 (000 eqs. 9-10);
* :func:`continued_fraction` - b_{+-1}/b_0 as the truncated continued fraction
  that the recurrence gives when b_{+-(N+1)} is neglected (000, after eq. 10);
* :func:`lambda_polynomial` - the equation for lam left when b_0 cancels from
  the n = 0 row, denominators cleared (degree 6 at depth 1, as the source says);
* :func:`hill_matrix` - the recurrence with each row divided by C_n (Hill's
  determinant, Whittaker & Watson sec. 19.42);
* :func:`small_parameter_exponent` - 000 eq. 11, from Hill's relation
  sin^2(pi lam/2) = Delta(0) sin^2(pi sqrt(theta0)/2) expanded to first order in
  theta0 and theta1^2;
* :func:`interval_eq12` - 000 eq. 12, from 0 < sin^2(pi lam/2) < 1.

The exponent is called ``lam`` (``lambda`` is a Python keyword, so a JSON
string containing it could not be read back).

>>> small_parameter_exponent(mathieu=True)
Eq(sin(pi*lam/2)**2, pi**2*(2*theta0 + theta1**2)/8)
>>> lower, upper = interval_eq12()
>>> lower
sqrt(2)*inertia_ratio*w0_over_w
"""

import functools
from typing import NamedTuple

import sympy as sp

from pendulab import symbols as S
from pendulab.errors import InputError

#: The Floquet exponent lambda of 000 eq. 8 (shared with pendulab.symbols).
lam = S.lam
#: The Fourier coefficients b_n of 000 eq. 8.
b = sp.IndexedBase("b")
#: The summation index n of 000 eqs. 8-10.
n = sp.Symbol("n", integer=True)

#: The dimensionless groups in which the source states its limits (000 eqs. 12, 19, 28):
#: a/l, omega0/omega and I/(m l^2).
a_over_l, w0_over_w, inertia_ratio = S.a_over_l, S.w0_over_w, S.inertia_ratio

#: Deepest truncation accepted by the symbolic functions (the expressions grow
#: quickly; numbers at any depth belong to pendulab.analyses.floquet).
MAX_DEPTH = 12


def _check_depth(depth):
    if isinstance(depth, bool) or not isinstance(depth, int):
        raise InputError(f"depth must be an integer, got {depth!r}")
    if not 1 <= depth <= MAX_DEPTH:
        raise InputError(f"depth must be between 1 and {MAX_DEPTH}, got {depth}")


def mathieu_operator(f):
    """Left side of 000 eq. 7 applied to ``f(tau)``, with 2 cos 2tau written as exponentials."""
    drive = (2 * sp.cos(2 * S.tau)).rewrite(sp.exp)
    # theta'' as the derivative of the derivative: the same value as diff(f, tau, 2), without
    # the factor_terms SymPy applies to a second derivative of a sum (the recurrence read from
    # it is the same expression, tests/test_phelps_hunter.py)
    return sp.diff(sp.diff(f, S.tau), S.tau) + (S.theta0 + S.theta1 * drive) * f


def ansatz(depth):
    """The Floquet series 000 eq. 8 truncated to |n| <= depth."""
    _check_depth(depth)
    return sp.exp(sp.I * lam * S.tau) * sum(
        b[k] * sp.exp(2 * sp.I * k * S.tau) for k in range(-depth, depth + 1))


def _frequency_part(expr, shift):
    """Coefficient of e^{i shift tau} in ``expr`` (a sum of exponentials in tau).

    Each term of the expanded sum (exponentials kept whole: no power_exp split) is
    a coefficient times exponentials; its frequency is the sum of their exponents
    over i tau, compared with ``shift``."""
    e = sp.expand(expr, power_exp=False, multinomial=False)
    part = []
    for term in sp.Add.make_args(e):
        factors = sp.Mul.make_args(term)
        exponent = sp.Add(*[f.args[0] for f in factors if isinstance(f, sp.exp)])
        coefficient = sp.Mul(*[f for f in factors if not isinstance(f, sp.exp)])
        frequency = sp.expand(exponent / (sp.I * S.tau))
        if coefficient.has(S.tau) or frequency.has(S.tau):  # pragma: no cover
            raise RuntimeError(f"{term} is not a multiple of an exponential in tau")
        if sp.expand(frequency - shift) == 0:
            part.append(coefficient)
    return sp.expand(sp.Add(*part))


def C(k):
    """C_k = theta0 - (2k + lam)^2 (000, after eq. 10)."""
    return S.theta0 - (2 * k + lam) ** 2


class Recurrence(NamedTuple):
    """theta1 b_{n-1} + C_n b_n + theta1 b_{n+1} = 0 (000 eqs. 9-10), as derived.

    ``lhs`` is the left side (in b[n-1], b[n], b[n+1]); ``coefficients`` maps
    the offset -1, 0, +1 to the coefficient of b[n + offset].
    """

    lhs: sp.Expr
    coefficients: dict
    n: sp.Symbol
    b: sp.IndexedBase

    @property
    def equation(self):
        return sp.Eq(self.lhs, 0)


@functools.lru_cache(maxsize=None)
def recurrence():
    """Derive the three-term recurrence 000 eqs. 9-10 from 000 eqs. 7-8.

    A window b_{n-2} .. b_{n+2} of the ansatz is put into Mathieu's operator
    and the coefficient of e^{i(2n+lam)tau} is read off; b_{n+-2} drop out,
    which is what makes the recurrence three-term.

    >>> rec = recurrence()
    >>> rec.coefficients[1], sp.factor(rec.coefficients[0] - C(n))
    (theta1, 0)
    """
    window = sum(b[n + k] * sp.exp(sp.I * (2 * (n + k) + lam) * S.tau) for k in range(-2, 3))
    row = _frequency_part(mathieu_operator(window), 2 * n + lam)
    coefficients = {k: sp.expand(row.coeff(b[n + k])) for k in range(-2, 3)}
    if coefficients[-2] != 0 or coefficients[2] != 0:  # pragma: no cover - a derivation bug
        raise RuntimeError("the recurrence is not three-term: b_{n+-2} did not drop out")
    lhs = sum(coefficients[k] * b[n + k] for k in (-1, 0, 1))
    if sp.expand(row - lhs) != 0:  # pragma: no cover
        raise RuntimeError("the n-th row has terms other than b_{n-1}, b_n, b_{n+1}")
    return Recurrence(lhs, {k: coefficients[k] for k in (-1, 0, 1)}, n, b)


def _row(k):
    """The recurrence at n = k with C_k kept in the source's factored form."""
    rec = recurrence()
    row = rec.lhs.subs(n, k)
    # The derived coefficient of b_k equals C_k; write it as C_k so that the
    # continued fractions read like the source's.
    if sp.expand(row.coeff(b[k]) - C(k)) != 0:  # pragma: no cover
        raise RuntimeError("derived C_k differs from theta0 - (2k + lam)^2")
    return row.coeff(b[k - 1]) * b[k - 1] + C(k) * b[k] + row.coeff(b[k + 1]) * b[k + 1]


def continued_fraction(n_sign, depth):
    """b_{+-1}/b_0 as the continued fraction truncated at depth N (000, after eq. 10).

    ``n_sign`` = +1 gives b_1/b_0 (the n > 0 branch), -1 gives b_{-1}/b_0.
    The fraction is built from the recurrence itself: b_{+-(N+1)} is set to
    zero and each row k = N, N-1, ..., 1 is solved for b_k in terms of b_{k-1}
    (n > 0; mirrored for n < 0).

    >>> continued_fraction(1, 2)
    -theta1/(theta0 - theta1**2/(theta0 - (lam + 4)**2) - (lam + 2)**2)
    """
    if isinstance(n_sign, bool) or not isinstance(n_sign, int) or n_sign not in (1, -1):
        raise InputError(f"n_sign must be +1 or -1, got {n_sign!r}")
    _check_depth(depth)
    return _continued_fraction(n_sign, depth)


@functools.lru_cache(maxsize=None)
def _continued_fraction(n_sign, depth):
    ratio = sp.Integer(0)  # b_{+-(N+1)} / b_{+-N}: neglected (000, after eq. 10)
    for k in range(depth, 0, -1):
        idx = n_sign * k
        inner, outer = b[idx + n_sign], b[idx - n_sign]
        row = _row(idx).subs(inner, ratio * b[idx])
        # The row is linear: p b_outer + q b_idx = 0, so b_idx/b_outer = -p/q.
        # Solved by hand (not sp.solve) to keep the nested shape of the fraction.
        p, q = row.coeff(outer), sp.Add(*[t / b[idx] for t in sp.Add.make_args(row)
                                          if t.has(b[idx])])
        if sp.expand(p * outer + q * b[idx] - row) != 0:  # pragma: no cover
            raise RuntimeError(f"row {idx} is not linear in b_{idx} and b_{idx - n_sign}")
        ratio = -p / q
        if ratio.has(b):  # pragma: no cover
            raise RuntimeError("continued fraction still contains a coefficient b")
    return ratio


def lambda_equation(depth):
    """The n = 0 row divided by b_0, with b_{+-1} = (continued fraction) b_0.

    b_0 cancels (checked), leaving C_0 + theta1 (b_1 + b_{-1})/b_0 = 0, an
    equation in lam, theta0 and theta1 alone (000, text after eq. 10).
    """
    _check_depth(depth)
    return _lambda_equation(depth)


@functools.lru_cache(maxsize=None)
def _lambda_equation(depth):
    row = _row(0).subs({b[1]: continued_fraction(1, depth) * b[0],
                        b[-1]: continued_fraction(-1, depth) * b[0]})
    equation = sp.expand(row / b[0])
    if equation.has(b):  # pragma: no cover
        raise RuntimeError("b_0 did not cancel from the n = 0 row")
    return equation


def lambda_polynomial(depth):
    """The equation for lam at depth N with denominators cleared, as a ``sympy.Poly`` in lam.

    Its degree is 2(2N + 1): 6 at the first approximation N = 1, as the
    source says (000, text before eq. 11).

    >>> lambda_polynomial(1).degree()
    6
    """
    _check_depth(depth)
    return _lambda_polynomial(depth)


@functools.lru_cache(maxsize=None)
def _lambda_polynomial(depth):
    numerator, _ = sp.fraction(sp.together(_lambda_equation(depth)))
    return sp.Poly(sp.expand(numerator), lam)


def hill_matrix(depth, exponent=None):
    """Rows n = -N..N of the recurrence divided by C_n (Hill's determinant).

    Entry (n, n) is 1 and (n, n+-1) is theta1/C_n (Whittaker & Watson, A Course
    of Modern Analysis, sec. 19.42).  ``exponent`` replaces lam (default: keep
    lam; 0 gives the matrix of Delta(0)).
    """
    _check_depth(depth)
    size = 2 * depth + 1
    M = sp.zeros(size, size)
    for i, k in enumerate(range(-depth, depth + 1)):
        row = _row(k)
        for j, kk in enumerate(range(-depth, depth + 1)):
            coeff = row.coeff(b[kk])
            if coeff != 0:
                M[i, j] = sp.cancel(coeff / C(k))
    if exponent is not None:
        M = M.subs(lam, exponent)
    return M


@functools.lru_cache(maxsize=None)
def _mathieu_parameters():
    """theta0, theta1 of the driven pivot with moment of inertia I (000 eqs. 5-6).

    Read from the canonical stage (the Mathieu form of the linearised equation
    derived from the Lagrangian), not typed in.
    """
    from pendulab.equations import derive
    from pendulab.pipeline import canonical_form
    from pendulab.systems import DrivenPivot

    form = canonical_form(derive(DrivenPivot(body="explicit")))
    if form.kind != "mathieu":  # pragma: no cover
        raise RuntimeError(f"the driven pivot's canonical form is {form.kind}, not Mathieu's")
    return form.theta0, form.theta1


def to_dimensionless(expr):
    """Write ``expr`` in a_over_l = a/l, w0_over_w = omega0/omega and inertia_ratio = I/(m l^2)."""
    return sp.simplify(_dimensionless_groups(expr))


def _dimensionless_groups(expr):
    """:func:`to_dimensionless` before its simplify: the groups substituted, nothing else."""
    return sp.sympify(expr).subs({S.omega0: w0_over_w * S.omega,
                                  S.a: a_over_l * S.l,
                                  S.I: inertia_ratio * S.m * S.l**2})


def small_parameter_exponent(mathieu=False, depth=1):
    """000 eq. 11: sin^2(pi lam/2) to first order in theta0 and theta1^2, derived.

    Hill's relation sin^2(pi lam/2) = Delta(0) sin^2(pi sqrt(theta0)/2)
    (Whittaker & Watson sec. 19.42) is expanded with theta0 -> eps theta0,
    theta1 -> sqrt(eps) theta1 and the O(eps) term kept; Delta(0) is the
    determinant of :func:`hill_matrix` at lam = 0 with 2 depth + 1 rows (the
    O(eps) term is the same for every depth >= 1, which the tests check).

    Returns ``Eq(sin(pi*lam/2)**2, rhs)``; with ``mathieu=False`` (default) the
    right side is in the physical symbols a, l, m, I, omega0, omega through
    theta0 = -4 omega0^2/omega^2 and theta1 = 2 a l m/I (000 eqs. 5-6, read from
    the canonical stage).
    """
    _check_depth(depth)
    return _small_parameter_exponent(bool(mathieu), depth)


def _taylor_coefficients(expr, s, order):
    """Coefficients of s^0 .. s^order of a rational function of s regular at s = 0.

    Polynomial arithmetic on numerator N and denominator D (cancelled first):
    c_k = (N_k - sum_{j<k} c_j D_{k-j}) / D_0, the long division of power series.
    """
    num, den = sp.fraction(sp.cancel(expr))
    num, den = sp.Poly(num, s), sp.Poly(den, s)
    n_k = [num.coeff_monomial(s**k) for k in range(order + 1)]
    d_k = [den.coeff_monomial(s**k) for k in range(order + 1)]
    if d_k[0] == 0:  # pragma: no cover - a derivation bug
        raise RuntimeError("the scaled Delta(0) has a pole at eps = 0")
    out = []
    for k in range(order + 1):
        out.append(sp.cancel((n_k[k] - sum(out[j] * d_k[k - j] for j in range(k))) / d_k[0]))
    return out


@functools.lru_cache(maxsize=None)
def _small_parameter_exponent(mathieu, depth):
    if not mathieu:
        # the physical form: the Mathieu-plane result with theta0, theta1 of 000 eqs. 5-6
        rhs = _small_parameter_exponent(True, depth).rhs
        th0, th1 = _mathieu_parameters()
        physical = rhs.subs({S.theta0: th0, S.theta1: th1}, simultaneous=True)
        return sp.Eq(sp.sin(sp.pi * lam / 2) ** 2, sp.factor(sp.cancel(physical)), evaluate=False)
    # eps = s^2: theta0 -> s^2 theta0, theta1 -> s theta1; Delta(0) is then rational in s
    # and regular at s = 0, sin^2(pi s sqrt(theta0)/2) a power series in s; the O(eps)
    # term is the s^2 coefficient of their product (series by polynomial arithmetic).
    s = sp.Symbol("s", positive=True)
    x = sp.Symbol("x")
    delta0 = hill_matrix(depth, 0).det(method="berkowitz")
    scaled = delta0.subs({S.theta0: s**2 * S.theta0, S.theta1: s * S.theta1},
                         simultaneous=True)
    c = _taylor_coefficients(scaled, s, 2)
    # Taylor coefficients f^(k)(0)/k! of sin^2(pi x/2), x = s sqrt(theta0)
    half, derivative = sp.sin(sp.pi * x / 2) ** 2, []
    for k in range(3):
        derivative.append(half.subs(x, 0) / sp.factorial(k))
        half = sp.diff(half, x)
    h = [derivative[k] * sp.sqrt(S.theta0) ** k for k in range(3)]
    product = [sp.expand(sum(c[j] * h[k - j] for j in range(k + 1))) for k in range(3)]
    if product[0] != 0 or product[1] != 0:  # pragma: no cover
        raise RuntimeError("Delta(0) sin^2 has an O(1) or O(sqrt(eps)) term")
    return sp.Eq(sp.sin(sp.pi * lam / 2) ** 2, sp.factor(product[2]), evaluate=False)


@functools.lru_cache(maxsize=None)
def interval_eq12():
    """000 eq. 12: (lower, upper) limits of a/l from 0 < sin^2(pi lam/2) < 1, derived.

    The right side of :func:`small_parameter_exponent` is written in a/l,
    omega0/omega and I/(m l^2); it increases with a/l (checked), so the limits
    are its roots at 0 and at 1.  Returns expressions in ``w0_over_w`` and
    ``inertia_ratio``.
    """
    # the right side in the groups, as one cancelled fraction: l, m and omega cancel (no
    # simplify needed; cancel's numerator and denominator are those of to_dimensionless's form,
    # which tests/test_phelps_hunter.py checks)
    rhs = sp.cancel(_dimensionless_groups(small_parameter_exponent().rhs))
    if rhs.free_symbols - {a_over_l, w0_over_w, inertia_ratio}:  # pragma: no cover
        raise RuntimeError(f"eq. 11 is not dimensionless: {rhs}")
    if not sp.factor(sp.diff(rhs, a_over_l)).is_positive:  # pragma: no cover
        raise RuntimeError("sin^2(pi lam/2) of eq. 11 does not increase with a/l")
    # rhs = level is a quadratic in a/l once the denominator is cleared: its roots by the
    # quadratic formula, the one that can be positive kept (a_over_l is a positive symbol)
    num, den = sp.fraction(rhs)
    return tuple(sp.simplify(quadratic_root(num - level * den, a_over_l, f"eq. 11 = {level}"))
                 for level in (0, 1))


def quadratic_root(expr, x, what):
    """The root of ``expr`` = 0, a quadratic polynomial in ``x``, by the quadratic formula:
    the one of the two that can be positive (exactly one must be)."""
    poly = sp.Poly(expr, x)
    if poly.degree() != 2:  # pragma: no cover - a derivation bug
        raise RuntimeError(f"{what} is not quadratic in {x}")
    A, B, C0 = (poly.coeff_monomial(x**k) for k in (2, 1, 0))
    roots = [(-B + sign * sp.sqrt(B**2 - 4 * A * C0)) / (2 * A) for sign in (1, -1)]
    (root,) = [r for r in roots if r.is_positive is not False]
    return root


def characteristic_a0_series(order):
    """a_0 as a power series in theta1 from the lam = 0 continued fraction, derived.

    At lam = 0 the Floquet solution has period pi and the equation for lam
    (:func:`lambda_polynomial`) becomes the characteristic equation of the
    even pi-periodic solutions; its root near theta0 = 0 is the characteristic
    value a_0 (in Mathieu's standard form theta0 = a, theta1 = -q, and
    a_0(-q) = a_0(q)).  theta0 = sum_{k=1}^{order} c_k theta1^(2k) is put into
    it and solved order by order; depth order + 1 is enough for these terms.

    >>> characteristic_a0_series(2)
    7*theta1**4/128 - theta1**2/2
    """
    if isinstance(order, bool) or not isinstance(order, int) or not 1 <= order <= MAX_DEPTH - 1:
        raise InputError(f"order must be an integer between 1 and {MAX_DEPTH - 1}, got {order!r}")
    return _characteristic_a0_series(order)


@functools.lru_cache(maxsize=None)
def _characteristic_a0_series(order):
    s = sp.Symbol("s")  # theta1^2
    poly = lambda_polynomial(order + 1).as_expr().subs(lam, 0)
    if poly.subs(S.theta1, sp.sqrt(s)).has(sp.sqrt(s)):  # pragma: no cover
        raise RuntimeError("the lam = 0 equation is not even in theta1")
    poly = sp.expand(poly.subs(S.theta1, sp.sqrt(s)))
    coeffs = sp.symbols(f"c1:{order + 1}")
    trial = sum(c * s ** (k + 1) for k, c in enumerate(coeffs))
    expanded = sp.expand(poly.subs(S.theta0, trial))
    found = {}
    for k, c in enumerate(coeffs):
        eq = expanded.coeff(s, k + 1).subs(found)
        (found[c],) = sp.solve(eq, c)
    return sum(found[c] * S.theta1 ** (2 * (k + 1)) for k, c in enumerate(coeffs))


def lower_limit_small_ratio(order=2):
    """The exact lower limit of a/l for small omega0/omega, as a series, derived.

    The inverted pendulum is stable just above the a_0 curve, so the lower
    limit solves a_0(theta1) = theta0 with theta0 = -4 (omega0/omega)^2 and
    theta1 = 2 (a/l)/(I/(m l^2)) (000 eqs. 5-6).  The series of
    :func:`characteristic_a0_series` is inverted term by term; returns a/l as a
    polynomial in w0_over_w (odd powers up to 2 order - 1) times inertia_ratio.

    >>> lower_limit_small_ratio(1)
    sqrt(2)*inertia_ratio*w0_over_w
    """
    a0 = characteristic_a0_series(order)
    return _lower_limit_small_ratio(order, a0)


@functools.lru_cache(maxsize=None)
def _lower_limit_small_ratio(order, a0):
    th0, th1 = _mathieu_parameters()
    th0 = to_dimensionless(th0)
    th1 = to_dimensionless(th1)
    # a/l in terms of theta1 (000 eq. 6) and theta1^2 = sum d_j rho^(2j) from a0(theta1) = theta0.
    (x_of_th1,) = sp.solve(sp.Eq(th1, S.theta1), a_over_l)
    u = sp.Symbol("u", positive=True)  # (omega0/omega)^2
    d = sp.symbols(f"d1:{order + 1}")
    s_trial = sum(dj * u ** (j + 1) for j, dj in enumerate(d))
    residual = sp.expand(a0.subs(S.theta1, sp.sqrt(s_trial)) - th0.subs(w0_over_w, sp.sqrt(u)))
    found = {}
    for j, dj in enumerate(d):
        eq = sp.expand(residual.coeff(u, j + 1).subs(found))
        sols = [v for v in sp.solve(eq, dj) if v != 0]
        (found[dj],) = sols
    s_series = s_trial.subs(found)
    theta1_series = sp.sqrt(s_series)  # theta1 > 0 on the branch a/l > 0
    rho = w0_over_w
    expansion = sp.series(theta1_series.subs(u, rho**2), rho, 0, 2 * order).removeO()
    return sp.expand(x_of_th1.subs(S.theta1, expansion))
