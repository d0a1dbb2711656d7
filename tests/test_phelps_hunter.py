"""Phelps–Hunter (000 sec. 2.2): the derived results against the source, DLMF and numbers.

References typed here are the SOURCE's printed equations (cited by number) or
DLMF; the module derives its results without them.
"""

import math
import random

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.special import mathieu_a

from pendulab import symbols as S
from pendulab.analyses import phelps_hunter as ph
from pendulab.errors import InputError

lam, b, n = ph.lam, ph.b, ph.n
rho, x, r = ph.w0_over_w, ph.a_over_l, ph.inertia_ratio


def trace_monodromy(theta0, theta1):
    """Trace of the monodromy matrix of 000 eq. 7 over one period pi (scipy, independent of ph).

    Floquet: the trace is 2 cos(pi lam) for theta = e^{i lam tau} p(tau).
    """
    def rhs(tau, y):
        k = theta0 + 2 * theta1 * math.cos(2 * tau)
        return [y[1], -k * y[0], y[3], -k * y[2]]
    sol = solve_ivp(rhs, (0, math.pi), [1, 0, 0, 1], rtol=1e-12, atol=1e-14, method="DOP853")
    y = sol.y[:, -1]
    return y[0] + y[3]


# -- 000 eqs. 9-10 --------------------------------------------------------------

def test_recurrence_is_the_sources_eq_10():
    # 000 eq. 10: theta1 b_{n-1} + C_n b_n + theta1 b_{n+1} = 0, C_n = theta0 - (2n + lam)^2.
    source = S.theta1 * b[n - 1] + (S.theta0 - (2 * n + lam) ** 2) * b[n] + S.theta1 * b[n + 1]
    assert sp.expand(ph.recurrence().lhs - source) == 0


def test_recurrence_leaves_zero_residual_in_eq_7():
    # Put the ansatz truncated at |n| <= 3 into 000 eq. 7 (cosine form, not the
    # module's exponential one) and subtract sum_k row_k e^{i(2k+lam)tau}:
    # exactly zero when b_{|k|>3} = 0.
    N = 3
    theta = ph.ansatz(N)
    lhs = sp.diff(theta, S.tau, 2) + (S.theta0 + 2 * S.theta1 * sp.cos(2 * S.tau)) * theta
    rows = 0
    for k in range(-N - 1, N + 2):
        row = ph.recurrence().lhs.subs(n, k)
        row = row.subs({b[j]: 0 for j in range(-N - 3, N + 4) if abs(j) > N})
        rows += row * sp.exp(sp.I * (2 * k + lam) * S.tau)
    residual = sp.expand(sp.powsimp(sp.expand((lhs - rows).rewrite(sp.exp)), combine="exp"))
    assert residual == 0


def test_recurrence_fails_for_a_wrong_row():
    # The residual test can fail: a wrong sign of theta1 leaves terms.
    theta = ph.ansatz(1)
    lhs = sp.diff(theta, S.tau, 2) + (S.theta0 + 2 * S.theta1 * sp.cos(2 * S.tau)) * theta
    wrong = sum((-S.theta1 * b[k - 1] + ph.C(k) * b[k] - S.theta1 * b[k + 1]).subs(
        {b[-2]: 0, b[2]: 0, b[-3]: 0, b[3]: 0}) * sp.exp(sp.I * (2 * k + lam) * S.tau)
        for k in range(-2, 3))
    residual = sp.expand(sp.powsimp(sp.expand((lhs - wrong).rewrite(sp.exp)), combine="exp"))
    assert residual != 0


# -- continued fractions ----------------------------------------------------------

def test_continued_fraction_has_the_sources_shape():
    # 000, after eq. 10: b_n = -theta1 b_{n-1} / (C_n - theta1^2/(C_{n+1} - ...)), n > 0,
    # and the mirror image for n < 0.
    C = ph.C
    plus = -S.theta1 / (C(1) - S.theta1**2 / (C(2) - S.theta1**2 / C(3)))
    minus = -S.theta1 / (C(-1) - S.theta1**2 / (C(-2) - S.theta1**2 / C(-3)))
    assert sp.simplify(ph.continued_fraction(1, 3) - plus) == 0
    assert sp.simplify(ph.continued_fraction(-1, 3) - minus) == 0


