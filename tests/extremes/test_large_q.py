"""q = 1e4 in the Floquet code: the characteristic values, the exponentially thin first
band, and the exponent in the gaps.

References: DLMF 28.8.1 to eight terms and DLMF 28.8.2 with its first correction
(tests/extremes/_dlmf.py); a_0(-q) = a_0(q), b_1(-q) = a_1(q) (DLMF 28.2.26); for the
exponent, three independent methods (ball arithmetic, Hill's determinant and the
vectorised double route (trace by a continuant, ~1e-9 relative
here, docs/floquet.md)).  tests/test_floquet_values.py checks five terms at 30 digits;
this module goes to eight terms, the width of the band and the exponent.
"""

import mpmath
import pytest

from pendulab.analyses.floquet import characteristic_exponent, exponent, mathieu_a, mathieu_b
from pendulab.errors import InputError

from ._dlmf import band_width, large_q

Q = "1e4"


@pytest.mark.parametrize("kind,m,asym_m", [("a", 0, 0), ("b", 1, 0), ("a", 1, 1), ("b", 2, 1)])
@pytest.mark.parametrize("method", ["arb", "mpmath"])
def test_characteristic_values_follow_dlmf_28_8_1_to_eight_terms(kind, m, asym_m, method):
    f = mathieu_a if kind == "a" else mathieu_b
    v = f(m, Q, dps=30, method=method)
    with mpmath.workdps(40):
        ref, err = large_q(asym_m, Q)
        assert abs(v - ref) <= err                       # 4e-14 (m = 0), 2e-12 (m = 1)
    assert abs(f(m, 1e4) - float(ref)) <= float(err) + 4e-16 * abs(float(ref))   # double route


def test_negative_q_by_symmetry():
    with mpmath.workdps(40):
        assert abs(mathieu_a(0, "-1e4", dps=30) - mathieu_a(0, Q, dps=30)) < mpmath.mpf(10) ** -25
        assert abs(mathieu_b(1, "-1e4", dps=30) - mathieu_a(1, Q, dps=30)) < mpmath.mpf(10) ** -25


@pytest.mark.parametrize("m", [0, 1])
@pytest.mark.parametrize("method", ["arb", "mpmath"])
def test_the_band_is_as_thin_as_dlmf_28_8_2_says(m, method):
    # b_1 - a_0 = 4.88e-170, b_2 - a_1 = 2.42e-166: 200 digits resolve it to 30
    d = mathieu_b(m + 1, Q, dps=200, method=method) - mathieu_a(m, Q, dps=200, method=method)
    with mpmath.workdps(210):
        assert d > 0 and abs(d / band_width(m, Q) - 1) < 2e-4      # O(h^-2) = 1e-4 left


def test_at_30_digits_the_two_edges_are_one_number():
    # the band is below any reasonable precision: both are right, and equal to 30 digits
    a, b = mathieu_a(0, Q, dps=30), mathieu_b(1, Q, dps=30)
    with mpmath.workdps(40):
        assert abs(b - a) <= mpmath.mpf(10) ** -25


@pytest.mark.parametrize("theta0,edge", [("0", 54), ("5000", 69)])
def test_the_exponent_in_a_gap_by_three_methods(theta0, edge):
    # (the continued fractions agree too, but take 12 s a point at S = 2e4 and 20 digits)
    res = {m: characteristic_exponent(theta0, Q, dps=20, method=m) for m in ("arb", "hill")}
    with mpmath.workdps(30):
        for r in res.values():
            assert not r.stable and mpmath.re(r.lam) == edge
        mus = [mpmath.im(r.lam) for r in res.values()]
        assert max(mus) - min(mus) < mpmath.mpf(10) ** -17 * max(mus)
    v = exponent(float(theta0), 1e4)
    assert v.real == edge and abs(v.imag / float(mus[0]) - 1) < 1e-8


def test_below_a0_only_hill_is_in_range_and_the_others_say_so():
    # theta0 = -2e4 < a_0(1e4): lam = i mu; S = |theta0| + 2|theta1| = 4e4 is beyond arb's
    # and cf's size limits (3e4), within hill's (4e6)
    r = characteristic_exponent("-20000", Q, dps=20)
    assert r.method == "hill" and not r.stable and mpmath.re(r.lam) == 0
    d = characteristic_exponent(-20000.0, 1e4)
    v = exponent(-20000.0, 1e4)
    assert abs(d.lam.imag / float(mpmath.im(r.lam)) - 1) < 1e-13
    assert abs(v.imag / float(mpmath.im(r.lam)) - 1) < 1e-8
    for method in ("cf", "arb"):
        with pytest.raises(InputError, match=rf"too large for method '{method}'.*limit"):
            characteristic_exponent("-20000", Q, dps=20, method=method)
