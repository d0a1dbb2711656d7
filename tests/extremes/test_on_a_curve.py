"""theta0 exactly on a characteristic curve: theta0 = 4 and 16 at theta1 = 0 (a_2(0) =
b_2(0) = 4, a_4(0) = b_4(0) = 16, DLMF 28.2(v)), and a hair off it.

References: at theta1 = 0 Mathieu's equation is w'' + theta0 w = 0, so lam = sqrt(theta0)
exactly, both solutions (cos 2 tau, sin 2 tau; cos 4 tau, sin 4 tau) are bounded and
the multipliers are exp(+-2 pi i) = 1 (every method must give this, or refuse).
Off the curve, theta0 = 4 and 0 < q << 1: DLMF 28.6 gives a_2 = 4 + 5q^2/12 + O(q^4),
b_2 = 4 - q^2/12 + O(q^4), so theta0 = 4 lies in gap 2, at the centre c = 4 + q^2/6
minus q^2/6, with half width w = q^2/4.  Near a simple gap lam = 2 + eps with
(theta0 - c)^2 - w^2 = (2 * 2 eps)^2 (d theta0/d lam = 2 lam = 4 at the edge), i.e.
eps = i mu, mu = sqrt(w^2 - (theta0 - c)^2)/4 = sqrt(5) q^2/48 (1 + O(q^2)).
"""

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from pendulab.analyses import series as se
from pendulab.analyses.floquet import (
    characteristic_exponent,
    exponent,
    is_stable,
    mathieu_a,
    mathieu_b,
    theta0_of_exponent,
    trace_monodromy,
)
from pendulab.analyses.floquet._exponent import _core
from pendulab.analyses.hill_general import hill_trace
from pendulab.errors import PrecisionError, SeriesDomainError

CURVES = [(4, 2), (16, 4)]          # (theta0, k): theta0 = k^2


@pytest.mark.parametrize("theta0,k", CURVES)
@pytest.mark.parametrize("method,dps", [(m, d) for m in ("hill", "cf", "monodromy", None)
                                         for d in (None, 30)] + [("arb", 30)])
def test_every_exponent_method_gives_the_curve(theta0, k, method, dps):
    r = characteristic_exponent(str(theta0), "0", dps=dps, method=method)
    assert r.lam == k and r.on_boundary and r.stable     # cos k tau, sin k tau are bounded
    assert all(m == 1 for m in r.multipliers)
    if method == "arb":
        assert r.certified_digits == 30


@pytest.mark.parametrize("theta0,k", CURVES)
@pytest.mark.parametrize("method", ["hill", "cf", "monodromy"])
def test_the_engines_themselves_find_u_zero_on_the_curve(theta0, k, method):
    # characteristic_exponent answers theta1 = 0 before any engine runs; here each
    # engine is run on the curve: band count 2k + 1 (a_0, b_1, a_1, ..., a_k = b_k = theta0
    # counted as below or at), edge e = k, u = (lam - k)^2 = 0 to the working precision
    count, e, u, _ = _core(method, Fraction(theta0), Fraction(0), 30)
    assert e == k and count in (2 * k - 1, 2 * k + 1)
    assert abs(u) < mpmath.mpf(10) ** -25


@pytest.mark.parametrize("theta0,k", CURVES)
def test_vectorised_and_general_hill_routes_on_the_curve(theta0, k):
    assert exponent(float(theta0), 0.0) == k
    assert bool(is_stable(float(theta0), 0.0))
    assert trace_monodromy(float(theta0), 0.0) == pytest.approx(2.0, abs=1e-12)
    assert hill_trace({0: (float(theta0), 0.0)}, math.pi).trace == pytest.approx(2.0, abs=1e-12)
    got = exponent(np.array([theta0, theta0, 0.5]), np.array([0.0, 0.0, 0.0]))
    assert list(got) == [k, k, math.sqrt(0.5)]


