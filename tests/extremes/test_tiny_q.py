"""a_0(q) at tiny q keeps its significant digits (the value is about -q^2/2).

Reference: DLMF 28.6.1, a_0(q) = -q^2/2 + 7q^4/128 - 29q^6/2304 + O(q^8), exact to far
beyond 30 digits for |q| <= 1e-10.  Before, the continued-fraction route (and with it
the double-precision call and the default route where the balls cannot answer) found
a_0 to 10^-dps absolute only: a_0(1e-40) came back as 0 (method "mpmath") or -1.07e-50
(double), a_0(1e-300) as 0 at dps = 30.
"""

import mpmath
import pytest

from pendulab.analyses.floquet import mathieu_a
from pendulab.errors import PrecisionError


def _dlmf(q):
    q = mpmath.mpf(q)
    return -q ** 2 / 2 + 7 * q ** 4 / 128 - 29 * q ** 6 / 2304


@pytest.mark.parametrize("q", ["1e-10", "1e-40", "1e-300", "-1e-300", "1e-2000"])
@pytest.mark.parametrize("method", [None, "mpmath"])
def test_a0_at_tiny_q_to_30_significant_digits(q, method):
    v = mathieu_a(0, q, dps=30, method=method)
    with mpmath.workdps(50):
        assert abs(v / _dlmf(q) - 1) < mpmath.mpf(10) ** -29


@pytest.mark.parametrize("q", [1e-10, 1e-40, 1e-150])
def test_a0_at_tiny_q_in_double_precision(q):
    with mpmath.workdps(50):
        ref = _dlmf(q)
    assert mathieu_a(0, q) == pytest.approx(float(ref), rel=4e-16)


def test_the_ball_route_asked_for_says_it_cannot():
    with pytest.raises(PrecisionError, match=r"^mathieu_a\(0, 1e-300\) not resolved to 30 digits"):
        mathieu_a(0, "1e-300", dps=30, method="arb")
