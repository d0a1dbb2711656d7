"""Tests written from the survivors of a mutation run (mutmut) of the Bessel modules.

Each test closes a gap a surviving mutant showed: a comparison made non-strict at the end
of an open window, a check skipped for the last pair of a list, a margin of the shortening
string summed instead of subtracted, the verdict on a margin just above zero.

References, each independent of the code under test:
* Abramowitz & Stegun, Table 9.5 (zeros j_n,s of J_1, J_2 to 10 decimals), for durations
  and margins worked out here by hand;
* 002_19b336b29bb1f03b.txt, last page: the first zeros of J1 and J2 as printed;
* mpmath (besselj, besseljzero) at the digits stated.
"""

import math
from fractions import Fraction

import mpmath
import pytest
from flint import arb

import pendulab.analyses.bessel_identities as bi
import pendulab.analyses.bessel_periods as bp
import pendulab.analyses.bessel_zeros as bz
from pendulab.errors import InputError

# A&S Table 9.5 (Abramowitz & Stegun 1964, p. 409), 10 decimals.
J11, J12, J13 = Fraction("3.8317059702"), Fraction("7.0155866698"), Fraction("10.1734681351")
J21, J22, J23 = Fraction("5.1356223018"), Fraction("8.4172441404"), Fraction("11.6198411721")
# 002, last page, as printed (6 significant digits, trailing zeros dropped by the source).
SOURCE_J1 = ["3.83171", "7.01559", "10.1735", "13.3237", "16.4706"]
SOURCE_J2 = ["5.13562", "8.41724", "11.6198", "14.796", "17.9598"]


# -- the index: the ends of the first bracket are not zeros -----------------------------------

def test_check_index_refuses_a_point_at_either_end_of_the_first_bracket():
    """first_bracket's (a, b) is open: J_1(a) > 0 and J_1(b) < 0 (mpmath, 30 digits), so
    neither end is a zero, and an exact ball at either end is refused as zero number 1
    (a non-strict comparison would take it).  The true first zero passes."""
    a, b, _ = bz.first_bracket(Fraction(1))
    with mpmath.workdps(30):
        for end, sign in ((a, 1), (b, -1)):
            value = mpmath.besselj(1, mpmath.mpf(end.mid().str(40, radius=False)))
            assert sign * value > mpmath.mpf(10) ** -3, (end, value)
    for end in (a, b):
        with pytest.raises(bz.CertificationError, match="ball 1 .* is not zero number 1"):
            bz.check_index(1, [arb(end.mid())])
    assert bz.check_index(1, bz.bessel_zeros(1, 1, 20).balls)


def test_check_index_refuses_a_point_at_either_end_of_a_sturm_window():
    """The window after j_1,1 is the open interval (sup ball, inf ball + 2 pi): exact points
    at its two ends (3.83 and 10.11) are more than 3 away from j_1,2 = 7.0156
    (mpmath.besseljzero), so they are not zero number 2 and are refused."""
    first = bz.bessel_zeros(1, 1, 20).balls[0]
    lo, hi, _ = bz.next_window(Fraction(1), first, max(64, first.mid().bits() + 16))
    with mpmath.workdps(30):
        j2 = mpmath.besseljzero(1, 2)
        for end in (lo, hi):
            assert abs(mpmath.mpf(end.mid().str(40, radius=False)) - j2) > 3
    for end in (lo, hi):
        with pytest.raises(bz.CertificationError, match="ball 2 .* is not zero number 2"):
            bz.check_index(1, [first, arb(end.mid())])


# -- interlacing: strict, and checked up to the last pair ---------------------------------------

