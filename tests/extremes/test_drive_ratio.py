"""omega0/omega -> 0 and large: the stability limits, the averaging and the scenes' maps.

References:
* omega0/omega -> 0, lower limit: a_0(q) = -q^2/2 + 7q^4/128 + O(q^6) (DLMF 28.6.1) with
  theta0 = -4 r^2 (000 eq. 5) gives q = 2 sqrt(2) r (1 + 7 r^2/16 + O(r^4)), and a/l =
  (I/(m l^2)) q/2 (000 eq. 6); the averaged bound (000 eq. 19, as derived for a
  physical pendulum) is sqrt(2) (I/(m l^2)) r, so exact/averaged - 1 = 7 r^2/16 + O(r^4).
* omega0/omega -> 0, upper limit: b_1(q*) = 0; q* from SciPy's mathieu_b (Zhang & Jin,
  independent of pendulab) by Brent's method, to ~1e-14.
* omega0/omega large: a_0(q) = b_1(q) = theta0 = -4 r^2 solved with DLMF 28.8.1 (eight
  terms, tests/extremes/_dlmf.py) for h = sqrt(q) by mpmath.findroot: the band
  (width ~e^{-4h}, DLMF 28.8.2) is far thinner than a double, so both limits are that q.
"""

import math

import mpmath
import numpy as np
import pytest
import scipy.optimize
import scipy.special

from pendulab.analyses import stability
from pendulab.analyses.floquet import stability_limits, stability_map
from pendulab.errors import InputError

from ._dlmf import large_q

BODIES = {"point": 1, "rod": mpmath.mpf(4) / 3}


def _q_star():
    return scipy.optimize.brentq(lambda q: scipy.special.mathieu_b(1, q), 0.5, 1.5, xtol=1e-15)


@pytest.mark.parametrize("body", sorted(BODIES))
def test_tiny_ratio_at_the_end_of_the_double_range(body):
    r_i = BODIES[body]
    lo, hi = stability_limits("1e-300", float(r_i) if body == "point" else "4/3")
    with mpmath.workdps(40):
        ref = mpmath.sqrt(2) * r_i * mpmath.mpf("1e-300")     # the O(r^2) term is 1e-600
        assert abs(lo / ref - 1) < 2e-16
    assert hi == pytest.approx(float(r_i) * _q_star() / 2, rel=1e-13)


def test_ratio_zero_is_the_free_rod_lower_limit_zero():
    lo, hi = stability_limits(0)
    assert lo == 0 and hi == pytest.approx(_q_star() / 2, rel=1e-13)


@pytest.mark.parametrize("ratio", ["0.1", "0.01", "0.001"])
def test_averaging_is_the_small_ratio_limit(ratio):
    # exact / averaged - 1 = 7 r^2/16 (1 + O(r^2)): the averaging's error is second order
    r = float(ratio)
    for body, r_i in (("point", 1.0), ("rod", 4 / 3)):
        exact, _ = stability_limits(ratio, "4/3" if body == "rod" else 1, dps=20)
        averaged, upper = stability.limits(r, r_i, "eq19-corrected")
        assert upper is None
        rel = float(exact) / averaged - 1
        assert rel == pytest.approx(7 * r * r / 16, rel=3 * r * r + 1e-6)


@pytest.mark.parametrize("ratio", ["100", "1000"])
def test_large_ratio_follows_dlmf_28_8_1(ratio):
    with mpmath.workdps(40):
        th0 = -4 * mpmath.mpf(ratio) ** 2
        h = mpmath.findroot(lambda h: large_q(0, h * h)[0] - th0, mpmath.sqrt(-th0 / 2))
        q = h * h
        _, err = large_q(0, q)
        tol = err / q                  # d a_0/dq ~ -2: relative error in q below err/(2q)
    lo, hi = stability_limits(ratio, dps=25)
    with mpmath.workdps(40):
        for x in (lo, hi):
            assert abs(x / (q / 2) - 1) < max(tol, mpmath.mpf(10) ** -24)  # 3e-19, 1e-24
    dlo, dhi = stability_limits(float(ratio))
    assert dlo == dhi == pytest.approx(float(q / 2), rel=1e-15)


def test_beyond_the_ratio_limit_one_line():
    with pytest.raises(InputError, match=r"^ratio = omega0/omega must be <= 1000 "):
        stability_limits(1000.5)


def test_maps_at_the_extreme_rows():
    # rows omega0/omega = 0, 1e-300 and 1e-8, the scenes' bodies.  At ratio 0 the first band
    # is 0 < a/l < r_i q*/2; at a/l = 1e-300 theta0 = 0 lies 2e-600 above a_0(2e-300) (DLMF
    # 28.6.1), stable (this cell was "on a_0" before the ceiling of the working precision
    # grew with -log10 theta1).  At ratio r > 0 the band starts at sqrt(2) r_i r.
    al = np.array([0.0, 1e-300, 2e-300, 1e-8, 0.25, 0.44, 0.46, 0.6, 0.62])
    for r_i, ratios in ((1.0, (0.0, 1e-300, 1e-8)), (4 / 3, (0.0, 1e-8))):
        m = stability_map(al, np.array(ratios), inertia_ratio=r_i)
        top = r_i * _q_star() / 2
        for row, ratio in zip(m, ratios):
            expected = [bool(math.sqrt(2) * r_i * ratio < a < top) for a in al]
            assert list(map(bool, row)) == expected, (r_i, ratio)
    assert math.isclose(_q_star(), 0.908046, rel_tol=1e-6)   # Kapitza's q* (point mass: 0.454)


def test_tiny_theta1_off_a_curve_is_decided():
    # theta0 = 0, theta1 = 2e-300: lam^2 = theta0 - a_0(q) = q^2/2 (DLMF 28.6.1), so
    # lam = sqrt(2) 1e-300, stable; every method, with the default ceiling of digits
    from pendulab.analyses.floquet import characteristic_exponent
    with mpmath.workdps(40):
        ref = mpmath.sqrt(2) * mpmath.mpf("1e-300")
    for method in ("arb", "hill", "cf"):
        r = characteristic_exponent("0", "2e-300", dps=20, method=method)
        with mpmath.workdps(40):
            assert r.stable and not r.on_boundary and abs(r.lam / ref - 1) < mpmath.mpf(10) ** -19
    d = characteristic_exponent(0.0, 2e-300)
    assert d.stable and d.lam == pytest.approx(float(ref), rel=1e-15)
