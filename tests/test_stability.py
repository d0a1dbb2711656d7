"""Limits of a/l by every method: numbers against the source's formulas and the exact curves."""

import math
import random

import pytest

from pendulab.analyses import stability as st
from pendulab.errors import InputError

ROD, POINT = 4 / 3, 1.0


def seeded_points(n=6, seed=1905):
    rng = random.Random(seed)
    return [(rng.uniform(0, 0.6), rng.choice([1.0, ROD, rng.uniform(1, 2)])) for _ in range(n)]


# -- closed forms against the source's printed formulas ---------------------------

@pytest.mark.parametrize("rho, r", seeded_points())
def test_eq12_numbers_are_the_sources_eq_12(rho, r):
    # 000 eq. 12 with omega = 1.
    lower = math.sqrt(2) * r * rho
    upper = math.sqrt(2) * r * math.sqrt(1 + math.pi**2 * rho**2) / math.pi
    got = st.limits(rho, r, "eq12")
    assert got == pytest.approx((lower, upper), rel=1e-13, abs=1e-15)


@pytest.mark.parametrize("rho, r", seeded_points())
def test_eq19_numbers(rho, r):
    # 000 eq. 19 as printed: sqrt(2) sqrt(I/(m l^2)) omega0/omega; corrected: sqrt(2) (I/(m l^2)) omega0/omega.
    assert st.limits(rho, r, "eq19") == pytest.approx((math.sqrt(2 * r) * rho, None), abs=1e-15)
    assert st.limits(rho, r, "eq19-corrected")[0] == pytest.approx(math.sqrt(2) * r * rho, abs=1e-15)
    assert st.limits(rho, r, "eq19-corrected")[1] is None


def test_point_mass_eq19_coincide():
    for rho in (0.05, 0.3):
        assert st.limits(rho, 1, "eq19") == st.limits(rho, 1, "eq19-corrected")


# -- the exact limits -----------------------------------------------------------------

@pytest.mark.parametrize("rho", [0.0, 0.02, 0.1, 0.3, 0.6])
@pytest.mark.parametrize("r", [POINT, ROD])
def test_exact_against_scipy_characteristic_values(rho, r, scipy_limits):
    # Independent reference: scipy.special.mathieu_a(0, q) / mathieu_b(1, q) roots
    # at q <= 3, where SciPy is reliable.
    exact = st.limits(rho, r, "exact")
    ref = scipy_limits(rho, r)
    assert exact[0] == pytest.approx(ref[0], rel=1e-10, abs=1e-14)
    assert exact[1] == pytest.approx(ref[1], rel=1e-10)


def test_exact_upper_at_zero_ratio_is_b1_root():
    # b_1(q) = 0 at q = 0.9080463...: mpmath root of DLMF 28.6.4 would be an
    # alternative; here scipy's mathieu_b at small q (reliable) is the reference.
    from scipy.optimize import brentq
    from scipy.special import mathieu_b
    q = brentq(lambda q: mathieu_b(1, q), 0.5, 1.5, xtol=1e-15)
    assert st.limits(0, 1, "exact")[1] == pytest.approx(q / 2, rel=1e-12)


@pytest.mark.parametrize("rho", [0.01, 0.05])
def test_eq19_verdict_numbers(rho):
    # Rod: the corrected bound matches the exact lower limit to O(rho^2); the
    # printed eq. 19 is too low by the factor sqrt(4/3).
    exact = st.limits(rho, ROD, "exact")[0]
    assert st.limits(rho, ROD, "eq19-corrected")[0] / exact == pytest.approx(1, abs=rho**2)
    assert exact / st.limits(rho, ROD, "eq19")[0] == pytest.approx(math.sqrt(4 / 3), abs=rho**2)


def test_eq12_is_close_to_exact_only_for_small_ratio():
    # eq. 12 is a small-parameter result: within 1 % at omega0/omega = 0.05 (lower)
    # and 0.02 (upper); off by more than 5 % (upper) at 0.6.
    lo, up = st.limits(0.05, ROD, "eq12")
    ex_lo, ex_up = st.limits(0.05, ROD, "exact")
    assert abs(lo / ex_lo - 1) < 0.01
    assert abs(up / ex_up - 1) < 0.02
    lo, up = st.limits(0.6, ROD, "eq12")
    ex_lo, ex_up = st.limits(0.6, ROD, "exact")
    assert abs(up / ex_up - 1) > 0.05


# -- the series methods (pendulab.analyses.series) ----------------------------------