def test_interlacing_is_strict_for_exact_points():
    """DLMF 10.21.3 is strict: a zero of J_nu+1 equal to a zero of J_nu (exact points,
    radius 0) is refused on either side; with balls of non-zero radius a non-strict test
    would have refused too, so the points are exact."""
    j1 = [b.mid() for b in bz.bessel_zeros(1, 2, 25).balls]
    with pytest.raises(bz.CertificationError, match=r"j_nu,1 < j_nu\+1,1 not proved"):
        bz.check_interlacing([j1[0]], [j1[0]])
    with pytest.raises(bz.CertificationError, match=r"j_nu\+1,1 < j_nu,2 not proved"):
        bz.check_interlacing(j1, [j1[1]])


def test_interlacing_checks_the_last_pair_and_allows_a_longer_upper_list():
    """In place of j_2,2 the list holds j_2,3 = 11.62 > j_1,3 = 10.17 (A&S 9.5): only the
    last comparison j_nu+1,2 < j_nu,3 can see it.  A list of J_2's zeros one longer than
    J_1's has nothing to compare its last zero with, and is accepted."""
    j1 = bz.bessel_zeros(1, 3, 25).balls
    j2 = bz.bessel_zeros(2, 4, 25).balls
    assert float(j2[2].mid()) > float(J13) > float(J12)
    with pytest.raises(bz.CertificationError, match=r"j_nu\+1,2 < j_nu,3 not proved"):
        bz.check_interlacing(j1, [j2[0], j2[2]])
    bz.check_interlacing(j1, j2)  # no error, no IndexError


# -- quarter periods: the zeros reported, the shortening margins, the verdict -----------------

def test_quarter_periods_report_the_zeros_they_used():
    """The growing string from z0 = j_2,1 with 3 quarter periods uses j_1,1..5 and
    j_2,1..5; at 6 digits they are the source's printed zeros."""
    q = bp.quarter_periods(3, 6)
    assert q.dps == 6 and q.start == 1
    assert [Fraction(s) for s in q.zeros_j1] == [Fraction(s) for s in SOURCE_J1]
    assert [Fraction(s) for s in q.zeros_j2] == [Fraction(s) for s in SOURCE_J2]


def test_shortening_margins_are_differences_in_time_order():
    """Shortening from z0 = j_2,3, in time order: inward j23^2 - j13^2, outward j13^2 - j22^2,
    inward j22^2 - j12^2, outward j12^2 - j21^2, inward j21^2 - j11^2.  margin_after[i] is
    inward i minus the outward swing after it, margin_before[i] inward i + 1 minus the one
    before it; worked out by hand from A&S 9.5 (error below 1e-8)."""
    q = bp.quarter_periods(5, 8, bp.SHORTENING)
    ins = [J23 ** 2 - J13 ** 2, J22 ** 2 - J12 ** 2, J21 ** 2 - J11 ** 2]
    outs = [J13 ** 2 - J22 ** 2, J12 ** 2 - J21 ** 2]
    after = [ins[0] - outs[0], ins[1] - outs[1]]
    before = [ins[1] - outs[0], ins[2] - outs[1]]
    assert len(q.margin_after) == 2 and len(q.margin_before) == 2
    for ours, ref in zip(q.margin_after + q.margin_before, after + before):
        assert abs(Fraction(ours) - ref) < Fraction(1, 10 ** 5), (ours, float(ref))
    for ball, ref in zip(q.after_balls + q.before_balls, after + before):
        assert abs(Fraction(ball.mid().str(30, radius=False)) - ref) < Fraction(1, 10 ** 7)


def test_a_single_inward_swing_has_no_margin():
    """Shortening from z0 = j_2,1: one quarter period, inward j21^2 - j11^2 (A&S 9.5), no
    outward swing beside it, so nothing decides the claim: the verdict is None (not False,
    not an empty value)."""
    q = bp.quarter_periods(1, 8, bp.SHORTENING, start=1)
    assert abs(Fraction(q.inward[0]) - (J21 ** 2 - J11 ** 2)) < Fraction(1, 10 ** 5)
    assert q.outward == [] and q.margin_after == [] and q.margin_before == []
    assert q.claim_holds is None and "no margin" in q._verdict()


