"""Characteristic values a_m(q), b_m(q), the exact stability limits and the
vectorised stable/unstable map, against published and independent references."""

import math

import mpmath
import numpy as np
import pytest
import scipy.special

from pendulab.analyses.floquet import (
    characteristic_exponent,
    is_stable,
    mathieu_a,
    mathieu_b,
    stability_limits,
    stability_map,
    trace_monodromy,
)
from pendulab.errors import AccuracyWarning, InputError

# Wolfram|Alpha, MathieuCharacteristicA[0, -1], 56 digits, as quoted in the GSL
# bug report "Different Value for MathieuCe in Mathematica and GSL" (2017).
A0_Q1 = "-0.45513860410741354823263318752888586691651984219666547103"

# Zhang & Jin, "Computation of Special Functions" (1996), example output of
# their characteristic-value program (CVA1) for q = 25, 9 decimals.
ZHANG_JIN_Q25 = {("a", 0): "-40.256779547", ("b", 1): "-40.256778985",
                 ("a", 1): "-21.314899691", ("b", 2): "-21.314860622",
                 ("a", 2): "-3.522164727", ("b", 3): "-3.520941527",
                 ("a", 3): "12.964079444", ("a", 5): "40.050190986",
                 ("b", 8): "69.057988351"}


def test_a0_at_q_plus_minus_one_to_50_digits():
    for q in ("1", "-1"):
        v = mathieu_a(0, q, dps=50)
        with mpmath.workdps(70):
            assert abs(v - mpmath.mpf(A0_Q1)) < mpmath.mpf(10) ** -50


@pytest.mark.parametrize("key,ref", sorted(ZHANG_JIN_Q25.items()))
def test_published_values_at_q25(key, ref):
    kind, m = key
    f = mathieu_a if kind == "a" else mathieu_b
    assert abs(f(m, 25) - float(ref)) <= 1.5e-9


def _eigsy_reference(family, q, n, dps):
    """Independent reference: all eigenvalues of the truncated DLMF 28.4 matrix
    by mpmath.eigsy (Jacobi/QL), at dps digits."""
    with mpmath.workdps(dps):
        q = mpmath.mpf(q)
        A = mpmath.zeros(n, n)
        for j in range(n):
            if family == "a_even":
                A[j, j] = (2 * j) ** 2
            elif family == "b_even":
                A[j, j] = (2 * j + 2) ** 2
            else:
                A[j, j] = (2 * j + 1) ** 2
        if family == "a_odd":
            A[0, 0] += q
        if family == "b_odd":
            A[0, 0] -= q
        for j in range(n - 1):
            off = q * (mpmath.sqrt(2) if (family == "a_even" and j == 0) else 1)
            A[j, j + 1] = A[j + 1, j] = off
        ev = mpmath.eigsy(A, eigvals_only=True)
        return sorted(ev[i] for i in range(n))


@pytest.mark.parametrize("q", ["5", "-37.5"])
def test_against_independent_eigensolver_at_50_digits(q):
    for family, kind, orders in (("a_even", "a", (0, 2, 4)), ("a_odd", "a", (1, 3)),
                                 ("b_odd", "b", (1, 3)), ("b_even", "b", (2, 4))):
        ref = _eigsy_reference(family, q, 28, 60)
        for i, m in enumerate(orders):
            f = mathieu_a if kind == "a" else mathieu_b
            v = f(m, q, dps=50)
            with mpmath.workdps(60):
                assert abs(v - ref[i]) <= mpmath.mpf(10) ** -48 * max(1, abs(ref[i]))


def _asymptotic(m, q):
    """DLMF 28.8.1, first five terms, s = 2m + 1, h = sqrt(q)."""
    h, s = mpmath.sqrt(q), 2 * m + 1
    return (-2 * h ** 2 + 2 * s * h - mpmath.mpf(s * s + 1) / 8 - (s ** 3 + 3 * s) / (2 ** 7 * h)
            - (5 * s ** 4 + 34 * s ** 2 + 9) / (2 ** 12 * h ** 2))


@pytest.mark.parametrize("m", [0, 1])
def test_huge_q_against_dlmf_28_8_1(m):
    # a_m(q) ~ b_{m+1}(q) ~ DLMF 28.8.1; the next term is ~1e-8 (m=0) at h = 100
    with mpmath.workdps(30):
        asy = _asymptotic(m, 10000)
        a = mathieu_a(m, 10000, dps=30)
        b = mathieu_b(m + 1, 10000, dps=30)
        tol = 1e-8 if m == 0 else 4e-7
        assert abs(a - asy) < tol and abs(b - asy) < tol
        # a_m < b_{m+1} for q > 0 with an exponentially small gap (DLMF 28.8.2)
    assert float(mathieu_a(0, -10000)) == pytest.approx(-19800.2503136784, rel=1e-14)


def test_q_sign_symmetry_dlmf_28_2_26():
    for q in ("0.7", "12"):
        mq = "-" + q
        assert abs(mathieu_a(2, mq, dps=30) - mathieu_a(2, q, dps=30)) < 1e-28
        assert abs(mathieu_a(1, mq, dps=30) - mathieu_b(1, q, dps=30)) < 1e-28
        assert abs(mathieu_b(3, mq, dps=30) - mathieu_a(3, q, dps=30)) < 1e-27
        assert abs(mathieu_b(2, mq, dps=30) - mathieu_b(2, q, dps=30)) < 1e-28


