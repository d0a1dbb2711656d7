"""The perturbation series of 000 sec. 3 and the integer-order series (DLMF 28.6).

Symbolic results are derived by pendulab.analyses.series and compared here
with the source's and DLMF's printed formulas (typed from those documents, with
their equation numbers), or proved by exact substitution into Mathieu's
equation; numbers are compared with SciPy and with an independent integration
of the equation.
"""

import math
import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from sympy import QQ
from sympy.polys.fields import field

from pendulab import symbols as S
from pendulab.analyses import series as se
from pendulab.errors import AccuracyWarning, PendulabError, SeriesDomainError

nu, tau, theta1 = S.nu, S.tau, S.theta1


def _same(a, b):
    return sp.cancel(sp.together(a - b)) == 0


def _coeffs(row):
    return dict(row)


# -- the source, 000 sec. 3 ---------------------------------------------------------

def test_order_one_and_two_agree_with_the_source():
    s = se.mathieu_series(2)
    # 000 sec. 3: alpha_1 = 0, alpha_2 = 1/(2(nu-1)(nu+1)) (also eq. 27)
    assert s.alpha[1] == 0
    assert _same(s.alpha[2], 1 / (2 * (nu - 1) * (nu + 1)))
    # 000 sec. 3: c_1 = (1/4)[cos((nu+2)tau)/(nu+1) - cos((nu-2)tau)/(nu-1)]
    c1 = _coeffs(s.c[1])
    assert set(c1) == {-1, 1}
    assert _same(c1[1], sp.Rational(1, 4) / (nu + 1))
    assert _same(c1[-1], -sp.Rational(1, 4) / (nu - 1))
    # 000 sec. 3 (before eq. 27): c_2 = (1/32)[cos((nu+4)tau)/((nu+1)(nu+2)) + cos((nu-4)tau)/((nu-1)(nu-2))]
    c2 = _coeffs(s.c[2])
    assert set(c2) == {-2, 2}
    assert _same(c2[2], sp.Rational(1, 32) / ((nu + 1) * (nu + 2)))
    assert _same(c2[-2], sp.Rational(1, 32) / ((nu - 1) * (nu - 2)))
    # the sine series (000, after eq. 27) has the same coefficients with sines
    assert s.s[1] == s.c[1] and s.s[2] == s.c[2]


def test_theta0_to_second_order_is_eq_27():
    s = se.mathieu_series(3)
    # 000 eq. 27: theta0 ~ nu^2 + theta1^2 / (2 (nu-1)(nu+1))
    eq27 = nu**2 + theta1**2 / (2 * (nu - 1) * (nu + 1))
    assert _same(s.theta0_expr(), eq27)   # alpha_3 = 0 as well


# -- DLMF 28.15 -------------------------------------------------------------------------

def test_alpha_agrees_with_dlmf_28_15_1():
    s = se.mathieu_series(6)
    # DLMF 28.15.1: a_nu(q) = nu^2 + q^2/(2(nu^2-1)) + (5nu^2+7) q^4/(32(nu^2-1)^3(nu^2-4))
    #               + (9nu^4+58nu^2+29) q^6/(64(nu^2-1)^5(nu^2-4)(nu^2-9)) + ...
    # with q = -theta1 the even powers are unchanged and the odd ones vanish.
    dlmf = {
        2: 1 / (2 * (nu**2 - 1)),
        4: (5 * nu**2 + 7) / (32 * (nu**2 - 1)**3 * (nu**2 - 4)),
        6: (9 * nu**4 + 58 * nu**2 + 29) / (64 * (nu**2 - 1)**5 * (nu**2 - 4) * (nu**2 - 9)),
    }
    for n in range(1, 7):
        assert _same(s.alpha[n], dlmf.get(n, 0)), n


def test_c_agrees_with_dlmf_28_15_2_away_from_k_0():
    s = se.mathieu_series(2)
    # DLMF 28.15.2: me_nu(z, q) = e^{i nu z} - (q/4)(e^{i(nu+2)z}/(nu+1) - e^{i(nu-2)z}/(nu-1))
    #   + (q^2/32)(e^{i(nu+4)z}/((nu+1)(nu+2)) + e^{i(nu-4)z}/((nu-1)(nu-2)) - ... e^{i nu z}) + ...
    # DLMF normalises me_nu differently, so only the k != 0 terms are comparable; q = -theta1.
    q = -theta1
    dlmf = {(1, 1): -(q / 4) / (nu + 1), (1, -1): (q / 4) / (nu - 1),
            (2, 2): (q**2 / 32) / ((nu + 1) * (nu + 2)), (2, -2): (q**2 / 32) / ((nu - 1) * (nu - 2))}
    for (n, k), value in dlmf.items():
        assert _same(_coeffs(s.c[n])[k] * theta1**n, value), (n, k)