def test_the_claim_holds_for_a_margin_just_above_zero(monkeypatch):
    """j_1,3 moved so that margin_after[1] = 2 j_1,3^2 - j_2,2^2 - j_2,3^2 is +1e-10 instead
    of 1.128: every margin is still positive, so the claim holds (a test of "positive" that
    asked for more than 0, e.g. more than 1, would leave the verdict undecided)."""
    real = bp.bessel_zeros

    def moved(nu, count, dps, extra_bits=0, window_bits=None):
        res = real(nu, count, dps, extra_bits)
        if nu == 1:
            j2 = real(2, count, dps, extra_bits).balls
            with bz._Prec(bz.bits_for(dps) + extra_bits + 16):
                res.balls[2] = ((j2[1] ** 2 + j2[2] ** 2 + arb("1e-10")) / 2).sqrt()
        return res
    monkeypatch.setattr(bp, "bessel_zeros", moved)
    q = bp.quarter_periods(3, 6)
    assert q.after_balls[1] > 0 and q.margin_after[1] == "1.00000e-10"
    assert q.claim_holds is True


def test_quarter_periods_refuse_a_count_or_start_past_ten_thousand():
    """count and start go from 1 to 10_000 (the limit of the API): 10_001 is refused with a
    message naming the argument and the range; so is an unknown direction."""
    with pytest.raises(InputError, match="count must be an integer from 1 to 10000, got 10001"):
        bp.quarter_periods(10_001, 6)
    with pytest.raises(InputError, match="start must be an integer from 1 to 10000, got 10001"):
        bp.quarter_periods(1, 6, start=10_001)
    with pytest.raises(InputError, match="direction must be 'growing' or 'shortening'"):
        bp.quarter_periods(1, 6, "sideways")


def test_a_shortening_string_reports_only_the_zeros_it_passes():
    """Shortening from z0 = j_2,2 with 3 quarter periods passes j_2,2, j_1,2, j_2,1, j_1,1 and
    nothing beyond z0: the zeros reported are j_1,1..2 and j_2,1..2 (A&S 9.5, 8 digits)."""
    q = bp.quarter_periods(3, 8, bp.SHORTENING, start=2)
    for ours, ref in zip((q.zeros_j1, q.zeros_j2), ((J11, J12), (J21, J22))):
        assert len(ours) == 2
        assert all(abs(Fraction(s) - r) < Fraction(1, 10 ** 6) for s, r in zip(ours, ref))


def test_each_precision_raise_of_quarter_periods_adds_bits(monkeypatch):
    """When a duration or margin cannot be rounded, quarter_periods retries with 32 more bits
    each time (MAX_RAISES times): with the margin made exactly 0 (no retry ever succeeds) the
    extra bits of the successive attempts must grow by 32, never stay the same."""
    real_zeros, real_compute = bp.bessel_zeros, bp._compute
    extras = []

    def moved(nu, count, dps, extra_bits=0, window_bits=None):
        res = real_zeros(nu, count, dps, extra_bits)
        if nu == 1:
            j2 = real_zeros(2, count, dps, extra_bits).balls
            with bz._Prec(bz.bits_for(dps) + extra_bits + 16):
                res.balls[2] = ((j2[1] ** 2 + j2[2] ** 2) / 2).sqrt()
        return res

    def spy(count, dps, direction, m, nmax, extra):
        extras.append(extra)
        return real_compute(count, dps, direction, m, nmax, extra)
    monkeypatch.setattr(bp, "bessel_zeros", moved)
    monkeypatch.setattr(bp, "_compute", spy)
    with pytest.raises(bz.CertificationError, match="with 512 more bits"):
        bp.quarter_periods(3, 6)
    assert len(extras) == bp.MAX_RAISES == 16
    assert [b - a for a, b in zip(extras, extras[1:])] == [32] * 15