def test_continued_fraction_solves_the_truncated_system():
    # Independent route: solve rows +-1..+-N of the recurrence (b_0 = 1,
    # b_{+-(N+1)} = 0) as a linear system at random non-special values.
    rng = random.Random(20240601)
    N = 4
    for _ in range(3):
        vals = {S.theta0: rng.uniform(-1, 3), S.theta1: rng.uniform(0.1, 2), lam: rng.uniform(0, 1)}
        unknowns = [b[k] for k in range(-N, N + 1) if k != 0]
        rows = [ph.recurrence().lhs.subs(n, k) for k in range(-N, N + 1) if k != 0]
        rows = [row.subs({b[0]: 1, b[N + 1]: 0, b[-N - 1]: 0}).subs(vals) for row in rows]
        sol = sp.solve(rows, unknowns)
        for sign in (1, -1):
            cf = ph.continued_fraction(sign, N).subs(vals)
            assert abs(float(cf) - float(sol[b[sign]])) < 1e-12


# -- the polynomial in lam --------------------------------------------------------

def test_lambda_polynomial_degree_6_at_first_approximation():
    # 000, text before eq. 11: "em uma primeira aproximação o polinômio ... é de ordem 6".
    assert ph.lambda_polynomial(1).degree() == 6
    assert [ph.lambda_polynomial(N).degree() for N in (2, 3)] == [10, 14]


def test_lambda_polynomial_depth_1_is_C0_C1_Cm1_form():
    # Clearing C_1 C_{-1} from C_0 - theta1^2/C_1 - theta1^2/C_{-1} = 0 by hand.
    C = ph.C
    by_hand = sp.expand(C(0) * C(1) * C(-1) - S.theta1**2 * (C(1) + C(-1)))
    ratio = sp.cancel(ph.lambda_polynomial(1).as_expr() / by_hand)
    assert ratio.is_number and ratio != 0


def _exponent_from_continued_fraction(theta0, theta1, depth=6):
    """Root in (0, 1) of the derived lam equation (continued fractions, depth 6), 30 digits."""
    eq = ph.lambda_equation(depth).subs({S.theta0: sp.Rational(theta0), S.theta1: sp.Rational(theta1)})
    f = sp.lambdify(lam, eq, "mpmath")
    with mpmath.workdps(30):
        return float(mpmath.findroot(f, 0.5))


def _exponent_from_hill(theta0, theta1, rows=2000):
    """Hill's relation with Delta(0) as a continuant of the derived entries theta1/C_n(0).

    The truncation error of Delta(0) falls like 1/N^3 (the entries fall like
    1/n^2), hence the many rows; the entries come from the derived matrix.
    """
    entry = ph.hill_matrix(1, 0)[1, 2]  # row n = 0, column n = 1: theta1/C_0(0)
    assert sp.simplify(entry - S.theta1 / S.theta0) == 0
    with mpmath.workdps(30):
        th0, th1 = mpmath.mpf(theta0), mpmath.mpf(theta1)
        e = [th1 / (th0 - 4 * k * k) for k in range(-rows, rows + 1)]
        d_prev, d = mpmath.mpf(1), mpmath.mpf(1)
        for i in range(1, len(e)):
            d_prev, d = d, d - e[i - 1] * e[i] * d_prev
        s2 = d * mpmath.sin(mpmath.pi * mpmath.sqrt(th0) / 2) ** 2
        return float(2 * mpmath.asin(mpmath.sqrt(s2)) / mpmath.pi)


@pytest.mark.parametrize("theta0, theta1", [("0.3", "0.2"), ("0.1", "0.35"), ("0.55", "0.1")])
def test_exponent_three_ways(theta0, theta1):
    # (a) root of the derived equation for lam (continued fractions);
    # (b) Hill's relation sin^2(pi lam/2) = Delta(0) sin^2(pi sqrt(theta0)/2);
    # (c) the monodromy matrix by scipy's integrator (fully independent).
    lam_a = _exponent_from_continued_fraction(theta0, theta1)
    lam_b = _exponent_from_hill(theta0, theta1)
    lam_c = math.acos(trace_monodromy(float(theta0), float(theta1)) / 2) / math.pi
    assert abs(lam_a - lam_c) < 1e-9
    assert abs(lam_b - lam_c) < 1e-9


def test_first_approximation_is_not_exact():
    # The depth-1 (degree-6) equation is an approximation: its root differs
    # from the exact exponent by more than the tolerance above (the test can fail).
    lam_1 = _exponent_from_continued_fraction("0.1", "0.35", depth=1)
    lam_c = math.acos(trace_monodromy(0.1, 0.35) / 2) / math.pi
    assert abs(lam_1 - lam_c) > 1e-6