# -- proof by substitution ---------------------------------------------------------------

def _field_value(raw, K, x):
    num = sum((c * x**i for i, c in enumerate(raw.num)), K(0))
    den = K(raw.den)
    for j, e in raw.exps:
        den *= (x + j) ** e
    return num / den


@pytest.mark.parametrize("order", [12])
def test_residual_vanishes_exactly_through_order(order):
    """theta_c'' + (theta0 + 2 theta1 cos 2tau) theta_c = O(theta1^(N+1)), coefficient by coefficient.

    Independent arithmetic: SymPy's field QQ(nu).  With theta = sum_k A_k cos((nu+2k)tau)
    and A_k = sum_n a_{k,n} theta1^n, the cos((nu+2k)tau) part of the residual is
    (nu^2 - (nu+2k)^2 + sum_m alpha_m theta1^m) A_k + theta1 (A_{k-1} + A_{k+1}).
    The sine series gives the same equations (2 cos 2tau sin x = sin(x+2tau) + sin(x-2tau)),
    so this also proves theta_s.
    """
    K, x = field("nu", QQ)
    s = se.mathieu_series(order)
    alpha = {n: _field_value(a, K, x) for n, a in s.alpha_raw.items()}
    A = {0: {0: K(1)}}
    for n, row in s.c_raw.items():
        for k, v in row:
            A.setdefault(k, {})[n] = _field_value(v, K, x)
    ks = range(-order - 2, order + 3)
    leading = []
    for k in ks:
        res = {}
        for n, v in A.get(k, {}).items():
            res[n] = res.get(n, K(0)) + (x**2 - (x + 2 * k) ** 2) * v
            for m, a in alpha.items():
                if a != 0 and n + m <= order + 1:
                    res[n + m] = res.get(n + m, K(0)) + a * v
        for kk in (k - 1, k + 1):
            for n, v in A.get(kk, {}).items():
                if n + 1 <= order + 1:
                    res[n + 1] = res.get(n + 1, K(0)) + v
        for p in range(0, order + 1):
            assert res.get(p, K(0)) == 0, (k, p)
        leading.append(res.get(order + 1, K(0)))
    # the residual really starts at theta1^(N+1)
    assert any(v != 0 for v in leading)


def test_residual_with_sympy_calculus_order_4():
    """Differentiate the SymPy expressions with SymPy and probe: no theta1^1..theta1^4 left."""
    s = se.mathieu_series(4)
    for kind in ("cos", "sin"):
        theta = s.solution_expr(kind)
        res = sp.diff(theta, tau, 2) + (s.theta0_expr() + 2 * theta1 * sp.cos(2 * tau)) * theta
        # probe at non-special nu, tau with 40 digits (the exact proof is the test above)
        for nv, tv in ((sp.Rational(3, 10), sp.Rational(7, 10)), (sp.Rational(13, 7), sp.Rational(5, 3))):
            poly = sp.Poly(sp.expand(res.subs({nu: nv, tau: tv})), theta1)
            for p in range(0, 5):
                assert abs(poly.coeff_monomial(theta1**p).evalf(40)) < 1e-30, (kind, p)
            # and theta1^5 is left: the residual starts at N + 1
            assert abs(poly.coeff_monomial(theta1**5).evalf(30)) > 1e-6


def _count_orders(eng):
    """Record, in the returned list, each order ``eng`` computes from now on."""
    calls = []
    original = eng._next

    def counting():
        calls.append(eng.order + 1)
        original()

    eng._next = counting
    return calls


def test_extension_reuses_computed_orders():
    eng = se._Engine()
    calls = _count_orders(eng)
    eng.extend(6)
    kept = {k: v for k, v in eng.c[5].items()}
    eng.extend(10)
    assert calls == list(range(1, 11))            # each order computed once
    assert all(eng.c[5][k] is v for k, v in kept.items())
    # and the grown engine agrees with a fresh one
    fresh = se._Engine()
    fresh.extend(10)
    assert fresh.alpha == eng.alpha and fresh.c == eng.c


def _stored_parts(v):
    """Numerator and denominator of a stored coefficient as SymPy polynomials, as stored (no cancel)."""
    num = sp.Poly(list(reversed(v.num)), nu)
    den = sp.Poly(v.den, nu)
    for j, e in v.exps:
        den = den * sp.Poly(nu + j, nu) ** e
    return num, den