# -- the default grid of the identity check ---------------------------------------------------

def test_default_grid_is_log_spaced_and_holds_the_doubles_next_to_the_first_zeros():
    """200 points log-spaced from 1e-30 to 1e6 (numpy.logspace as the reference, 1e-13
    relative) and the doubles nearest to j_n,k, n = 0, 1, 2, k = 1, 2, 3 (mpmath.besseljzero
    at 30 digits, rounded to a double)."""
    import numpy as np
    grid = bi.default_grid()
    with mpmath.workdps(30):
        zeros = sorted(float(mpmath.besseljzero(n, k)) for n in (0, 1, 2) for k in (1, 2, 3))
    assert len(grid) == 209 and grid == sorted(grid)
    assert all(z in grid for z in zeros)
    rest = [z for z in grid if z not in zeros]
    ref = np.logspace(-30, 6, 200)
    assert len(rest) == 200
    assert np.max(np.abs(np.array(rest) / ref - 1)) < 1e-13


@pytest.mark.parametrize("count", [1, 10_001, True, 2.0])
def test_default_grid_refuses_a_bad_count(count):
    with pytest.raises(InputError, match="points must be an integer from 2 to 10000"):
        bi.default_grid(count)


def test_default_grid_takes_the_largest_count():
    assert len(bi.default_grid(10_000, near_zeros=False)) == 10_000


# -- the double-precision comparison of docs/bessel.md ----------------------------------------

def test_scipy_cross_product_is_accurate_where_nothing_overflows():
    """J_n Y_n+1 - J_n+1 Y_n = -2/(pi z) (DLMF 10.5.3) in doubles: at z = 1e-30, 0.5 and 10,
    n = 0..3, nothing overflows and SciPy's product is right to a few ulps relative to
    2/(pi z) (6e29 at z = 1e-30, so an absolute error would not pass); the list has one
    entry per (z, n) in that order.  A wrong sign, order or reference would give errors near
    1.  Where Y_n overflows (n = 12 at 1e-30) the error is reported as infinite."""
    got = bi.scipy_cross_product_errors(3, [1e-30, 0.5, 10.0])
    assert [(z, n) for z, n, _ in got] == [(z, n) for z in (1e-30, 0.5, 10.0) for n in range(4)]
    assert all(err < 1e-13 for _, _, err in got), got
    assert bi.scipy_cross_product_errors(12, [1e-30])[-1][2] == math.inf


def test_scipy_value_errors_of_y_are_small_away_from_its_zeros():
    """SciPy's yv(1, z) against arb: a few ulps at z = 0.5 and 1e6, no correct digit at the
    double next to y_1,1 (mpmath.besselyzero, 30 digits), where Y_1 ~ 1e-17."""
    with mpmath.workdps(30):
        y11 = float(mpmath.besselyzero(1, 1))
    got = bi.scipy_value_errors(1, [0.5, 1e6, y11])
    assert got[0][2] < 1e-14 and got[1][2] < 1e-14
    assert got[2][2] > 0.1


def test_the_worst_error_of_each_identity_is_the_largest_over_the_points():
    """by_rule keeps, for each (engine, identity), the largest error over the grid: checked
    over two points it equals the larger of the two one-point checks (and its z), and for
    at least one identity the larger is at the second point, so keeping the first would
    show."""
    pts = [3.8317059702075125, 0.5]
    both = bi.check_identities(1, 15, pts, engines=("mpmath",))
    one = [bi.check_identities(1, 15, [z], engines=("mpmath",)) for z in pts]
    later = 0
    for key, (err, z, _) in both.by_rule.items():
        errs = [rep.by_rule[key][0] for rep in one]
        assert err == max(errs) and z == pts[errs.index(max(errs))], key
        later += errs[1] > errs[0]
    assert later >= 1


# -- the bound on J'' of interval Newton, where its two terms are of one size -------------------

