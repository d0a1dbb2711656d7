"""Each proof step of the Bessel modules, fed a wrong candidate, refuses it.

Modules: pendulab.analyses.bessel_zeros (interval Newton, the bound on J'' it uses, the
Sturm windows, the asymptotic-phase index, interlacing, decimal rounding of a ball),
bessel_identities (the balls behind ``arb_certified``, the engines' agreement, the bounds
on the fourth derivatives), bessel_periods (the interlacing and the margins of the claim),
bessel (the symbolic zero test) and variable_length_motion (the strict positivity of L).

References, each an independent method or a printed source:
* mpmath (besselj, bessely with ``derivative=k``, besseljzero), at the digits stated;
* DLMF 10.2.1 (Bessel's equation), 10.5.3 (the Wronskian), 10.6.6 (derivative rules),
  10.21.3 (interlacing);
* 002_19b336b29bb1f03b.txt, last page, for the quarter periods.
Next to each test: which inner function a wrong candidate is slipped through, if any.
"""

from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from flint import arb

import pendulab.analyses.bessel_identities as bi
import pendulab.analyses.bessel_periods as bp
import pendulab.analyses.bessel_zeros as bz
from pendulab import symbols as S
from pendulab.analyses import bessel as bs
from pendulab.analyses import variable_length_motion as vlm


def _ball(value, digits=40, rad_exp=-35):
    """An arb ball at 200 bits around an mpmath number (as a decimal string)."""
    with bz._Prec(200):
        return arb(mpmath.nstr(value, digits)) + arb(0, arb(10) ** rad_exp)


# -- the bound on J'' used by interval Newton ------------------------------------------------

@pytest.mark.parametrize("nu, lo, top, step", [(100, 100, 400, 0.5), (10, 10, 60, 0.1),
                                               (2, 1, 40, 0.05), (0, "0.5", 40, 0.05)])
def test_second_derivative_bound_is_above_mpmaths_max_on_a_grid(nu, lo, top, step):
    """sup |J_nu''| on [lo, oo) from Bessel's equation (DLMF 10.2.1).  The bound used to be
    (nu/lo + 1)/lo + |1 - nu^2/lo^2|, which for lo = nu = 100 is 0.02, while mpmath's
    J_100'' (its own differentiation, derivative=2) reaches 0.0455 near x = 150: the
    term |1 - nu^2/x^2| rises toward 1 beyond x = nu."""
    with bz._Prec(64):
        bound = float(bz.second_derivative_bound(arb(nu), arb(lo)))
    with mpmath.workdps(15):
        a = mpmath.mpf(lo)
        n = int((top - a) / step)
        worst = max(abs(mpmath.besselj(nu, a + i * step, derivative=2)) for i in range(n + 1))
    assert bound >= worst, (nu, lo, bound, worst)


def test_interval_newton_refuses_an_interval_where_the_derivative_vanishes(monkeypatch):
    """X = j_1,1 +- 1.6 holds the maximum of |J_1| at j'_1,2 = 5.33 (J_1' = 0 there) and
    X = j_1,1 +- 3.5 holds j_1,2 = 7.02 too: no unique zero is certified.  With the bound on
    J'' ten times too small the first is accepted, with no bound at all the second too."""
    good = bz.bessel_zeros(1, 2, 30).balls
    bits = bz.bits_for(30)
    m = good[0].mid()
    with mpmath.workdps(30):  # the wrong candidates really are wrong (mpmath)
        assert m - 1.6 < mpmath.besseljzero(1, 2, derivative=1) < m + 1.6
        assert m + 3.5 > mpmath.besseljzero(1, 2)
    for radius in ("1.6", "3.5"):
        with pytest.raises(bz.CertificationError, match="may vanish"):
            bz.interval_newton(1, m, arb(radius), bits)
    # the same X with a small enough radius is certified, and holds j_1,1
    ball = bz.interval_newton(1, m, arb(2) ** -60, bits)
    assert ball.overlaps(good[0])


