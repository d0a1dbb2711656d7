"""Characteristic exponent of 000 eq. 7 by three independent methods.

References: the three methods (continued fractions of 000 eq. 10, Hill's
determinant, monodromy integration) check one another; closed forms at
theta1 = 0; the source's small-parameter result (000 eq. 11); Liouville's
theorem (det of the monodromy matrix = 1).
"""

import math

import mpmath
import numpy as np
import pytest

from pendulab.analyses.floquet import (
    characteristic_exponent,
    mathieu_a,
    mathieu_b,
    theta0_of_exponent,
    trace_monodromy,
)
from pendulab.errors import InputError, PrecisionError


def close(a, b, digits):
    """|a - b| <= 10^-digits * max(1, |b|); strings are read at digits + 20."""
    with mpmath.workdps(digits + 20):
        a, b = mpmath.mpmathify(a), mpmath.mpmathify(b)
        return abs(a - b) <= mpmath.mpf(10) ** (-digits) * max(1, abs(b))


# points: band 0 (the source's Fig. 2 parameters, 000 sec. 2.2), the same with
# theta1 -> -theta1, gap 1 at large q, gap 2, inside band 1, below a_0
POINTS = [("-0.002", "0.2"), ("-0.002", "-0.2"), ("-100", "60"), ("3", "10"),
          ("2", "0.3"), ("-0.5", "0.2")]


@pytest.mark.parametrize("theta0,theta1", POINTS)
def test_three_methods_agree_at_50_digits(theta0, theta1):
    res = {m: characteristic_exponent(theta0, theta1, dps=50, method=m)
           for m in ("cf", "hill", "monodromy")}
    assert close(res["hill"].lam, res["cf"].lam, 49)
    assert close(res["monodromy"].lam, res["cf"].lam, 49)
    assert len({r.stable for r in res.values()}) == 1
    assert all(not r.on_boundary for r in res.values())


def test_verdicts_of_known_points():
    # source's Fig. 2 point is stable (000 sec. 2.2); a = 0.5, q = -1 lies between
    # b_1(1) and a_1(1) (A&S Table 20.1: -0.1102, 1.8591): unstable, Re lam = 1
    assert characteristic_exponent("-0.002", "0.2").stable
    r = characteristic_exponent("0.5", "1", dps=20)
    assert not r.stable and mpmath.re(r.lam) == 1 and mpmath.im(r.lam) > 0
    # below a_0: lam purely imaginary
    r = characteristic_exponent("-0.5", "0.2", dps=20)
    assert mpmath.re(r.lam) == 0 and not r.stable


def test_all_methods_agree_at_220_digits():
    cf = characteristic_exponent("-1/500", "1/5", dps=220, method="cf")
    hill = characteristic_exponent("-1/500", "1/5", dps=220, method="hill")
    mono = characteristic_exponent("-1/500", "1/5", dps=220, method="monodromy")
    assert close(hill.lam, cf.lam, 219) and close(mono.lam, cf.lam, 219)
    # the 220-digit answer is not merely the 50-digit one padded
    low = characteristic_exponent("-1/500", "1/5", dps=50, method="cf")
    with mpmath.workdps(240):
        assert 0 < abs(cf.lam - low.lam) < mpmath.mpf(10) ** -49


def test_hill_and_cf_agree_at_1000_digits():
    cf = characteristic_exponent("1/3", "1/2", dps=1000, method="cf")
    hill = characteristic_exponent("1/3", "1/2", dps=1000, method="hill")
    assert cf.stable and hill.stable
    assert close(hill.lam, cf.lam, 999)
    assert hill.depth > 1000  # Richardson used more than dps truncated determinants


def test_multipliers_product_is_one_and_trace_matches_double_path():
    for t0, t1 in POINTS:
        r = characteristic_exponent(t0, t1, dps=30)
        m1, m2 = r.multipliers
        with mpmath.workdps(30):
            assert abs(m1 * m2 - 1) < mpmath.mpf(10) ** -28  # Liouville: det = 1
            tr = mpmath.re(m1 + m2)
        td = float(trace_monodromy(float(t0), float(t1)))
        assert abs(td - float(tr)) <= 1e-9 * max(1.0, abs(float(tr)))


@pytest.mark.parametrize("theta0,expected", [("2.25", "1.5"), ("0.09", "0.3"), ("30.25", "5.5")])
def test_theta1_zero_gives_sqrt_theta0(theta0, expected):
    r = characteristic_exponent(theta0, "0", dps=40)
    with mpmath.workdps(40):
        assert r.lam == mpmath.mpf(expected)
    assert r.stable and not r.on_boundary