@pytest.mark.parametrize("nu, lo", [(0, 1), (1, 2)])
def test_second_derivative_bound_where_its_terms_are_alike(nu, lo):
    """At lo = 1 (nu = 0) and lo = 2 (nu = 1) the term (nu/lo + 1)/lo is as large as the
    swing max(|1 - nu^2/lo^2|, 1) = 1: a bound that subtracted one from the other (0 and
    0.25), or used nu/lo - 1 (0 for J_0), would fall below sup |J_nu''| on [lo, 40]
    (mpmath's own derivative=2 on a grid of step 0.05: 0.325 for J_0 at 1)."""
    with bz._Prec(64):
        bound = float(bz.second_derivative_bound(arb(nu), arb(lo)))
    with mpmath.workdps(15):
        worst = max(abs(mpmath.besselj(nu, lo + i * mpmath.mpf("0.05"), derivative=2))
                    for i in range(int((40 - lo) / 0.05) + 1))
    assert worst > 0.2 and bound >= worst, (nu, lo, bound, worst)


# -- the Sturm window where it must be two-sided ----------------------------------------------

#: j_300,4..6 by scipy.special.jn_zeros(300, 6) (SciPy 1.x, double precision); each is
#: confirmed below by a sign change of mpmath.besselj(300, x) across x -+ 1e-9.
J_300 = {4: 337.3581757209018, 5: 343.9879577023811, 6: 350.2333678599057}


def test_next_window_of_a_large_order_just_below_q_one_quarter():
    """After j_300,4 = 337.358, q(x) = 1 - (nu^2 - 1/4)/x^2 = 0.209 < 1/4, and the next zero
    is 6.63 > 2 pi further: a window (sup ball, inf ball + 2 pi) would miss it, so the
    window must be the two-sided one of the turning point.  It holds j_300,5 and not
    j_300,6."""
    with mpmath.workdps(30):
        balls = {}
        for k, x in J_300.items():
            lo, hi = mpmath.mpf(x) - mpmath.mpf("1e-9"), mpmath.mpf(x) + mpmath.mpf("1e-9")
            assert mpmath.besselj(300, lo) * mpmath.besselj(300, hi) < 0, k
            with bz._Prec(200):
                balls[k] = arb(repr(x)) + arb(0, arb("1e-9"))
    assert J_300[5] - J_300[4] > 2 * float(mpmath.pi)
    a, b, c = bz.next_window(Fraction(300), balls[4], 200)
    assert a < balls[5] < b and c < balls[5]
    assert b < balls[6]


@pytest.mark.parametrize("nu", ["3/5", "3/4", "9/10"])
def test_next_window_for_orders_between_one_half_and_one(nu):
    """For 1/2 <= nu < 1, q = 1 - (nu^2 - 1/4)/x^2 < 1, so zeros are at least pi apart and the
    window after x ends at x + 2 pi.  Ending it at x + 2 pi/sqrt(q(x)) instead (the bound
    for nu < 1/2) would take in j_nu,k+2 as well: by 0.02 to 0.09 for k = 1 (mpmath).
    Reference: mpmath.besseljzero at 40 digits."""
    nuq = Fraction(nu)
    with mpmath.workdps(40):
        order = mpmath.mpf(nuq.numerator) / nuq.denominator
        js = [mpmath.besseljzero(order, k) for k in range(1, 5)]
        q = 1 - (order ** 2 - mpmath.mpf(1) / 4) / js[0] ** 2
        assert js[0] + 2 * mpmath.pi / mpmath.sqrt(q) > js[2]  # the looser end is wrong here
        balls = [arb(mpmath.nstr(j, 40)) + arb(0, arb(10) ** -35) for j in js]
    for k in range(2):
        a, b, c = bz.next_window(nuq, balls[k], 200)
        assert a < balls[k + 1] < b and c < balls[k + 1], (nu, k + 1)
        assert b < balls[k + 2], (nu, k + 1)