# -- 000 eq. 11 -----------------------------------------------------------------

def test_small_parameter_exponent_is_the_sources_eq_11():
    a, l, m, I, w, w0 = S.a, S.l, S.m, S.I, S.omega, S.omega0
    # 000 eq. 11 as printed.
    source_rhs = sp.pi**2 / 4 * (2 * a**2 * l**2 * m**2 / I**2 - 4 * w0**2 / w**2)
    derived = ph.small_parameter_exponent()
    assert derived.lhs == sp.sin(sp.pi * lam / 2) ** 2
    assert sp.simplify(derived.rhs - source_rhs) == 0
    rng = random.Random(11)
    for _ in range(5):
        vals = {s: sp.Rational(rng.randint(1, 97), rng.randint(1, 31)) for s in (a, l, m, I, w, w0)}
        assert derived.rhs.subs(vals) == source_rhs.subs(vals)


def test_eq_11_does_not_depend_on_the_truncation():
    assert ph.small_parameter_exponent(mathieu=True, depth=2) == \
        ph.small_parameter_exponent(mathieu=True, depth=1)


@pytest.mark.parametrize("eps", [1e-2, 1e-3])
def test_eq_11_is_the_small_parameter_limit(eps):
    # sin^2(pi lam/2) = (2 - trace)/4 from the monodromy matrix; eq. 11 must
    # approach it with a relative error O(eps) as theta0 ~ eps, theta1 ~ sqrt(eps).
    theta0, theta1 = -0.7 * eps, math.sqrt(2.9 * eps)
    exact = (2 - trace_monodromy(theta0, theta1)) / 4
    rhs = ph.small_parameter_exponent(mathieu=True).rhs
    approx = float(rhs.subs({S.theta0: theta0, S.theta1: theta1}))
    assert abs(approx - exact) / abs(exact) < 3 * eps


# -- 000 eq. 12 -----------------------------------------------------------------

def test_interval_is_the_sources_eq_12():
    lower, upper = ph.interval_eq12()
    # 000 eq. 12 with omega = 1 (only omega0/omega enters):
    # sqrt(2) (I/m l^2) omega0/omega < a/l < sqrt(2) (I/m l^2) sqrt(omega^2 + pi^2 omega0^2)/(pi omega).
    assert sp.simplify(lower - sp.sqrt(2) * r * rho) == 0
    assert sp.simplify(upper - sp.sqrt(2) * r * sp.sqrt(1 + sp.pi**2 * rho**2) / sp.pi) == 0
    rng = random.Random(12)
    for _ in range(5):
        vals = {rho: rng.uniform(0, 1), r: rng.uniform(1, 2)}
        ref_up = math.sqrt(2) * vals[r] * math.sqrt(1 + math.pi**2 * vals[rho]**2) / math.pi
        assert abs(float(upper.subs(vals)) - ref_up) < 1e-12


# -- a_0 and the exact lower limit ------------------------------------------------

def test_a0_series_is_dlmf_28_6_1():
    # DLMF 28.6.1: a_0(q) = -q^2/2 + 7 q^4/128 - 29 q^6/2304 + 68687 q^8/18874368 + ...
    q = S.theta1
    dlmf = -q**2 / 2 + sp.Rational(7, 128) * q**4 - sp.Rational(29, 2304) * q**6 \
        + sp.Rational(68687, 18874368) * q**8
    assert sp.expand(ph.characteristic_a0_series(4) - dlmf) == 0


def test_a0_series_against_scipy_at_small_q():
    # scipy.special.mathieu_a(0, q) is accurate at small q.
    series = sp.lambdify(S.theta1, ph.characteristic_a0_series(4))
    for q in (0.05, 0.2, 0.4):
        assert abs(series(q) - mathieu_a(0, q)) < 2e-3 * q**10 + 1e-13


def test_lower_limit_slope_is_eq_12_lower_bound():
    # The exact lower limit starts as sqrt(2) (I/(m l^2)) omega0/omega, the
    # lower end of 000 eq. 12, whatever the body.
    series = ph.lower_limit_small_ratio(3)
    assert sp.expand(series.coeff(rho, 1) - sp.sqrt(2) * r) == 0
    # and agrees with a scipy root of a_0(q) = theta0 at omega0/omega = 0.05, rod:
    from scipy.optimize import brentq
    ratio, inertia = 0.05, 4 / 3
    q = brentq(lambda q: mathieu_a(0, q) + 4 * ratio**2, 1e-6, 1)
    exact = q * inertia / 2
    assert abs(float(series.subs({rho: ratio, r: inertia})) - exact) < 1e-7