def test_no_floats_and_lowest_terms():
    s = se.mathieu_series(10)
    for n, a in s.alpha.items():
        assert not a.atoms(sp.Float)
    rows = [[(None, a) for a in s.alpha_raw.values() if not a.is_zero()]] + list(s.c_raw.values())
    checked = 0
    for row in rows:
        for _, v in row:
            num, den = _stored_parts(v)
            # SymPy's polynomial gcd of the parts as stored is a unit: nothing left to cancel,
            # neither a factor (nu + j) nor an integer
            assert sp.gcd(num, den).is_ground and math.gcd(*v.num, v.den) == 1
            x = Fraction(7, 3)                      # the parts are those of the stored value
            assert Fraction(int(num.eval(x).p), int(num.eval(x).q)) / Fraction(
                int(den.eval(x).p), int(den.eval(x).q)) == v.evaluate(x)
            checked += 1
    assert checked == 65          # alpha_2..alpha_10 (5); c_1..c_10 have 2, 2, 4, 4, .., 10, 10 (60)
    # the check can fail: an unreduced value is caught
    doubled = se.mathieu_series(4).alpha_raw[2]
    bad_num, bad_den = _stored_parts(doubled)
    bad_num, bad_den = bad_num * sp.Poly(nu + 3, nu), bad_den * sp.Poly(nu + 3, nu)
    assert not sp.gcd(bad_num, bad_den).is_ground


# -- integer order: DLMF 28.6 -----------------------------------------------------------

# DLMF 28.6.1-28.6.13 (leading terms as printed there), power of q -> coefficient
DLMF_28_6 = {
    "a0": [0, 0, "-1/2", 0, "7/128", 0, "-29/2304", 0, "68687/18874368"],                       # 28.6.1
    "a1": [1, 1, "-1/8", "-1/64", "-1/1536", "11/36864", "49/589824", "55/9437184",
           "-83/35389440"],                                                                   # 28.6.2
    "b1": [1, -1, "-1/8", "1/64", "-1/1536", "-11/36864", "49/589824", "-55/9437184",
           "-83/35389440"],                                                                   # 28.6.3
    "a2": [4, 0, "5/12", 0, "-763/13824", 0, "1002401/79626240", 0, "-1669068401/458647142400"],  # 28.6.4
    "b2": [4, 0, "-1/12", 0, "5/13824", 0, "-289/79626240", 0, "21391/458647142400"],           # 28.6.5
    "a3": [9, 0, "1/16", "1/64", "13/20480", "-5/16384", "-1961/23592960", "-609/104857600"],   # 28.6.6
    "b3": [9, 0, "1/16", "-1/64", "13/20480", "5/16384", "-1961/23592960", "609/104857600"],    # 28.6.7
    "a4": [16, 0, "1/30", 0, "433/864000", 0, "-5701/2721600000"],                              # 28.6.8
    "b4": [16, 0, "1/30", 0, "-317/864000", 0, "10049/2721600000"],                             # 28.6.9
    "a5": [25, 0, "1/48", 0, "11/774144", "1/147456", "37/891813888"],                          # 28.6.10
    "b5": [25, 0, "1/48", 0, "11/774144", "-1/147456", "37/891813888"],                         # 28.6.11
    "a6": [36, 0, "1/70", 0, "187/43904000", 0, "6743617/92935987200000"],                      # 28.6.12
    "b6": [36, 0, "1/70", 0, "187/43904000", 0, "-5861633/92935987200000"],                     # 28.6.13
}


@pytest.mark.parametrize("kind", sorted(DLMF_28_6))
def test_integer_series_agree_with_dlmf_28_6(kind):
    ref = DLMF_28_6[kind]
    s = se.characteristic_series(kind, len(ref) - 1)
    assert [s.coefficients[p] for p in range(len(ref))] == [Fraction(c) for c in ref]


def test_integer_series_dlmf_28_6_14_and_28_6_15():
    # DLMF 28.6.14: for m >= 7 both a_m and b_m begin
    # m^2 + q^2/(2(m^2-1)) + (5m^2+7)q^4/(32(m^2-1)^3(m^2-4)) + (9m^4+58m^2+29)q^6/(64(m^2-1)^5(m^2-4)(m^2-9))
    for m in (7, 8, 9):
        M = Fraction(m * m)
        ref = [M, 0, 1 / (2 * (M - 1)), 0, (5 * M + 7) / (32 * (M - 1)**3 * (M - 4)), 0,
               (9 * M * M + 58 * M + 29) / (64 * (M - 1)**5 * (M - 4) * (M - 9))]
        for letter in "ab":
            s = se.characteristic_series(f"{letter}{m}", 6)
            assert [s.coefficients[p] for p in range(7)] == ref
    # DLMF 28.6.15: a_m - b_m = 2 q^m / (2^(m-1) (m-1)!)^2 (1 + O(q^2)): first difference at q^m
    for m in range(1, 9):
        a = se.characteristic_series(f"a{m}", m + 1).coefficients
        b = se.characteristic_series(f"b{m}", m + 1).coefficients
        diffs = [a[p] - b[p] for p in range(m + 2)]
        assert diffs[:m] == [0] * m
        assert diffs[m] == Fraction(2, (2 ** (m - 1) * math.factorial(m - 1)) ** 2)
        assert diffs[m + 1] == 0