def test_interval_newton_refuses_a_midpoint_a_few_radii_off():
    """X = [m - r, m + r] with the zero at m - 1.5 r (outside X) is refused; at m - r/2
    (inside) it is certified: the refusal is the image test, not a loose tolerance."""
    bits = bz.bits_for(40)
    j = bz.bessel_zeros(2, 3, 40).balls[2].mid()
    r = arb(2) ** -100
    with bz._Prec(bits + 40):
        inside, outside = j + r / 2, j + 3 * r / 2
    assert bz.interval_newton(2, inside, r, bits).overlaps(arb(j))
    with pytest.raises(bz.CertificationError, match="not inside"):
        bz.interval_newton(2, outside, r, bits)
    with pytest.raises(bz.CertificationError, match="not positive"):
        bz.interval_newton(2, "0.25", "0.5", bits)


# -- the index: Sturm windows, the first bracket, the asymptotic phase -------------------------

def _shift_zero(monkeypatch, nu, k, bad_k, dps):
    """Make bessel_zeros' final interval Newton step return the ball of j_nu,bad_k where it
    certified j_nu,k (the wrong candidate: a zero given the wrong index)."""
    good = bz.bessel_zeros(nu, max(k, bad_k) + 1, dps).balls
    real = bz._certify

    def wrong(nu_, x, bits, acc):
        ball = real(nu_, x, bits, acc)
        return good[bad_k - 1] if ball.overlaps(good[k - 1]) else ball
    monkeypatch.setattr(bz, "_certify", wrong)


def test_a_zero_outside_its_sturm_window_is_refused(monkeypatch):
    _shift_zero(monkeypatch, 1, 3, 4, 20)
    with pytest.raises(bz.CertificationError, match="not in the window .* zero number 3"):
        bz.bessel_zeros(1, 5, 20)


def test_a_zero_with_the_wrong_index_is_refused_by_the_asymptotic_phase(monkeypatch):
    """The window is widened (so it lets j_1,4 through as zero number 3): the phase
    theta_1(x) = (k - 1/2) pi gives its index 4 and the zero is refused."""
    _shift_zero(monkeypatch, 1, 3, 4, 20)
    real = bz.next_window

    def wide(nu, prev, bits=64):
        a, b, c = real(nu, prev, bits)
        with bz._Prec(bits):
            return a, (b + 3 * arb.pi()).upper(), c
    monkeypatch.setattr(bz, "next_window", wide)
    with pytest.raises(bz.CertificationError, match="asymptotic phase gives index 4 for zero 3"):
        bz.bessel_zeros(1, 5, 20)


def test_phase_index_refuses_a_point_a_quarter_away_from_a_zero():
    """theta_1(j_1,10 + d pi) = (9.5 + d) pi: index 10 for d = 0.2, 0.24, none for d = 0.26,
    0.3 (the margin is 0.25), 11 for d = 0.8.  Where the phase series is not accurate
    (x = 310 for nu = 300) no index is claimed.  Reference: mpmath.besseljzero."""
    with mpmath.workdps(30):
        j = mpmath.besseljzero(1, 10)
        got = {d: bz.phase_index(Fraction(1), arb(mpmath.nstr(j + d * mpmath.pi, 25)))
               for d in (0, 0.2, 0.24, 0.26, 0.3, 0.8)}
    assert got == {0: 10, 0.2: 10, 0.24: 10, 0.26: None, 0.3: None, 0.8: 11}
    assert bz.phase_index(Fraction(300), arb(310)) is None