def test_eq28_is_the_sources_eq_28():
    for rho, r in seeded_points(4):
        # 000 eq. 28: sqrt(2) r rho < a/l < sqrt(2) r (1/4 + rho^2).
        lower, upper = st.limits(rho, r, "eq28")
        assert lower == pytest.approx(math.sqrt(2) * r * rho, rel=1e-12)
        assert upper == pytest.approx(math.sqrt(2) * r * (0.25 + rho**2), rel=1e-12)


def test_series_lower_limit_approaches_exact():
    """The lower limit from the order-N series converges to the Floquet one.

    (The upper limit of the non-integer series cannot: the exact one lies at
    nu = 1, where the series is singular; see docs/series.md.)
    """
    rho = 0.1
    exact = st.limits(rho, ROD, "exact")
    errors = [abs(st.limits(rho, ROD, f"series:{n}")[0] - exact[0]) for n in (2, 4, 8, 12)]
    assert errors[0] > errors[1] > errors[2] > errors[3]
    assert errors[3] < 1e-9


@pytest.mark.parametrize("rho", [0.0, 0.1, 0.3])
def test_integer_series_limits_approach_exact_on_both_sides(rho, scipy_limits):
    """The a_0/b_1 series reach both exact limits (the non-integer one cannot reach the upper)."""
    ref = scipy_limits(rho, ROD)          # roots of SciPy's mathieu_a(0, q), mathieu_b(1, q)
    lo, up = st.limits(rho, ROD, "integer-series:40")
    assert lo == pytest.approx(ref[0], abs=1e-9) and up == pytest.approx(ref[1], rel=1e-9)
    coarse = st.limits(rho, ROD, "integer-series:4")
    assert abs(coarse[1] - ref[1]) > abs(up - ref[1])


def test_integer_series_limit_beyond_the_radius_is_none():
    # rho = 0.9: the lower limit has Q = 2 (a/l)/r near 2.5 > 1.4687686138 (a_0's radius, DLMF
    # Table 28.6.1), so that limit is omitted; the upper limit's Q stays inside b_1's radius 3.77
    ref = st.limits(0.9, 1, "exact")
    assert 2 * ref[0] > 1.4687686138 and 2 * ref[1] < 3.769957494
    lo, up = st.limits(0.9, 1, "integer-series:30")
    assert lo is None and up == pytest.approx(ref[1], rel=1e-4)    # Q = 3.31: slow, near the radius


# -- comparison --------------------------------------------------------------------

def test_comparison_table():
    table = st.comparison([0, 0.1, "1/5"], ROD, ["exact", "eq12", "eq19"])
    assert table["w0_over_w"] == [0.0, 0.1, 0.2]
    assert table["methods"] == ["exact", "eq12", "eq19"]
    assert table["limits"]["eq19"][1] == [pytest.approx(math.sqrt(8 / 3) * 0.1), None]
    assert table["limits"]["exact"][0][0] == 0.0


def test_comparison_reports_every_problem_at_once():
    with pytest.raises(InputError) as info:
        st.comparison([0.1, -1, "x"], 0.5, ["eq12", "bogus", "series"])
    message = str(info.value)
    for fragment in ("must be >= 0", "must be a number", "I/(m l^2) must be >= 1",
                     "unknown method 'bogus'", "needs series_order"):
        assert fragment in message
    assert "\n" not in message


# -- bad input -----------------------------------------------------------------------

@pytest.mark.parametrize("args, fragment", [
    ((-0.1, 1, "eq12"), "omega0/omega must be >= 0"),
    ((1e200, 1, "eq12"), "omega0/omega must be >= 0 and <= 1000"),
    ((0.1, 1e9, "eq12"), "I/\\(m l\\^2\\) must be <= 1000"),
    ((float("nan"), 1, "eq12"), "must be finite"),
    ((float("inf"), 1, "eq12"), "must be finite"),
    (("abc", 1, "eq12"), "must be a number"),
    ((True, 1, "eq12"), "must be a number"),
    ((0.1, 0.9, "eq12"), "must be >= 1"),
    ((0.1, None, "eq12"), "must be a real number"),
    ((0.1, 1, "eq13"), "unknown method 'eq13'"),
    ((0.1, 1, "series:x"), "series order must be an integer"),
    ((0.1, 1, "series:0"), "series order must be an integer"),
    # series:1 used to pass parse_method and fail later with another range
    ((0.1, 1, "series:1"), "between 2 and 40"),
    ((0.1, 1, "series:41"), "between 2 and 40"),
    ((0.1, 1, "integer-series:0"), "between 1 and 40"),
    ((0.1, 1, "integer-series:"), "series order must be an integer"),
    ((0.1, 1, 12), "method must be a string"),
])
def test_bad_input(args, fragment):
    with pytest.raises(InputError, match=fragment) as info:
        st.limits(*args)
    assert "\n" not in str(info.value)