def test_nu_series_at_nu_0_is_the_a0_series():
    """Two independent generators: alpha_n(0) (000 eq. 20 at nu = 0) and a_0(q) (DLMF 28.6.1)."""
    N = 30
    s = se.mathieu_series(N)
    a0 = se.characteristic_series("a0", N).coefficients
    for n in range(1, N + 1):
        value = s.alpha_raw[n].evaluate(Fraction(0))
        assert Fraction(value) == a0[n] * (-1) ** n, n    # q = -theta1


def test_radii_from_dlmf_table_28_6_1():
    """The refusals' radii are the computed branch points (pendulab.analyses.mathieu_radii);
    they round to the digits of DLMF Table 28.6.1 (tests/test_mathieu_branch.py computes them
    afresh and compares every entry)."""
    # DLMF Table 28.6.1: rho_0^(1) = 1.4687686138 (a_0, a_2), rho_0^(3) = 3.7699574940 (a_1, b_1),
    # rho_0^(2) = 6.9289547588 (b_2, b_4), rho_2^(1) = 7.2681468935 (a_4); last full row, n = 7:
    # rho_7^(1) = 95.4752727072 (a_14), rho_7^(2) = 125.435411314 (b_16), rho_7^(3) = 110.027369210
    for kind, printed in (("a0", "1.4687686138"), ("a2", "1.4687686138"), ("b1", "3.7699574940"),
                          ("a3", "3.7699574940"), ("b2", "6.9289547588"), ("a4", "7.2681468935"),
                          ("a14", "95.4752727072"), ("b16", "125.435411314"),
                          ("b15", "110.027369210")):
        r = se.characteristic_series(kind, 2).radius
        half_unit = 0.5 * 10.0 ** -len(printed.split(".")[1])
        assert abs(r - float(printed)) <= half_unit * (1 + 1e-6), (kind, r)
        assert se.RADII[kind] == r
    assert len(se.RADII) == 64            # rows 0-15: a_0 .. a_31, b_1 .. b_32
    for kind in ("a32", "b33", "a40"):
        s = se.characteristic_series(kind, 2)
        assert s.radius is None and "not computed" in s.radius_source and kind not in se.RADII


def test_integer_series_extend_instead_of_recomputing():
    eng = se._CharEngine("b", 1)
    calls = _count_orders(eng)
    eng.extend(10)
    kept = list(eng.lam)
    eng.extend(25)
    eng.extend(7)
    assert calls == list(range(1, 26))            # each order computed once
    assert all(a is b for a, b in zip(eng.lam, kept))
    fresh = se._CharEngine("b", 1)
    fresh.extend(25)
    assert fresh.lam == eng.lam
    # the public function keeps one engine per kind and grows it
    se.characteristic_series("a9", 6)
    engine = se._CHAR_ENGINES[("a", 9)]
    se.characteristic_series("a9", 3)
    assert engine.order >= 6
    s = se.characteristic_series("a9", 30)
    assert se._CHAR_ENGINES[("a", 9)] is engine and engine.order >= 30 and len(s.coefficients) == 31


def _rayleigh_schroedinger(letter, m, order):
    """a_m / b_m to q^order by Rayleigh-Schroedinger perturbation theory, in Fractions.

    An independent method (pendulab lifts the root of the Hill determinant by
    Newton's iteration): on the basis phi_s of m's parity class (DLMF 28.4),
    2 cos 2z phi_s = phi_{s+2} + phi_{s-2} with cos(-x) = cos x, sin(-x) = -sin x,
    sin 0 = 0; with intermediate normalisation lam_n = (V x_{n-1})_m and
    x_n[t] = (sum_p lam_p x_{n-p}[t] - (V x_{n-1})_t) / (t^2 - m^2).
    """
    def action(s):
        out = {}
        for t in (s + 2, s - 2):
            sign = 1
            if t < 0:
                t, sign = -t, (1 if letter == "a" else -1)
            if not (letter == "b" and t == 0):
                out[t] = out.get(t, 0) + sign
        return out

    lam, x = [Fraction(m * m)], [{m: Fraction(1)}]
    for n in range(1, order + 1):
        vx = {}
        for s, v in x[n - 1].items():
            for t, w in action(s).items():
                vx[t] = vx.get(t, 0) + w * v
        lam.append(vx.get(m, Fraction(0)))
        xn = {}
        for t in set(vx).union(*x[1:n]) - {m}:
            acc = -vx.get(t, 0) + sum((lam[p] * x[n - p].get(t, 0) for p in range(1, n)), Fraction(0))
            if acc:
                xn[t] = acc / (t * t - m * m)
        x.append(xn)
    return lam