# -- bad input ----------------------------------------------------------------------

@pytest.mark.parametrize("call, message", [
    (lambda: ph.continued_fraction(0, 2), "n_sign must be \\+1 or -1"),
    (lambda: ph.continued_fraction(True, 2), "n_sign must be \\+1 or -1"),
    (lambda: ph.continued_fraction(1, 0), "depth must be between 1"),
    (lambda: ph.continued_fraction(1, 2.0), "depth must be an integer"),
    (lambda: ph.lambda_polynomial(99), "depth must be between 1"),
    (lambda: ph.characteristic_a0_series(0), "order must be an integer"),
])
def test_bad_input_is_one_line_input_error(call, message):
    with pytest.raises(InputError, match=message) as info:
        call()
    assert "\n" not in str(info.value)


# -- the fast derivation against the slow one ----------------------------------------

def _slow_eq11_and_eq12():
    """000 eqs. 11-12 the slow way (SymPy series, simplify and solve), an independent route
    to the same expressions that the module derives by polynomial arithmetic."""
    eps = sp.Symbol("eps", positive=True)
    delta0 = ph.hill_matrix(1, 0).det(method="berkowitz")
    half = sp.sin(sp.pi * sp.sqrt(S.theta0) / 2) ** 2
    scaled = (delta0 * half).subs({S.theta0: eps * S.theta0, S.theta1: sp.sqrt(eps) * S.theta1},
                                  simultaneous=True)
    expansion = sp.expand(sp.series(scaled, eps, 0, 2).removeO())
    mathieu = sp.factor(sp.simplify(expansion.coeff(eps, 1)))
    th0, th1 = ph._mathieu_parameters()
    physical = sp.factor(sp.simplify(mathieu.subs({S.theta0: th0, S.theta1: th1},
                                                  simultaneous=True)))
    rhs = ph.to_dimensionless(physical)
    (lower,) = sp.solve(sp.Eq(rhs, 0), x)
    (upper,) = sp.solve(sp.Eq(rhs, 1), x)
    return mathieu, physical, (sp.simplify(lower), sp.simplify(upper))


def test_fast_derivation_gives_the_slow_routes_expressions():
    # structural equality: the JSON of the stability product prints these expressions and
    # lambdify turns them into the numbers, so the same tree is needed, not only equal values
    mathieu, physical, interval = _slow_eq11_and_eq12()
    assert ph.small_parameter_exponent(mathieu=True).rhs == mathieu
    assert ph.small_parameter_exponent().rhs == physical
    assert ph.interval_eq12() == interval


def test_taylor_coefficients_against_series():
    s = sp.Symbol("s")
    f = (1 + 2 * s + S.theta0 * s**2) / (3 - s + S.theta1 * s**2)
    ref = sp.expand(sp.series(f, s, 0, 4).removeO())
    got = ph._taylor_coefficients(f, s, 3)
    assert all(sp.simplify(got[k] - ref.coeff(s, k)) == 0 for k in range(4))
    # and it fails for a wrong function
    assert sp.simplify(ph._taylor_coefficients(f + s**2, s, 3)[2] - ref.coeff(s, 2)) != 0


def test_recurrence_row_is_the_one_of_the_second_derivative():
    # mathieu_operator differentiates twice by first derivatives; the row read off must be the
    # one SymPy's second derivative diff(f, tau, 2) gives, tree for tree (srepr)
    n, b = ph.n, ph.b
    window = sum(b[n + k] * sp.exp(sp.I * (2 * (n + k) + ph.lam) * S.tau) for k in range(-2, 3))
    drive = (2 * sp.cos(2 * S.tau)).rewrite(sp.exp)
    slow = sp.diff(window, S.tau, 2) + (S.theta0 + S.theta1 * drive) * window
    row = ph._frequency_part(slow, 2 * n + ph.lam)
    lhs = sum(sp.expand(row.coeff(b[n + k])) * b[n + k] for k in (-1, 0, 1))
    assert sp.srepr(ph.recurrence().lhs) == sp.srepr(lhs)
    assert sp.srepr(ph._frequency_part(ph.mathieu_operator(window), 2 * n + ph.lam)) == sp.srepr(row)
