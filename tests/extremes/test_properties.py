"""Properties at random points (hypothesis, derandomized: the same examples on every run).

* the series residual: the truncated series of order N satisfies Mathieu's equation
  (000 eq. 7) through theta1^N exactly, at any rational non-integer nu;
* the exponent's methods agree (ball arithmetic, Hill's determinant, continued fractions:
  three routes that share no code but the band count);
* theta0_of_exponent inverts characteristic_exponent;
* zero interlacing j_nu,k < j_nu+1,k < j_nu,k+1 (DLMF 10.21.3), read from the printed
  digits (not from pendulab's own check), and the certificate refusing swapped lists.
"""

from fractions import Fraction

import mpmath
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pendulab.analyses import series as se
from pendulab.analyses.bessel_zeros import CertificationError, bessel_zeros, check_interlacing
from pendulab.analyses.floquet import characteristic_exponent, theta0_of_exponent

from ._series_check import residual

FAST = settings(max_examples=12, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])

non_integer_nu = st.builds(Fraction, st.integers(-40, 40), st.integers(2, 7)).filter(
    lambda f: f.denominator != 1)


@FAST
@given(nu=non_integer_nu, order=st.integers(2, 8))
def test_series_residual_vanishes_through_its_order(nu, order):
    R = residual(se.mathieu_series(order), nu, order)
    assert all(v == 0 for v in R.values())


@FAST
@given(theta0=st.floats(-3, 20), theta1=st.floats(-10, 10))
def test_exponent_methods_agree(theta0, theta1):
    res = [characteristic_exponent(theta0, theta1, dps=15, method=m) for m in ("arb", "hill", "cf")]
    assert len({(r.stable, r.on_boundary) for r in res}) == 1
    with mpmath.workdps(30):
        lams = [r.lam for r in res]
        scale = max(1, abs(lams[0]))
        assert max(abs(x - lams[0]) for x in lams) <= 1e-13 * scale


@FAST
@given(nu=st.floats(0.001, 3.999).filter(lambda x: abs(x - round(x)) > 1e-3),
       theta1=st.floats(-5, 5))
def test_theta0_of_exponent_inverts_the_exponent(nu, theta1):
    t0 = theta0_of_exponent(nu, theta1, dps=25)
    r = characteristic_exponent(t0, theta1, dps=25)
    with mpmath.workdps(40):
        assert r.stable and abs(r.lam - mpmath.mpf(nu)) < mpmath.mpf(10) ** -18


@FAST
@given(nu=st.builds(Fraction, st.integers(0, 200), st.sampled_from([1, 2, 4])),
       count=st.integers(3, 12))
def test_zeros_of_consecutive_orders_interlace(nu, count):
    lo, hi = bessel_zeros(nu, count, 20), bessel_zeros(nu + 1, count, 20)
    with mpmath.workdps(30):
        a = [mpmath.mpf(s) for s in lo.strings]
        b = [mpmath.mpf(s) for s in hi.strings]
        for k in range(count):
            assert a[k] < b[k]
            if k + 1 < count:
                assert b[k] < a[k + 1]
    assert check_interlacing(lo.balls, hi.balls) == 2 * count
    with pytest.raises(CertificationError, match="interlacing fails"):
        check_interlacing(hi.balls, lo.balls)