@pytest.mark.parametrize("kind", ["a0", "a1", "b1", "a2", "b2", "a3", "b4", "a7", "b8"])
def test_integer_series_agree_with_rayleigh_schroedinger(kind):
    lam = _rayleigh_schroedinger(kind[0], int(kind[1:]), 40)
    assert [se.characteristic_series(kind, 40).coefficients[p] for p in range(41)] == lam
    # lifting a known prefix of any length gives the same coefficients as one lift
    for first in (1, 2, 7, 13):
        eng = se._CharEngine(kind[0], int(kind[1:]))
        eng.extend(first)
        eng.extend(40)
        assert eng.lam == lam, first


def _characteristic_reference(kind, q):
    """a_m(q), b_m(q) from SciPy 1.17.1 at |q|, using DLMF 28.2.26 for q < 0."""
    from scipy.special import mathieu_a, mathieu_b
    letter, m = kind[0], int(kind[1:])
    if q < 0 and m % 2 == 1:
        letter = "b" if letter == "a" else "a"        # a_{2n+1}(-q) = b_{2n+1}(q)
    return (mathieu_a if letter == "a" else mathieu_b)(m, abs(q))


@pytest.mark.parametrize("kind,order", [("a0", 4), ("a0", 20), ("b1", 6), ("b1", 30), ("a3", 12), ("b4", 9)])
def test_integer_estimate_covers_the_error_inside_the_radius(kind, order):
    s = se.characteristic_series(kind, order)
    rng = np.random.default_rng(28_6)
    qs = rng.uniform(-0.98 * s.radius, 0.98 * s.radius, 80)
    values, ests = s.evaluate(qs)
    for q, v, e in zip(qs, values, ests):
        ref = _characteristic_reference(kind, q)
        assert abs(v - ref) <= 2 * e + 1e-12 * max(1.0, abs(ref)), q


def test_untabulated_kinds_are_checked_by_the_growth_of_their_terms():
    """a_32 and b_33 are beyond the computed table of radii; values are checked against Hill's method."""
    from pendulab.analyses import floquet
    for kind, q in (("a32", 12.0), ("b33", -30.0)):
        s = se.characteristic_series(kind, 16)
        value, est = s.evaluate(q)
        ref = float((floquet.mathieu_a if kind[0] == "a" else floquet.mathieu_b)(int(kind[1:]), q))
        assert abs(value - ref) <= 2 * est + 1e-12 * abs(ref)
    s = se.characteristic_series("a32", 10)
    with pytest.raises(SeriesDomainError, match="not in the computed table of radii"):
        s.evaluate(1e4)
    with pytest.raises(SeriesDomainError, match=r"element 1"):
        s.evaluate(np.array([12.0, 1e4]))
    with pytest.raises(SeriesDomainError):
        s.evaluate("1e4", dps=20)
    with pytest.warns(AccuracyWarning):
        value, est = s.evaluate(1e4, on_domain="warn")
    ref = float(floquet.mathieu_a(32, 1e4))
    assert abs(value - ref) > 1e6 and est > 1e6      # the refused sum is far off, and says so


# SciPy 1.17.1: scipy.special.mathieu_a(m, q), mathieu_b(m, q) (DLMF conventions) at small q
@pytest.mark.parametrize("kind,q", [("a0", 0.1), ("a0", 0.5), ("a0", 1.0), ("b1", 0.5), ("b1", 2.0),
                                    ("a1", 1.0), ("b2", 3.0), ("a2", 0.7)])
def test_integer_series_against_scipy(kind, q):
    from scipy.special import mathieu_a, mathieu_b
    ref = (mathieu_a if kind[0] == "a" else mathieu_b)(int(kind[1:]), q)
    s = se.characteristic_series(kind, 60)
    value, est = s.evaluate(q)
    assert abs(value - ref) < 1e-9 * max(1.0, abs(ref))
    assert est < 1e-8


def test_integer_series_truncation_shows_convergence():
    from scipy.special import mathieu_a
    ref = mathieu_a(0, 0.8)             # SciPy 1.17.1
    errors = [abs(se.characteristic_series("a0", n).evaluate(0.8)[0] - ref) for n in (4, 8, 16)]
    assert errors[0] > errors[1] > errors[2]


# -- numbers from the series --------------------------------------------------------------

def _monodromy_trace(theta0, theta1):
    """Half the trace of the monodromy matrix over tau in [0, pi] (solve_ivp, rtol 1e-12)."""
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        k = theta0 + 2 * theta1 * np.cos(2 * t)
        return [y[1], -k * y[0], y[3], -k * y[2]]

    sol = solve_ivp(rhs, (0, np.pi), [1, 0, 0, 1], rtol=1e-12, atol=1e-14, method="DOP853")
    y = sol.y[:, -1]
    return 0.5 * (y[0] + y[3])


