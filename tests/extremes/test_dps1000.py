"""1000 digits: Bessel zeros and identities, characteristic values and exponents.

References: mpmath.besseljzero at 1020 digits (its own root finder, not pendulab's);
the identities' exact right-hand sides (DLMF 10.5.1 and the cross product, 002); for
a_0(q) the exact power series of the integer-order engine (DLMF 28.6.1, coefficients
from Newton's iteration on the Hill determinant) at q = 1e-5, where its terms beyond
q^200 are below 1e-1000, against the ball-arithmetic and continued-fraction routes;
for the exponent, the ball-arithmetic route against the continued fractions.
"""

import mpmath
import pytest

from pendulab.analyses import series as se
from pendulab.analyses.bessel_identities import check_identities
from pendulab.analyses.bessel_zeros import bessel_zeros
from pendulab.analyses.floquet import characteristic_exponent, mathieu_a, theta0_of_exponent

D = 1000


def _close(x, ref, digits):
    return abs(mpmath.mpf(x) - ref) <= mpmath.mpf(10) ** -digits * abs(ref)


@pytest.mark.parametrize("nu", [1, 2])
def test_bessel_zeros_at_1000_digits(nu):
    z = bessel_zeros(nu, 3, D)
    with mpmath.workdps(D + 20):
        for k, s in enumerate(z.strings, start=1):
            assert len(s.replace(".", "")) == D
            # the string is the correctly rounded value: within half a unit of its last digit
            assert _close(s, mpmath.besseljzero(nu, k), D - 1)


def test_identities_certified_at_1000_digits():
    rep = check_identities(2, D, [0.5, 30.0], engines=("arb",))
    assert rep.arb_certified and rep.worst[0] < mpmath.mpf(10) ** -D


def test_a0_at_1000_digits_three_ways():
    q = "1e-5"
    v, est = se.characteristic_series("a0", 200).evaluate(q, dps=D)
    arb_v = mathieu_a(0, q, dps=D)
    mp_v = mathieu_a(0, q, dps=D, method="mpmath")
    with mpmath.workdps(D + 20):
        assert est < mpmath.mpf(10) ** -(D + 5)
        assert _close(arb_v, v, D - 1) and _close(mp_v, v, D - 1)


def test_exponent_and_inverse_at_1000_digits():
    a = characteristic_exponent("1/3", "1/2", dps=D)
    c = characteristic_exponent("1/3", "1/2", dps=D, method="cf")
    assert a.certified_digits == D
    with mpmath.workdps(D + 20):
        assert _close(a.lam, c.lam, D - 1)
    t0 = theta0_of_exponent("0.25", "0.3", dps=D)
    r = characteristic_exponent(t0, "0.3", dps=D)
    with mpmath.workdps(D + 20):
        assert r.stable and _close(r.lam, mpmath.mpf("0.25"), D - 2)