def test_theta1_zero_negative_theta0_is_imaginary():
    r = characteristic_exponent("-1/4", 0, dps=30)
    assert r.lam == mpmath.mpc(0, 0.5) and not r.stable


@pytest.mark.parametrize("theta0,stable", [("0", False), ("1", True), ("4", True), ("9", True)])
def test_theta1_zero_on_the_curves(theta0, stable):
    # theta0 = k^2, theta1 = 0: cos k tau and sin k tau are both bounded for k >= 1
    # (coexistence), while theta0 = 0 has the growing solution tau
    r = characteristic_exponent(theta0, 0, dps=25)
    assert r.on_boundary and r.stable is stable
    assert r.lam == int(theta0) ** 0.5


def test_double_precision_returns_python_numbers():
    r = characteristic_exponent(-0.002, 0.2)
    assert isinstance(r.lam, float) and r.dps is None
    assert isinstance(characteristic_exponent(3, 10).lam, complex)


@pytest.mark.parametrize("family,m,theta1", [("a", 0, "0.2"), ("b", 1, "-0.2"), ("a", 1, "0.2")])
def test_point_on_a_curve_to_45_digits_is_resolved_at_dps_30(family, m, theta1):
    # a 45-digit approximation of a curve is 1e-46 off it: the working precision
    # grows (default max_dps = 180) until the side is decided; the side must be
    # the one of the 45-digit value against the curve at 80 digits (mathieu_a/b:
    # eigenvalue + continued fraction in a, independent of the exponent routes)
    q = "0.2" if theta1.startswith("-") else "-0.2"  # q = -theta1, exactly
    f = mathieu_a if family == "a" else mathieu_b
    edge = f(m, q, dps=45)
    with mpmath.workdps(90):
        above = edge > f(m, q, dps=80)
    r = characteristic_exponent(edge, theta1, dps=30)
    assert not r.on_boundary
    assert abs(mpmath.re(r.lam) - m) < 1e-20 and 0 < abs(r.lam - m) < 1e-20
    # verdict, lam and multipliers agree
    assert r.stable == (mpmath.im(r.lam) == 0)
    m1, m2 = r.multipliers
    with mpmath.workdps(40):   # |m1| - 1 ~ pi mu ~ 1e-23 is below the default 15 digits
        assert r.stable == (abs(abs(m1) - 1) < 1e-25)
    cf = characteristic_exponent(edge, theta1, dps=30, method="cf")
    assert cf.stable == r.stable and close(cf.lam, r.lam, 29)
    # a_0 is the lower edge of band 0; a_1(-0.2) = b_1(0.2) and b_1(0.2) are its
    # upper edge (DLMF 28.2.26-28.2.27 and a_0 < b_1 < a_1 for q > 0)
    lower_edge = family == "a" and m == 0
    assert r.stable == (above if lower_edge else not above)


def test_near_a_curve_but_resolvable():
    # 1e-20 above a_0(0.2): inside band 0, lam ~ sqrt(c * 1e-20); hill and cf agree
    with mpmath.workdps(60):
        t0 = mathieu_a(0, "0.2", dps=60) + mpmath.mpf("1e-20")
    hill = characteristic_exponent(t0, "-0.2", dps=30, method="hill")
    cf = characteristic_exponent(t0, "-0.2", dps=30, method="cf")
    assert hill.stable and cf.stable and not hill.on_boundary
    assert 1e-12 < hill.lam < 1e-8
    assert close(hill.lam, cf.lam, 29 + 10)  # relative agreement on a ~1e-10 number
    below = characteristic_exponent(t0 - mpmath.mpf("2e-20"), "-0.2", dps=30, method="cf")
    assert not below.stable and mpmath.re(below.lam) == 0


def test_dps_too_low_for_the_answer_raises_precision_error():
    # a point 1e-25 (relative) from a_0: resolving lam to 30 digits needs ~60
    # working digits, more than max_dps allows
    with mpmath.workdps(80):
        t0 = mathieu_a(0, "0.2", dps=80)
        t0 = t0 * (1 - mpmath.mpf("1e-25"))
    with pytest.raises(PrecisionError, match="cannot resolve"):
        characteristic_exponent(t0, "0.2", dps=30, method="hill", max_dps=45)
    r = characteristic_exponent(t0, "0.2", dps=30, method="hill")  # default ceiling suffices
    assert r.stable and not r.on_boundary


def test_source_small_parameter_formula_eq11():
    # 000 eq. 11: sin^2(pi lam/2) ~ (pi^2/4)(theta1^2/2 + theta0) for small theta0, theta1
    for t0, t1 in [(-0.002, 0.2), (-0.001, 0.1), (0.0005, 0.05)]:
        lam = characteristic_exponent(t0, t1).lam
        lhs = math.sin(math.pi * lam / 2) ** 2
        rhs = math.pi ** 2 / 4 * (t1 ** 2 / 2 + t0)
        assert abs(lhs - rhs) < 0.05 * rhs