@pytest.mark.parametrize("nu_value,t1", [(0.3, 0.2), (0.7, 0.1), (1.6, 0.3), (-0.45, 0.25)])
def test_theta0_of_nu_against_an_integration(nu_value, t1):
    """Floquet: for theta0 = theta0(nu, theta1) the solutions have multipliers e^{+-i nu pi}."""
    value, est = se.theta0_of_nu(nu_value, t1, 24)
    assert est < 1e-11
    assert abs(_monodromy_trace(value, t1) - math.cos(math.pi * nu_value)) < 1e-9


def test_theta0_of_nu_vectorised_and_mpmath_agree_with_exact_coefficients():
    N = 16
    s = se.mathieu_series(N)
    nus = [Fraction(3, 10), Fraction(17, 20), Fraction(-13, 10)]
    t1 = Fraction(1, 8)
    exact = [x * x + sum(a.evaluate(x) * t1**n for n, a in s.alpha_raw.items()) for x in nus]
    vals, ests = se.theta0_of_nu(np.array([float(x) for x in nus]), float(t1), N)
    assert vals.shape == (3,) and ests.shape == (3,)
    for v, e in zip(vals, exact):
        assert abs(v - float(e)) < 1e-14
    for x, e in zip(nus, exact):
        v, _ = se.theta0_of_nu(x, "1/8", N, dps=50)
        with mpmath.workdps(60):
            ref = mpmath.mpf(e.numerator) / e.denominator
            assert abs(v - ref) < mpmath.mpf(10) ** -45
    assert mpmath.mp.dps == 15


def test_truncation_estimate_bounds_the_error():
    ref, _ = se.theta0_of_nu(0.4, 0.5, 40, dps=30)
    for n in (4, 8, 12):
        v, est = se.theta0_of_nu(0.4, 0.5, n)
        assert abs(v - float(ref)) <= 2 * est


@pytest.mark.parametrize("kind", ["cos", "sin"])
def test_theta_c_and_theta_s_solve_the_equation(kind):
    """Integrate Mathieu's equation from the series' initial values; compare at later tau."""
    from scipy.integrate import solve_ivp
    N, nu_value, t1 = 20, 0.37, 0.3
    th0, _ = se.theta0_of_nu(nu_value, t1, N)
    f = se.theta_c if kind == "cos" else se.theta_s
    y0, _ = f(0.0, nu_value, t1, N)
    h = 1e-4
    dy0 = (f(h, nu_value, t1, N, dps=40)[0] - f(-h, nu_value, t1, N, dps=40)[0]) / (2 * h)
    sol = solve_ivp(lambda t, y: [y[1], -(th0 + 2 * t1 * np.cos(2 * t)) * y[0]], (0, 3.0),
                    [y0, float(dy0)], rtol=1e-12, atol=1e-13, t_eval=[1.0, 2.0, 3.0], method="DOP853")
    taus = np.array([1.0, 2.0, 3.0])
    vals, ests = f(taus, nu_value, t1, N)
    assert np.all(ests < 1e-9)
    assert np.max(np.abs(vals - sol.y[0])) < 1e-7


def test_theta_c_mpmath_matches_numpy():
    v1, _ = se.theta_c(1.3, 0.41, 0.2, 12)
    v2, _ = se.theta_c("1.3", "0.41", "0.2", 12, dps=30)
    assert abs(v1 - float(v2)) < 1e-14


# -- refusals --------------------------------------------------------------------------------

@pytest.mark.parametrize("nu_value", [1 + 1e-7, -2 + 5e-7, 3.0])
def test_refuses_near_integer_nu(nu_value):
    with pytest.raises(SeriesDomainError, match="integer"):
        se.theta0_of_nu(nu_value, 0.1, 6)
    with pytest.raises(SeriesDomainError):
        se.theta0_of_nu(np.array([0.5, nu_value]), 0.1, 6)
    with pytest.raises(SeriesDomainError):
        se.theta_c(0.3, nu_value, 0.1, 6, dps=20)
    with pytest.warns(AccuracyWarning) as record:
        value, est = se.theta0_of_nu(nu_value, 0.1, 6, on_domain="warn")
    assert any("integer" in str(w.message) for w in record)
    assert math.isfinite(value) or math.isinf(value)


def test_nu_zero_is_allowed_for_theta0_but_not_theta_s():
    value, _ = se.theta0_of_nu(0.0, 0.1, 8)
    ref, _ = se.characteristic_series("a0", 8).evaluate(-0.1)
    assert abs(value - ref) < 1e-15
    with pytest.raises(SeriesDomainError):
        se.theta_s(0.5, 1e-9, 0.1, 8)