def test_small_q_series_dlmf_28_6():
    with mpmath.workdps(40):
        q = mpmath.mpf(1) / 100
        a0 = -q ** 2 / 2 + 7 * q ** 4 / 128 - 29 * q ** 6 / 2304 + 68687 * q ** 8 / 18874368
        assert abs(mathieu_a(0, "0.01", dps=35) - a0) < mpmath.mpf(10) ** -19
        # DLMF 28.6.15: a_1 - b_1 = 2q (1 + O(q^2))
        d = mathieu_a(1, "0.01", dps=35) - mathieu_b(1, "0.01", dps=35)
        assert abs(d / (2 * q) - 1) < 1e-4


def test_zero_q_and_bad_orders():
    assert mathieu_a(3, 0) == 9.0 and mathieu_b(2, 0, dps=20) == 4
    with pytest.raises(InputError, match="order"):
        mathieu_b(0, 1.0)
    with pytest.raises(InputError, match="order"):
        mathieu_a(-1, 1.0)
    with pytest.raises(InputError, match="q"):
        mathieu_a(0, "x")


def test_scipy_agrees_where_it_is_right_and_ours_is_right_where_it_is_not():
    # a_0 and b_1 (the inverted pendulum's edges): SciPy 1.17 agrees to 1e-13
    for q in (0.1, 1.0, 10.0, 100.0, 1000.0, 10000.0):
        assert scipy.special.mathieu_a(0, q) == pytest.approx(mathieu_a(0, q), rel=1e-13)
        assert scipy.special.mathieu_b(1, q) == pytest.approx(mathieu_b(1, q), rel=1e-13)
    # a_2(3162.28): ours follows DLMF 28.8.1 (s = 5) to 1e-6 whatever SciPy returns
    q = 3162.2776601683795
    with mpmath.workdps(30):
        assert abs(mathieu_a(2, q) - float(_asymptotic(2, q))) < 1e-5


def test_stability_limits_are_on_the_curves():
    lo, up = stability_limits("0.1", 1, dps=30)
    for al in (lo, up):
        with mpmath.workdps(40):
            th1 = 2 * al
        # 30-digit limits are ~1e-31 off the curves: lam within ~1e-15 of the edge
        r = characteristic_exponent("-0.04", th1, dps=28)
        assert not r.on_boundary and abs(r.lam - r.band_edge) < 1e-13
    # inside: stable; outside: unstable
    mid = (lo + up) / 2
    assert characteristic_exponent("-0.04", 2 * mid, dps=20).stable
    assert not characteristic_exponent("-0.04", 2 * up * 1.01, dps=20).stable
    assert not characteristic_exponent("-0.04", 2 * lo * 0.99, dps=20).stable


def test_stability_limits_scale_with_inertia_and_match_eq12_for_small_ratio():
    lo1, up1 = stability_limits(0.05, 1)
    lo2, up2 = stability_limits(0.05, "4/3")
    assert lo2 == pytest.approx(4 / 3 * lo1, rel=1e-14) and up2 == pytest.approx(4 / 3 * up1, rel=1e-14)
    # 000 eq. 12 (small-parameter result) approaches the exact limits as ratio -> 0
    r = 0.01
    lo, up = stability_limits(r, 1)
    assert lo == pytest.approx(math.sqrt(2) * r, rel=1e-3)
    assert up == pytest.approx(math.sqrt(2) * math.sqrt(1 + math.pi ** 2 * r ** 2) / math.pi, rel=0.05)
    assert stability_limits(0, 1)[0] == 0.0
    with pytest.raises(InputError, match="ratio"):
        stability_limits(-0.1)
    with pytest.raises(InputError, match="inertia_ratio"):
        stability_limits(0.1, 0)


def test_is_stable_against_scipy_monodromy(rng):
    """Point-wise check of the vectorised verdict against the monodromy matrix
    integrated with scipy's solve_ivp (an independent method)."""
    from scipy.integrate import solve_ivp

    t0 = rng.uniform(-3, 8, 60)
    t1 = rng.uniform(-3, 3, 60)
    verdict = is_stable(t0, t1)
    checked = 0
    for a, b, v in zip(t0, t1, verdict):
        def rhs(t, y):
            p = a + 2 * b * np.cos(2 * t)
            return [y[1], -p * y[0], y[3], -p * y[2]]
        sol = solve_ivp(rhs, (0, np.pi), [1, 0, 0, 1], rtol=1e-11, atol=1e-13, method="DOP853")
        tr = sol.y[0, -1] + sol.y[3, -1]
        if abs(abs(tr) - 2) < 1e-6:
            continue  # too close to a curve for this reference
        assert v == (abs(tr) < 2)
        checked += 1
    assert checked > 50


def test_is_stable_broadcasts_and_matches_trace():
    t0 = np.linspace(-2, 10, 301)[:, None]
    t1 = np.linspace(0, 4, 7)[None, :]
    v = is_stable(t0, t1)
    assert v.shape == (301, 7)
    tr = trace_monodromy(np.broadcast_to(t0, v.shape), np.broadcast_to(t1, v.shape))
    clear = np.abs(np.abs(tr) - 2) > 1e-6
    assert np.array_equal(v[clear], (np.abs(tr) < 2)[clear])


def test_is_stable_warns_next_to_a_curve_and_rejects_nan():
    edge = mathieu_a(0, 0.5)
    with pytest.warns(AccuracyWarning, match="resolution"):
        is_stable(np.array([edge]), -0.5)
    with pytest.raises(InputError, match="finite"):
        is_stable(np.array([np.nan]), 0.2)


def test_stability_map_orientation():
    al = np.array([0.05, 0.3, 0.9])
    ratio = np.array([0.1, 0.5])
    m = stability_map(al, ratio)
    assert m.shape == (2, 3)
    lo, up = stability_limits(0.1, 1)
    assert m[0].tolist() == [lo < x < up for x in al]