@pytest.mark.parametrize("theta0,theta1", [("-0.002", "0.2"), ("2", "0.3"), ("5.3", "-1.2")])
def test_inverse_round_trip(theta0, theta1):
    lam = characteristic_exponent(theta0, theta1, dps=40, method="cf").lam
    back = theta0_of_exponent(lam, theta1, dps=35)
    assert close(back, theta0, 34)


def test_inverse_at_and_near_integers():
    # integer nu: DLMF convention lambda_n(q) = a_n(q), q = -theta1; a_1(-q) = b_1(q)
    assert close(theta0_of_exponent(1, "0.2", dps=30), mathieu_b(1, "0.2", dps=30), 29)
    assert close(theta0_of_exponent(0, "0.2", dps=30), mathieu_a(0, "0.2", dps=30), 29)
    with mpmath.workdps(60):
        nu = mpmath.mpf(1) - mpmath.mpf("1e-15")
        # lam - 1 ~ sqrt(theta0 - edge): 1e-15 digits are lost, so 60 digits in
        t0 = theta0_of_exponent(nu, "0.2", dps=60)
        edge = mathieu_b(1, "0.2", dps=60)
        assert 0 < edge - t0 < mpmath.mpf("1e-28")  # edge approached like (1 - nu)^2
    r = characteristic_exponent(t0, "0.2", dps=40, method="cf")
    assert r.stable and not r.on_boundary and close(r.lam, nu, 39)
    # 1e-30 from the integer: still resolved at 40 digits (the distance to the
    # curve, ~1e-60, is far above the 10^-max_dps the working precision reaches)
    with mpmath.workdps(80):
        nu = 1 - mpmath.mpf("1e-30")
        t0 = theta0_of_exponent(nu, "0.2", dps=70)
    r = characteristic_exponent(t0, "0.2", dps=40, method="cf")
    assert not r.on_boundary and r.stable and close(r.lam, nu, 39)
    assert theta0_of_exponent(0.5, 0) == 0.25


@pytest.mark.parametrize("bad,match", [
    (dict(theta0="abc", theta1="0.2"), "theta0"),
    (dict(theta0="0.1", theta1=float("nan")), "theta1"),
    (dict(theta0=True, theta1="0.2"), "theta0"),
    (dict(theta0="1/0", theta1="0.2"), "theta0"),
    (dict(theta0="0.1", theta1="0.2", dps=0), "dps"),
    (dict(theta0="0.1", theta1="0.2", method="euler"), "method"),
])
def test_bad_input_is_a_one_line_value_error(bad, match):
    with pytest.raises(InputError, match=match) as info:
        characteristic_exponent(**bad)
    assert isinstance(info.value, ValueError) and "\n" not in str(info.value)


def test_inputs_are_read_exactly_not_through_float():
    # "1/3" read at 60 digits differs from float(1/3) after 17 digits
    a = characteristic_exponent("1/3", "1/5", dps=50, method="cf").lam
    b = characteristic_exponent(1 / 3, 0.2, dps=50, method="cf").lam
    with mpmath.workdps(60):
        assert abs(a - b) > mpmath.mpf(10) ** -20


def test_vectorised_trace_against_mp(rng):
    t0 = rng.uniform(-3, 12, 40)
    t1 = rng.uniform(-4, 4, 40)
    tr = trace_monodromy(t0, t1)
    for a, b, t in zip(t0, t1, tr):
        ref = characteristic_exponent(float(a), float(b), dps=25).trace
        ref = float(mpmath.re(ref))
        assert abs(t - ref) <= 1e-9 * max(1.0, abs(ref))
    assert trace_monodromy(np.zeros((2, 3)), 0.0).shape == (2, 3)


def test_huge_q_exponent_two_methods_and_the_vectorised_verdict():
    """theta1 = 1e4 (q = -1e4): Hill's determinant and the source's continued fractions
    are independent routes; they agree to 15 digits and with the double-precision map."""
    import mpmath
    import numpy as np
    from pendulab.analyses.floquet import characteristic_exponent, is_stable
    theta0 = "-0.01"
    hill = characteristic_exponent(theta0, 10000, dps=20, method="hill")
    cf = characteristic_exponent(theta0, 10000, dps=20, method="cf")
    assert abs(mpmath.mpc(hill.lam) - mpmath.mpc(cf.lam)) < mpmath.mpf("1e-15") * abs(mpmath.mpc(cf.lam))
    assert hill.stable == cf.stable == bool(is_stable(np.array(-0.01), np.array(1e4)))