def test_refuses_beyond_the_radius():
    with pytest.raises(SeriesDomainError, match="radius"):
        se.theta0_of_nu(0.5, 3.0, 20)
    with pytest.warns(AccuracyWarning):
        value, est = se.theta0_of_nu(0.5, 3.0, 20, on_domain="warn")
    assert est > 1
    a0 = se.characteristic_series("a0", 20)
    with pytest.raises(SeriesDomainError, match="Table 28.6.1"):
        a0.evaluate(1.5)
    with pytest.raises(SeriesDomainError):
        a0.evaluate("1.5", dps=30)
    with pytest.warns(AccuracyWarning):
        a0.evaluate(1.5, on_domain="warn")
    assert a0.evaluate(1.4)[0] < 0


def _exact_theta0(nu_value, t1):
    """theta0 with characteristic exponent nu (pendulab.analyses.floquet: Hill's matrix, not the series)."""
    from pendulab.analyses import floquet
    return floquet.theta0_of_exponent(nu_value, t1)


def test_refusal_beyond_the_radius_at_every_order_of_either_parity():
    """nu = 0.9, theta1 = 0.3 lies beyond the radius (the partial sums run away from the true theta0).

    The old check compared the last two nonzero terms and let even orders through
    (1.6, -8.6, 316 at N = 10, 20, 30 without a word).
    """
    exact = _exact_theta0(0.9, 0.3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        errs = [abs(se.theta0_of_nu(0.9, 0.3, n, on_domain="warn")[0] - exact) for n in (10, 20, 30)]
    assert errs[0] < errs[1] < errs[2] and errs[2] > 100      # really divergent
    for n in range(1, 31):
        with pytest.raises(SeriesDomainError, match="radius"):
            se.theta0_of_nu(0.9, 0.3, n)
        for f in (se.theta_c, se.theta_s):
            with pytest.raises(SeriesDomainError, match="radius"):
                f(0.7, 0.9, 0.3, n)
    with pytest.raises(SeriesDomainError, match="radius"):
        se.theta_c("0.7", "0.9", "0.3", 10, dps=30)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_orders_with_one_term_are_checked_too(order):
    """With at most one nonzero term there is nothing to compare; the look-ahead terms decide."""
    for nu_value, t1 in ((0.5, 50.0), (0.5, 3.0)):
        with pytest.raises(SeriesDomainError, match="radius"):
            se.theta0_of_nu(nu_value, t1, order)
        with pytest.raises(SeriesDomainError, match="radius"):
            se.theta0_of_nu(nu_value, t1, order, dps=20)


def test_no_false_refusal_at_small_theta1_for_any_order():
    """Odd orders used to be refused at nu = 0.7, theta1 = 0.01 (c_N and c_{N-1} differ in size)."""
    exact = _exact_theta0(0.7, 0.01)
    for n in range(1, 31):
        value, est = se.theta0_of_nu(0.7, 0.01, n)
        assert abs(value - exact) <= 2 * est + 1e-14
        for f in (se.theta_c, se.theta_s):
            v, e = f(0.7, 0.9, 0.01, n)
            assert math.isfinite(v) and e < 1e-3
    v5, _ = se.theta_c(0.7, 0.9, 0.01, 5)
    v30, _ = se.theta_c(0.7, 0.9, 0.01, 30)
    assert abs(v5 - v30) < 1e-9


@pytest.mark.parametrize("order", [2, 5, 12, 25])
def test_accepted_values_are_within_their_estimate_on_random_points(order):
    """Seeded random (nu, theta1); Floquet's theta0 (an independent method) is the reference.

    Every accepted value lies within twice its estimate (plus the reference's own
    rounding); refusals are real: at every refused point the truncated sum is
    off by more than 1e-8 relative.
    """
    rng = np.random.default_rng(20261122)
    nus = rng.uniform(0.02, 5.98, 600)
    nus = nus[np.abs(nus - np.round(nus)) > 1e-3]
    t1s = np.exp(rng.uniform(np.log(1e-3), np.log(30.0), nus.size))
    exact = _exact_theta0(nus, t1s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        values, ests = se.theta0_of_nu(nus, t1s, order, on_domain="warn")
    refused = np.zeros(nus.size, dtype=bool)
    for i in range(nus.size):
        try:
            se.theta0_of_nu(nus[i], t1s[i], order)
        except SeriesDomainError:
            refused[i] = True
    err = np.abs(values - exact)
    slack = 1e-10 * np.maximum(1.0, np.abs(exact))
    assert 0.2 < refused.mean() < 0.5                     # the sample spans both sides
    assert np.all(err[~refused] <= 2 * ests[~refused] + slack[~refused])
    assert np.all(err[refused] > 1e-8 * np.maximum(1.0, np.abs(exact[refused])))
    with pytest.raises(SeriesDomainError, match=r"element \d+"):
        se.theta0_of_nu(nus, t1s, order)


@pytest.mark.parametrize("call,fragment", [
    (lambda: se.mathieu_series(0), "order"),
    (lambda: se.mathieu_series(2.0), "order"),
    (lambda: se.mathieu_series(True), "order"),
    (lambda: se.characteristic_series("c1", 4), "kind"),
    (lambda: se.characteristic_series("b0", 4), "b0"),
    (lambda: se.characteristic_series("a01", 4), "plainly"),
    (lambda: se.theta0_of_nu(0.5, 0.1, 4, on_domain="ignore"), "on_domain"),
    (lambda: se.theta0_of_nu(0.5, 0.1, 4, dps=2), "dps"),
    (lambda: se.theta0_of_nu("x", 0.1, 4), "real numbers"),
    (lambda: se.stability_interval_series(4, -0.1, 1), "omega0/omega"),
    (lambda: se.stability_interval_series(1, 0.1, 1), "order"),
    # a rigid body has I = m l^2 + I0 >= m l^2 (000 sec. 2.1)
    (lambda: se.stability_interval_series(4, 0.1, 0.5), "must be >= 1"),
    (lambda: se.stability_interval_integer_series(4, 0.1, 0.99), "must be >= 1"),
    (lambda: se.stability_interval_integer_series(4, 0.1, 1, on_domain="skip"), "on_domain"),
])
def test_bad_input_is_a_one_line_value_error(call, fragment):
    with pytest.raises(PendulabError) as info:
        call()
    assert isinstance(info.value, ValueError)
    assert fragment in str(info.value) and "\n" not in str(info.value)
    assert not isinstance(info.value, SeriesDomainError) or fragment == "integer"


# -- stability intervals -----------------------------------------------------------------------

@pytest.mark.parametrize("ratio,iota", [(0.1, 1), (0.1, 4 / 3), (0.37, 4 / 3), (0.8, 1), (0.0, 2.0)])
def test_order_two_is_eq_28(ratio, iota):
    lower, upper = se.stability_interval_series(2, ratio, iota)
    # 000 eq. 28: sqrt(2) (I/ml^2) (w0/w) < a/l < sqrt(2) (I/ml^2) (1/4 + (w0/w)^2)
    assert lower == pytest.approx(math.sqrt(2) * iota * ratio, rel=1e-12, abs=1e-15)
    assert upper == pytest.approx(math.sqrt(2) * iota * (0.25 + ratio**2), rel=1e-11)


def _scipy_limits(ratio, iota):
    """Exact limits from SciPy 1.17.1's a_0 and b_1 (reliable at these small q): an independent reference."""
    from scipy.optimize import brentq
    from scipy.special import mathieu_a, mathieu_b
    target = -4 * ratio**2
    lo = brentq(lambda Q: mathieu_a(0, Q) - target, 1e-9, 1.4)
    up = brentq(lambda Q: mathieu_b(1, Q) - target, 0.5, 3.0)
    return lo * iota / 2, up * iota / 2


def test_integer_series_interval_converges_to_the_exact_one():
    ratio, iota = 0.1, 4 / 3
    exact = _scipy_limits(ratio, iota)
    prev = None
    for n in (2, 6, 12, 24):
        lo, up = se.stability_interval_integer_series(n, ratio, iota)
        err = max(abs(lo - exact[0]), abs(up - exact[1]))
        if prev is not None:
            assert err < prev
        prev = err
    assert prev < 1e-9


def test_nu_series_lower_limit_converges_but_upper_does_not():
    ratio, iota = 0.1, 4 / 3
    exact = _scipy_limits(ratio, iota)
    lows, ups = [], []
    for n in (2, 6, 10, 14, 18):
        lo, up = se.stability_interval_series(n, ratio, iota)
        lows.append(lo)
        ups.append(up)
        # lower limit: nu^2 = 0, where the nu-series is the a_0 series (see test above)
        lo_int, _ = se.stability_interval_integer_series(n, ratio, iota)
        assert lo == pytest.approx(lo_int, rel=1e-12)
    assert abs(lows[-1] - exact[0]) < 1e-8
    # the fold moves up with N but stays well below the exact upper limit (nu = 1 is a pole)
    assert ups == sorted(ups)
    assert ups[-1] < exact[1] - 0.05
    # orders 4, 8, ... have no fold: theta0 -> +infinity as nu -> 1
    assert se.stability_interval_series(4, ratio, iota)[1] is None


def test_coefficients_pickle_as_their_exact_data():
    """Engine values hold FLINT polynomials inside; they still pickle (e.g. to dask workers) exactly."""
    import pickle
    s = se.mathieu_series(8)
    for n in (4, 8):
        for k, v in s.c_raw[n]:
            back = pickle.loads(pickle.dumps(v))
            assert back == v and back.text() == v.text() and back.evaluate(Fraction(1, 3)) == v.evaluate(Fraction(1, 3))
    a = s.alpha_raw[8]
    assert pickle.loads(pickle.dumps(a)).degree() == a.degree()
