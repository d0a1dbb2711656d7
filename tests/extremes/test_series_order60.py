"""The series at order 60: coefficients exact, sums right against the continued fraction.

References: the residual of the truncated series in Mathieu's equation (000 eq. 7),
formed in this test in the basis cos((nu + 2k) tau) from 2 cos 2tau cos x = cos(x + 2tau)
+ cos(x - 2tau) (000 eq. 26) with exact rationals: it must vanish through theta1^60 and
not at theta1^61; alpha_n(0) = (-1)^n [q^n] a_0(q) (at nu = 0 the series is a_0's,
DLMF 28.6.1 with q = -theta1), from the integer-order engine (Newton on the Hill
determinant, no code shared); theta0 and a_0 at 50 digits from the continued-fraction
routes (theta0_of_exponent, mathieu_a).
"""

from fractions import Fraction

import mpmath
import pytest

from pendulab.analyses import series as se
from pendulab.analyses.floquet import mathieu_a, theta0_of_exponent

from ._series_check import residual

ORDER = 60


@pytest.fixture(scope="module")
def s60():
    return se.mathieu_series(ORDER)


def test_the_residual_vanishes_exactly_through_order_60(s60):
    nu = Fraction(1, 3)
    R = residual(s60, nu, ORDER)
    assert len(R) > 1500 and all(v == 0 for v in R.values())
    # and the next order is really there: theta1^61 of the order-60 truncation does not
    # vanish (its cos((nu + 2k) tau) parts are those of C[60] shifted by 2 cos 2tau)
    last = s60.c_raw[ORDER]
    shifted = {}
    for k, v in last:
        for kk in (k - 1, k + 1):
            shifted[kk] = shifted.get(kk, 0) + v.evaluate(nu)
    assert any(v != 0 for v in shifted.values())


def test_alpha_at_nu_zero_is_a0_to_order_60(s60):
    a0 = se.characteristic_series("a0", ORDER).coefficients
    for n in range(1, ORDER + 1):
        assert s60.alpha_raw[n].evaluate(Fraction(0)) == (-1) ** n * a0[n], n
    assert a0[60] != 0


def test_order_60_against_the_continued_fraction_at_50_digits():
    # theta1 = 0.3 at nu = 0.5 is well inside the radius (~0.95): the omitted terms are
    # ~ (0.3/0.95)^61 ~ 1e-31
    v, est = se.theta0_of_nu("0.5", "0.3", ORDER, dps=50)
    ref = theta0_of_exponent("0.5", "0.3", dps=50)
    with mpmath.workdps(60):
        err = abs(v - ref)
        assert err <= 2 * est and err < mpmath.mpf(10) ** -28
    # the order-20 sum is worse by far: the test can tell orders apart
    v20, _ = se.theta0_of_nu("0.5", "0.3", 20, dps=50)
    with mpmath.workdps(60):
        assert abs(v20 - ref) > 1e6 * err


def test_a0_series_order_60_against_the_continued_fraction():
    v, est = se.characteristic_series("a0", ORDER).evaluate("0.5", dps=50)
    ref = mathieu_a(0, "0.5", dps=50, method="mpmath")
    with mpmath.workdps(60):
        err = abs(v - ref)
        assert err <= 2 * est and err < mpmath.mpf(10) ** -27       # (0.5/1.4688)^61 ~ 1e-29