@pytest.mark.parametrize("theta0,k", CURVES)
def test_inverse_and_characteristic_values_give_the_curve(theta0, k):
    assert theta0_of_exponent(k, 0.0) == theta0
    assert theta0_of_exponent(k, "0", dps=30) == theta0
    assert list(theta0_of_exponent(np.array([float(k)]), np.array([0.0]))) == [theta0]
    for f in (mathieu_a, mathieu_b):
        assert f(k, 0) == theta0
        assert f(k, "0", dps=30) == theta0 and f(k, "0", dps=30, method="mpmath") == theta0
    for kind in (f"a{k}", f"b{k}"):
        v, est = se.characteristic_series(kind, 12).evaluate(0.0)
        assert v == theta0 and est == 0


@pytest.mark.parametrize("theta0,k", CURVES)
@pytest.mark.parametrize("dps", [None, 20])
def test_the_nu_series_refuses_the_curve_in_one_line(theta0, k, dps):
    for call, args in ((se.theta0_of_nu, ()), (se.theta_c, (0.3,)), (se.theta_s, (0.3,))):
        with pytest.raises(SeriesDomainError, match=rf"^nu = {k}(\.0)? is within 1e-06 of the "
                                                    rf"integer {k}: the series .* is singular there"):
            call(*args, k, 0, 6, dps=dps)


def _mu(q):
    with mpmath.workdps(40):
        return mpmath.sqrt(5) * mpmath.mpf(q) ** 2 / 48


@pytest.mark.parametrize("q", ["1e-30", "1e-3"])
@pytest.mark.parametrize("method", ["arb", "cf"])
def test_a_hair_off_the_curve_is_in_gap_2(q, method):
    r = characteristic_exponent("4", q, dps=20, method=method)
    assert not r.stable and not r.on_boundary
    with mpmath.workdps(40):
        assert mpmath.re(r.lam) == 2
        assert abs(mpmath.im(r.lam) / _mu(q) - 1) < 10 * mpmath.mpf(q) ** 2 + mpmath.mpf(10) ** -18


def test_hill_needs_the_digits_of_cosh_pi_mu_minus_one_or_says_so():
    # q = 1e-30: cos(pi lam) - 1 ~ (pi mu)^2/2 ~ 1e-122, so u = -mu^2 needs ~145 digits: the
    # default ceiling (4 dps + 60 + 4 (-log10 theta1) + 5 = 265) allows them; a ceiling below
    # is refused in one line that names the remedy
    r = characteristic_exponent("4", "1e-30", dps=20, method="hill")
    with mpmath.workdps(40):
        assert not r.stable and abs(mpmath.im(r.lam) / _mu("1e-30") - 1) < mpmath.mpf(10) ** -18
    with pytest.raises(PrecisionError, match=r"cannot resolve the digits of the exponent at "
                                             r"theta0=4, theta1=1e-30 with method 'hill'.*raise max_dps$"):
        characteristic_exponent("4", "1e-30", dps=20, method="hill", max_dps=140)


@pytest.mark.parametrize("method", ["arb", "hill", "cf"])
def test_far_closer_to_the_curve_is_still_decided(method):
    # theta1 = 1e-100: mu = 4.7e-202, u = -mu^2 = -2e-403; the default ceiling
    # (4 dps + 60 + 4 * 100 + 5 = 545) decides it
    r = characteristic_exponent("4", "1e-100", dps=20, method=method)
    with mpmath.workdps(40):
        assert not r.stable and not r.on_boundary
        assert abs(mpmath.im(r.lam) / _mu("1e-100") - 1) < mpmath.mpf(10) ** -18


@pytest.mark.parametrize("method", ["hill", "cf"])
def test_a_hair_off_the_curve_in_double_precision(method):
    r = characteristic_exponent(4.0, 1e-30, method=method)
    assert not r.stable and not r.on_boundary and r.lam.real == 2
    assert r.lam.imag == pytest.approx(float(_mu("1e-30")), rel=1e-14)


def test_monodromy_a_hair_off_the_curve():
    r = characteristic_exponent("4", "1e-3", dps=12, method="monodromy")
    with mpmath.workdps(40):
        assert not r.stable and abs(mpmath.im(r.lam) / _mu("1e-3") - 1) < 1e-5
