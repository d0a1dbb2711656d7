"""theta1 (q) at and beyond the radius of convergence: the series refuse, the exact
methods stay right.

References: the radii of DLMF Table 28.6.1 (Meixner et al.; a_0: 1.4687686138,
b_1: 3.7699574940, b_2: 6.9289547588), which the computed radii pendulab uses
(pendulab.analyses.mathieu_radii, 15 digits) must round to; SciPy 1.17.1's mathieu_a / mathieu_b
(Zhang & Jin's Fortran, an implementation independent of pendulab's; right to
~1e-14 for a_0, b_1 up to q = 1e4, benchmarks/scipy_mathieu_accuracy.py) and the
project's two independent routes for a_m (ball arithmetic "arb"; continued
fraction "mpmath").  For non-integer nu: the forward exponent (Hill's
determinant) of the inverse's theta0 gives nu back.
"""

import warnings

import mpmath
import pytest
import scipy.special as sc

from pendulab.analyses import series as se
from pendulab.analyses.mathieu_radii import BRANCH_POINTS
from pendulab.analyses.floquet import characteristic_exponent, mathieu_a, mathieu_b, theta0_of_exponent
from pendulab.errors import AccuracyWarning, SeriesDomainError

DLMF = {"a0": "1.4687686138", "b1": "3.7699574940", "b2": "6.9289547588"}
RADII = {kind: BRANCH_POINTS[kind][0] for kind in DLMF}      # the decimals pendulab uses


def test_the_computed_radii_round_to_dlmf_table_28_6_1():
    for kind, text in DLMF.items():
        assert float(RADII[kind]) == pytest.approx(float(text), abs=5.1e-11)


@pytest.mark.parametrize("kind", sorted(RADII))
@pytest.mark.parametrize("how", ["double", "text", "double-dps", "beyond", "negative"])
def test_integer_series_refuse_at_and_beyond_the_table_radius(kind, how):
    s = se.characteristic_series(kind, 30)
    r = RADII[kind]
    q, dps = {"double": (float(r), None), "text": (r, 30), "double-dps": (float(r), 30),
              "beyond": (2 * float(r), None), "negative": ("-" + r, 30)}[how]
    with pytest.raises(SeriesDomainError, match=rf"^{kind}: \|q\| = .* is beyond the radius of "
                                                rf"convergence {float(r)!r} \(computed branch "
                                                r"point, DLMF Table 28.6.1\)$"):
        s.evaluate(q, dps=dps)


def test_just_inside_the_radius_the_sum_is_accepted_and_its_estimate_holds():
    s = se.characteristic_series("a0", 60)
    q = "1.46876861"                           # 4e-9 inside: the terms fall like (q/R)^n
    v, est = s.evaluate(q, dps=30)
    exact = mathieu_a(0, q, dps=30)
    with mpmath.workdps(40):
        assert abs(v - exact) <= 2 * est


@pytest.mark.parametrize("kind,m", [("a", 0), ("b", 1), ("b", 2)])
def test_exact_methods_right_at_and_beyond_the_radius(kind, m):
    f = mathieu_a if kind == "a" else mathieu_b
    ref = sc.mathieu_a if kind == "a" else sc.mathieu_b
    r = float(RADII[f"{kind}{m}"])
    for q in (r, 2 * r, 10 * r):
        arb_v = f(m, q, dps=30)
        mp_v = f(m, q, dps=30, method="mpmath")
        with mpmath.workdps(40):
            assert abs(arb_v - mp_v) <= mpmath.mpf(10) ** -29 * max(1, abs(arb_v))
        assert float(arb_v) == pytest.approx(ref(m, q), rel=1e-13, abs=1e-13)


def test_warned_sum_beyond_the_radius_carries_an_estimate_that_covers_its_error():
    s = se.characteristic_series("a0", 20)
    with pytest.warns(AccuracyWarning, match="beyond the radius of convergence"):
        v, est = s.evaluate(2.0, on_domain="warn")
    assert abs(v - float(mathieu_a(0, 2.0, dps=20))) <= est


@pytest.mark.parametrize("call", ["theta0_of_nu", "theta_c", "theta_s"])
@pytest.mark.parametrize("dps", [None, 30])
def test_nu_series_refuse_beyond_the_radius(call, dps):
    # at nu = 0.5 the radius in theta1 is about 0.95 (docs/series.md, from the coefficients
    # to order 200): theta1 = 1.5 is beyond it
    args = {"theta0_of_nu": (), "theta_c": (0.3,), "theta_s": (0.3,)}[call]
    with pytest.raises(SeriesDomainError, match=rf"^{call}: theta1 = 1.5 is beyond the radius of "
                                                r"convergence at nu = 0.5: the terms of the series grow"):
        getattr(se, call)(*args, "0.5" if dps else 0.5, "1.5" if dps else 1.5, 20, dps=dps)


def test_exact_inverse_right_beyond_the_nu_series_radius():
    t0 = theta0_of_exponent("0.5", "1.5", dps=30)
    r = characteristic_exponent(t0, "1.5", dps=25, method="hill")
    with mpmath.workdps(40):
        assert r.stable and abs(r.lam - mpmath.mpf("0.5")) < mpmath.mpf(10) ** -24
    with warnings.catch_warnings():                  # the warned sum really is off
        warnings.simplefilter("ignore", AccuracyWarning)
        v, _ = se.theta0_of_nu(0.5, 1.5, 20, on_domain="warn")
    assert abs(v - float(t0)) > 1e-3