@pytest.mark.parametrize("nu", ["0", "1/3", "1/2", "1", "5/2", "30", "200", "300"])
def test_next_window_holds_the_next_zero_and_not_the_one_after(nu):
    """For the ball of j_nu,k (from mpmath.besseljzero at 40 digits), next_window's (a, b)
    holds j_nu,k+1 and not j_nu,k+2, and c (the start of the bracket search) is below
    j_nu,k+1: the Sturm bounds of the module docstring, against an independent engine."""
    nuq = Fraction(nu)
    with mpmath.workdps(40):
        order = mpmath.mpf(nuq.numerator) / nuq.denominator
        js = [mpmath.besseljzero(order, k) for k in range(1, 6)]
        for k in range(3):
            a, b, c = bz.next_window(nuq, _ball(js[k]), 200)
            nxt, after = _ball(js[k + 1]), _ball(js[k + 2])
            assert a < nxt < b and c < nxt, (nu, k + 1)
            assert b < after, (nu, k + 1)


#: j_1000,1 by mpmath.besseljzero(1000, 1) at 40 digits (mpmath 1.3; four minutes there, so
#: stored; DLMF 10.21.40 gives 1000 + 1.8557571 * 1000^(1/3) = 1018.56 as a check of its size)
J_1000_1 = "1018.660880967907961551926150832493000636"


def test_next_window_refuses_where_sturm_cannot_exclude_a_second_zero():
    """Past nu = 300 the two-sided window near the turning point is too wide; below
    sqrt(nu^2 - 1/4) no window is claimed at all."""
    with mpmath.workdps(40):
        j = mpmath.mpf(J_1000_1)
    with pytest.raises(bz.CertificationError, match="too wide"):
        bz.next_window(Fraction(1000), _ball(j), 200)
    with pytest.raises(bz.CertificationError, match="below sqrt"):
        bz.next_window(Fraction(200), _ball(mpmath.mpf(150)), 200)


@pytest.mark.parametrize("nu", ["0", "1/3", "1", "2", "10", "100", "299.5", "300"])
def test_first_bracket_holds_the_first_zero_and_starts_below_it(nu):
    """J_nu > 0 on (0, a] and j_nu,1 in (a, b) with b < j_nu,2 (mpmath.besseljzero)."""
    nuq = Fraction(nu)
    a, b, sa = bz.first_bracket(nuq)
    with mpmath.workdps(30):
        order = mpmath.mpf(nuq.numerator) / nuq.denominator
        j1, j2 = mpmath.besseljzero(order, 1), mpmath.besseljzero(order, 2)
    assert sa == 1
    assert a < _ball(j1) < b < _ball(j2), (nu, a, b, j1)


def test_check_index_refuses_a_zero_number_two_in_place_of_one_or_three():
    balls = bz.bessel_zeros("1/3", 4, 25).balls
    assert bz.check_index("1/3", balls)
    with pytest.raises(bz.CertificationError, match="ball 3 .* is not zero number 3"):
        bz.check_index("1/3", [balls[0], balls[1], balls[1]])
    with pytest.raises(bz.CertificationError, match="ball 2"):
        bz.check_index("1/3", [balls[0], balls[2]])


def test_interlacing_refuses_a_zero_of_j_nu_plus_1_beyond_the_next_zero_of_j_nu():
    """DLMF 10.21.3: j_nu,k < j_nu+1,k < j_nu,k+1.  In place of j_2,k the list holds j_1,k+1
    (equal to the upper neighbour, so the second inequality cannot be proved) or j_1,k
    (equal to the lower one)."""
    j1 = bz.bessel_zeros(1, 6, 25).balls
    with pytest.raises(bz.CertificationError, match=r"j_nu\+1,1 < j_nu,2 not proved"):
        bz.check_interlacing(j1, j1[1:])
    with pytest.raises(bz.CertificationError, match=r"j_nu,1 < j_nu\+1,1 not proved"):
        bz.check_interlacing(j1, j1)


def test_ball_digits_refuses_a_ball_that_reaches_the_rounding_boundary():
    """[1.2499 +- 5e-5] lies in (1.2485, 1.25): "1.2"; [1.2499 +- 2e-4] reaches 1.2501,
    which rounds to 1.3: refused (None), also for a radius only 2x past the boundary."""
    with bz._Prec(100):
        assert bz.ball_digits(arb("1.2499", "5e-5"), 2) == "1.2"
        assert bz.ball_digits(arb("1.2499", "2e-4"), 2) is None
        assert bz.ball_digits(arb("-1.2499", "5e-5"), 2) == "-1.2"
        assert bz.ball_digits(arb("1.2499", "9e-5"), 2) == "1.2"
        assert bz.ball_digits(arb("1.2499", "1.1e-4"), 2) is None


# -- identities: the arb balls, the engines' agreement, the fourth-derivative bounds -----------

def _perturbed_arb(monkeypatch, rel):
    """The arb engine's Y_1 ball multiplied by 1 + rel, its radius kept (a wrong value)."""
    real = bi._arb_values

    def wrong(n_top, z, bits, derivatives=True):
        J, Y, dJ, dY = real(n_top, z, bits, derivatives)
        with bz._Prec(400):
            Y[1] = Y[1] * (1 + arb(rel))
        return J, Y, dJ, dY
    monkeypatch.setattr(bi, "_arb_values", wrong)


def test_arb_certified_is_true_only_for_balls_that_hold_the_exact_values(monkeypatch):
    """At 30 digits the identities are evaluated at 120 bits (7.5e-37 relative): a Y_1 ball
    wrong by 3e-36 is within mpmath's agreement tolerance (1e-35) but its cross product
    ball misses -2/(pi z): the flag is False, with either engine set.  It is True for the
    right balls and None when the arb engine did not run."""
    assert bi.check_identities(2, 30, [0.5]).arb_certified is True
    alone = bi.check_identities(2, 30, [0.5], engines=("mpmath",))
    assert alone.arb_certified is None and "did not run" in alone._caption()[1]
    _perturbed_arb(monkeypatch, "3e-36")
    wrong = bi.check_identities(2, 30, [0.5], engines=("arb",))
    assert wrong.arb_certified is False and "misses" in wrong._caption()[1]
    rep = bi.check_identities(2, 30, [0.5])  # the engines still agree within 1e-35
    assert rep.agreements == 14 and rep.arb_certified is False


def test_a_wrong_arb_engine_is_caught_by_the_agreement(monkeypatch):
    """Y_1 wrong by 3e-35 relative, three times the tolerance 10^-(dps+5)."""
    _perturbed_arb(monkeypatch, "3e-35")
    with pytest.raises(bi.EngineDisagreement, match="Y_1"):
        bi.check_identities(2, 30, [0.5])


@pytest.mark.parametrize("x", [0.01, 0.5, 3.8317059702075125, 20.0])
def test_j_fourth_derivative_bounds_are_above_mpmath_on_the_interval(x):
    """sup |J_n''''| on (0, x], n = 0..5, against mpmath's J_n'''' (derivative=4) on 200
    points of (0, x].  At x -> 0 the bound of J_0 is tight (J_0''''(0) = 3/8 = 6/16)."""
    with bz._Prec(64):
        bounds = [float(b) for b in bi._j_fourth_derivative_bounds(6, arb(x))]
    with mpmath.workdps(20):
        for n in range(6):
            worst = max(abs(mpmath.besselj(n, x * i / 200, derivative=4)) for i in range(1, 201))
            assert bounds[n] >= worst, (x, n, bounds[n], worst)
            if n == 0 and x <= 0.01:
                assert bounds[0] < 1.001 * worst  # tight: a bound 0.1 % smaller fails


@pytest.mark.parametrize("z", [0.5, 2.197141326031017, 12.0])
def test_y_fourth_derivative_bounds_are_above_mpmath_beyond_z(z):
    """sup |Y_n''''| on [z, oo) <= M_n+4(z), n = 0..3, against mpmath's Y_n'''' (derivative=4)
    on 41 points of [z, 3 z]."""
    with bz._Prec(80):
        zb = arb(z)
        J = [zb.bessel_j(n) for n in range(5)]
        Y = [zb.bessel_y(n) for n in range(5)]
        bounds = [float(b) for b in bi._y_fourth_derivative_bounds(4, zb, J, Y)]
    with mpmath.workdps(20):
        for n in range(4):
            worst = max(abs(mpmath.bessely(n, z * (1 + i / 20), derivative=4)) for i in range(41))
            assert bounds[n] >= worst, (z, n, bounds[n], worst)


@pytest.mark.parametrize("which, z", [("J", 3.8317059702075125), ("Y", 2.197141326031017)])
def test_a_fourth_derivative_bound_of_zero_is_flagged(monkeypatch, which, z):
    """Next to j_1,1 (J_0' = -J_1 ~ 1e-17) and y_1,1 (Y_0' = -Y_1 ~ 1e-17) the Taylor
    remainder decides the derivative ball; with no bound on f'''' the balls of J_0', Y_0'
    miss the exact derivative and arb_certified is False (True with the bound)."""
    assert bi.check_identities(1, 30, [z], engines=("arb",)).arb_certified is True
    if which == "J":
        monkeypatch.setattr(bi, "_j_fourth_derivative_bounds", lambda n_top, x: [arb(0)] * n_top)
    else:
        monkeypatch.setattr(bi, "_y_fourth_derivative_bounds", lambda n_top, zb, J, Y: [arb(0)] * n_top)
    rep = bi.check_identities(1, 30, [z], engines=("arb",))
    assert rep.arb_certified is False and rep.worst[2] == f"derivative_{which}"


# -- quarter periods: interlacing and the margins of the claim --------------------------------

def test_quarter_periods_refuse_zeros_that_do_not_interlace(monkeypatch):
    """The zeros of J_2 shifted by one index (j_2,k+1 given as j_2,k): refused."""
    real = bp.bessel_zeros

    def shifted(nu, count, dps, extra_bits=0, window_bits=None):
        if nu == 2:
            res = real(nu, count + 1, dps, extra_bits)
            res.balls, res.strings = res.balls[1:], res.strings[1:]
            return res
        return real(nu, count, dps, extra_bits)
    monkeypatch.setattr(bp, "bessel_zeros", shifted)
    with pytest.raises(bz.CertificationError, match="interlacing fails"):
        bp.quarter_periods(3, 6)


def test_the_claim_is_false_for_a_margin_just_below_zero(monkeypatch):
    """j_1,3 moved so that margin_after[1] = 2 j_1,3^2 - j_2,2^2 - j_2,3^2 is -1e-10 instead of
    1.128 (the zero moves down by 0.028, still between j_2,2 and j_2,3): the claim of 002 no
    longer holds and the verdict says so."""
    assert bp.quarter_periods(3, 6).claim_holds is True  # the source's table, unchanged
    real = bp.bessel_zeros
    made = {}

    def moved(nu, count, dps, extra_bits=0, window_bits=None):
        res = real(nu, count, dps, extra_bits)
        if nu == 1:
            j2 = real(2, count, dps, extra_bits).balls
            with bz._Prec(bz.bits_for(dps) + extra_bits + 16):
                res.balls[2] = ((j2[1] ** 2 + j2[2] ** 2 - arb("1e-10")) / 2).sqrt()
            made["shift"] = res.balls[2] - real(1, count, dps, extra_bits).balls[2]
        return res
    monkeypatch.setattr(bp, "bessel_zeros", moved)
    q = bp.quarter_periods(3, 6)
    assert -0.03 < float(made["shift"].mid()) < -0.02
    assert q.after_balls[1] < 0 and q.margin_after[1] == "-1.00000e-10"
    assert q.claim_holds is False


def test_a_margin_ball_that_holds_zero_is_refused_not_retried_forever(monkeypatch):
    """j_1,3 moved so that margin_after[1] is exactly 0 (as a ball, it holds 0 at every
    precision): no sign and no digit can be proved, so quarter_periods refuses after its
    precision raises (it used to raise the precision forever)."""
    real = bp.bessel_zeros

    def moved(nu, count, dps, extra_bits=0, window_bits=None):
        res = real(nu, count, dps, extra_bits)
        if nu == 1:
            j2 = real(2, count, dps, extra_bits).balls
            with bz._Prec(bz.bits_for(dps) + extra_bits + 16):
                res.balls[2] = ((j2[1] ** 2 + j2[2] ** 2) / 2).sqrt()
        return res
    monkeypatch.setattr(bp, "bessel_zeros", moved)
    with pytest.raises(bz.CertificationError, match="cannot be rounded to 6 digits"):
        bp.quarter_periods(3, 6)


def test_toward_swings_verdict_sees_a_shorter_toward_swing():
    """bessel.toward_swings_are_longer on the source's durations, and with the second
    toward swing made shorter than the outward one after it."""
    per = bs.quarter_periods(4, 20)
    assert [ok for _, ok in bs.toward_swings_are_longer(per)] == [True, True]
    with mpmath.workdps(30):
        per[2]["duration"] = per[3]["duration"] - mpmath.mpf("1e-15")
    assert bs.toward_swings_are_longer(per) == [(0, True), (2, False)]


# -- symbolic: the zero test behind the closed form's checks ----------------------------------

def test_is_zero_refuses_a_wrong_sign_a_shifted_order_and_a_wrong_constant():
    z = S.z
    J, Y = sp.besselj, sp.bessely
    rule = sp.diff(z ** -1 * J(1, z), z)
    assert bs.is_zero(rule + z ** -1 * J(2, z))  # DLMF 10.6.6
    assert not bs.is_zero(rule - z ** -1 * J(2, z))  # sign swapped
    assert not bs.is_zero(rule + z ** -1 * J(3, z))  # order shifted
    cross = J(1, z) * Y(2, z) - J(2, z) * Y(1, z)
    assert bs.is_zero(sp.diff(z * cross, z))  # Abel: z times the cross product is constant
    assert not bs.is_zero(sp.diff(z * (J(1, z) * Y(3, z) - J(3, z) * Y(1, z)), z))
    assert bs.derivative_rule_holds(1, "J") and bs.derivative_rule_holds(2, "Y")


def test_cross_product_is_dlmf_10_5_3():
    """J_n Y_n+1 - J_n+1 Y_n = -2/(pi z) (DLMF 10.5.3, rearranged), derived for n = 0, 1, 2."""
    for n in range(3):
        assert sp.simplify(bs.cross_product(n) + 2 / (sp.pi * S.z)) == 0


# -- the variable-length pendulum: L(t) > 0 only where it is proved ---------------------------

def test_positive_is_strict():
    """_positive decides a float that underflowed to 0 from the expression: a value evalf
    cannot tell from 0 (an exact zero: 1 - t at t = 1, which plain evalf gives as a digitless
    0.e-165 that compares > 0), a pole, a complex value or a symbol is not positive."""
    t = S.t
    r = sp.Symbol("r", real=True)
    p = sp.Symbol("p", positive=True)
    refused = [1 - t, t - 1, sp.sin(sp.pi * t), 1 / (t - 1), sp.sqrt(t - 2), r * t, p * t,
               sp.Symbol("a") * t, 0 * t]
    for expr in refused:
        assert vlm._positive(expr, 1.0, 0.0) is False, expr
    tiny = [sp.exp(-800 * t), (t - sp.Rational(1, 3)) * sp.exp(-800 * t), sp.exp(-t) * sp.Float("1e-400", 30)]
    for expr in tiny:  # positive, and below the smallest double
        assert vlm._positive(expr, 1.0, 0.0) is True, expr


@pytest.mark.parametrize("length", ["(t - 1)**2*exp(-800*t)", "(1 - t)*exp(-800*t)"])
def test_an_underflowing_length_with_an_exact_zero_is_found(length):
    """L(t) = (t - 1)^2 e^(-800 t) and (1 - t) e^(-800 t) vanish at t = 1 exactly (by
    inspection); their floats underflow to 0 from t ~ 0.93 on.  The scan of (0, 4] (step
    2^-10, so t = 1 is a grid point) must find t = 1; the old non-strict test took the zero
    for positive and found none (first length) or the next grid point (second)."""
    expr = sp.sympify(length, locals={"t": S.t})
    vlm._LENGTH_FUNCTIONS.clear()
    assert vlm.length_zero_time(expr, {}, horizon=4.0) == 1.0


def test_swings_of_a_trajectory_refuse_two_turning_points_in_a_row():
    """quarter_periods of a trajectory needs the events to alternate (turning point, theta = 0,
    ...): a missed crossing between two turning points is refused, not paired up."""
    t = np.linspace(0.0, 4.0, 5)
    good = vlm.Trajectory(t, np.zeros(5), np.zeros(5), {}, True,
                          (np.array([2.0]), np.array([0.1])), np.array([1.0, 3.0]))
    assert [k for k, _, _ in vlm.quarter_periods(good)] == ["toward", "outward", "toward"]
    missed = vlm.Trajectory(t, np.zeros(5), np.zeros(5), {}, True,
                            (np.array([2.0]), np.array([0.1])), np.array([3.0]))
    with pytest.raises(vlm.ConvergenceError, match="two turn events in a row"):
        vlm.quarter_periods(missed)


@pytest.mark.parametrize("length, first_zero", [
    ("5*(t - 7/3)**2", 7 / 3), ("(t - 1/7)**2*(t + 2)", 1 / 7), ("(t - pi)**2", 3.141592653589793),
    ("(t - 3/10)**2 + 1/10**14", None), ("(t - 2)**3*(t - 1/3)", 1 / 3), ("1 + t**2", None)])
def test_a_polynomial_length_that_touches_zero_is_found(length, first_zero):
    """A double root (L touches 0 and comes back) is a zero of L: the exact real roots find
    it, where numpy.roots had made 5 (t - 7/3)^2 a complex pair (imaginary part 4.6e-8 >
    the 1e-12 test) and reported no zero.  References by inspection of the factors; the
    length that stays above 1e-14 has none."""
    expr = sp.expand(sp.sympify(length, locals={"t": S.t}))
    vlm._LENGTH_FUNCTIONS.clear()
    got = vlm.length_zero_time(expr, {})
    if first_zero is None:
        assert got is None
    else:
        assert got == pytest.approx(first_zero, rel=1e-15, abs=0), (length, got)


def test_the_inverse_of_z_is_used_only_when_it_gives_back_l_and_t():
    """The fast residual route writes L (or t) back from z; an inverse that does not undo
    z = k L^beta (a wrong k) or L(t) (a wrong z(t)) is refused (None), and the slow route
    is taken instead."""
    L, z, t = S.Lvar, S.z, S.t
    k, beta = 2 * sp.sqrt(S.g) / S.v0, sp.Rational(1, 2)
    right = bs._inverse_power(k * L ** beta, k, beta)
    assert sp.simplify(right - (z / k) ** 2) == 0
    assert bs._inverse_power(3 * k * L ** beta, k, beta) is None
    length = S.L0 + S.v0 * t
    z_t = (k * L ** beta).subs(L, length)
    assert bs._inverse_linear(length, right, z_t) is not None
    assert bs._inverse_linear(length, right, (2 * k * L ** beta).subs(L, length)) is None
    assert bs._inverse_linear(S.L0 + S.v0 * t ** 2, right, z_t) is None
