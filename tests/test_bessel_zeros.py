"""pendulab's certified zero finder for J_nu (pendulab.analyses.bessel_zeros).

References, each with its provenance:
* Abramowitz & Stegun, Table 9.5 (zeros j_{n,s} of J_n, 10 decimals);
* 002_19b336b29bb1f03b.txt, last page: the first 8 zeros of J1 and of J2 as printed;
* DLMF 10.21.19 (McMahon's coefficients) and DLMF 10.18.18 (phase), printed formulas;
* mpmath.besseljzero (a different algorithm: mpmath's own root polishing) as a
  cross-check of our digits, never as the thing under test.
"""

from fractions import Fraction

import mpmath
import pytest
from flint import arb, fmpq_poly

from pendulab.analyses.bessel_asymptotics import mcmahon_coefficients, phase_coefficients
from pendulab.analyses.bessel_zeros import (CertificationError, ball_digits, bessel_zeros, bits_for,
                                            check_index, check_interlacing, interval_newton)
from pendulab.errors import InputError

# A&S Table 9.5 (Abramowitz & Stegun 1964, p. 409), 10 decimals.
AS_9_5 = {(1, 1): "3.8317059702", (1, 2): "7.0155866698", (1, 3): "10.1734681351",
          (2, 1): "5.1356223018", (2, 2): "8.4172441404", (2, 3): "11.6198411721"}
# 002, last page, as printed (6 significant digits, trailing zeros dropped by the source).
SOURCE_J1 = ["3.83171", "7.01559", "10.1735", "13.3237", "16.4706", "19.6159", "22.7601", "25.9037"]
SOURCE_J2 = ["5.13562", "8.41724", "11.6198", "14.796", "17.9598", "21.117", "24.2701", "27.4206"]

MU = fmpq_poly([0, 1])


def test_mcmahon_coefficients_are_dlmf_10_21_19():
    """Derived by series reversion; DLMF 10.21.19 prints the first four."""
    c = mcmahon_coefficients()
    assert c[0] == -(MU - 1) / 8
    assert c[1] == -4 * (MU - 1) * (7 * MU - 31) / (3 * 8 ** 3)
    assert c[2] == -32 * (MU - 1) * (83 * MU ** 2 - 982 * MU + 3779) / (15 * 8 ** 5)
    assert c[3] == -64 * (MU - 1) * (6949 * MU ** 3 - 153855 * MU ** 2 + 1585743 * MU - 6277237) / (105 * 8 ** 7)


def _mcmahon_full_order_passes(terms):
    """The reversion as first written: terms + 1 fixed-point passes, every one at the full order."""
    from pendulab.analyses.bessel_asymptotics import _inv, _phi_of, _zero
    n = 2 * terms + 1
    delta = _zero(n)
    for _ in range(terms + 1):
        y = [fmpq_poly(0)] + _inv([fmpq_poly(1)] + delta[:n], n)[:n]
        delta = [-c for c in _phi_of(y, n, terms)]
    return tuple(delta[2 * j - 1] for j in range(1, terms + 1))


@pytest.mark.parametrize("terms", [1, 2, 5, 10, 12])
def test_mcmahon_truncated_passes_equal_full_order_passes(terms):
    """The cheap passes (pass i truncated after s^2i) give the same exact rationals."""
    assert mcmahon_coefficients(terms) == _mcmahon_full_order_passes(terms)


def test_phase_coefficients_are_dlmf_10_18_18():
    d = phase_coefficients()
    assert d[1] == (MU - 1) / (2 * 4)
    assert d[3] == (MU - 1) * (MU - 25) / (6 * 4 ** 3)
    assert all(d[j] == 0 for j in range(0, len(d), 2))


@pytest.mark.parametrize("n", [1, 2])
def test_abramowitz_stegun_table_9_5(n):
    got = bessel_zeros(n, 3, 11).strings
    for k in (1, 2, 3):
        ref = AS_9_5[(n, k)]
        # 11 significant digits of ours against 10 decimals of the table: agree within 1 unit
        assert abs(Fraction(got[k - 1]) - Fraction(ref)) <= Fraction(1, 10 ** 10), (n, k, got[k - 1], ref)


def test_the_sources_eight_zeros_to_every_printed_digit():
    for n, printed in ((1, SOURCE_J1), (2, SOURCE_J2)):
        for k, text in enumerate(printed, start=1):
            digits = len(text.replace(".", ""))
            ours = bessel_zeros(n, k, digits).strings[-1]
            assert Fraction(ours) == Fraction(text), (n, k, ours, text)


@pytest.mark.parametrize("nu, count, dps", [(1, 40, 50), (2, 40, 50), (0, 10, 30), ("1/3", 10, 40),
                                            ("2.5", 5, 60), (0.5, 5, 25), (30, 5, 25), (1, 3, 1000)])
def test_every_digit_agrees_with_mpmath_besseljzero(nu, count, dps):
    res = bessel_zeros(nu, count, dps)
    nu_q = Fraction(nu) if not isinstance(nu, float) else Fraction(nu)
    with mpmath.workdps(dps + 20):
        order = mpmath.mpf(nu_q.numerator) / nu_q.denominator
        for k in (1, 2, count):
            ref = mpmath.besseljzero(order, k)
            assert res.strings[k - 1] == mpmath.nstr(ref, dps, strip_zeros=False), (nu, k)


def test_half_order_zeros_are_multiples_of_pi():
    """J_{1/2}(x) = sqrt(2/(pi x)) sin x (DLMF 10.16.1): j_{1/2,k} = k pi exactly."""
    res = bessel_zeros("1/2", 6, 40)
    with mpmath.workdps(60):
        for k, s in enumerate(res.strings, start=1):
            assert s == mpmath.nstr(k * mpmath.pi, 40, strip_zeros=False)


def test_ten_thousandth_zero_and_the_phase_check():
    res = bessel_zeros(1, 10_000, 30)
    assert res.phase_checked == 10_000  # the asymptotic phase confirms every index
    with mpmath.workdps(50):
        assert res.strings[-1] == mpmath.nstr(mpmath.besseljzero(1, 10_000), 30, strip_zeros=False)


def test_certifier_rejects_a_perturbed_zero():
    bits = bits_for(40)
    good = bessel_zeros(1, 1, 40).balls[0]
    ball = interval_newton(1, good.mid(), arb(2) ** -120, bits)
    assert ball.overlaps(good)
    with pytest.raises(CertificationError):
        interval_newton(1, good.mid() + arb(2) ** -60, arb(2) ** -120, bits)
    with pytest.raises(CertificationError):  # no zero at all near 5
        interval_newton(1, 5, arb(2) ** -20, bits)


def test_index_check_catches_a_skipped_or_repeated_zero():
    balls = bessel_zeros(2, 5, 30).balls
    assert check_index(2, balls)
    with pytest.raises(CertificationError, match="zero number 2"):
        check_index(2, [balls[0], balls[2], balls[3]])  # j_{2,2} skipped
    with pytest.raises(CertificationError):
        check_index(2, [balls[0], balls[0]])  # counted twice
    with pytest.raises(CertificationError, match="zero number 1"):
        check_index(2, balls[1:])  # the first zero missing


def test_interlacing_is_proved_and_can_fail():
    j1, j2 = bessel_zeros(1, 20, 30).balls, bessel_zeros(2, 20, 30).balls
    assert check_interlacing(j1, j2) == 40
    with pytest.raises(CertificationError):
        check_interlacing(j1, j2[1:])  # shifted by one: j_{2,2} > j_{1,2}


def test_ball_digits_refuses_ambiguous_rounding():
    assert ball_digits(arb("1.25", 1e-3), 2) is None  # 1.249 -> 1.2 but 1.251 -> 1.3
    assert ball_digits(arb("1.5", 1e-3), 2) == "1.5"
    assert ball_digits(arb(0, 1e-3), 2) is None


@pytest.mark.parametrize("args, fragment", [
    ((-1, 3, 10), "order must be >= 0"), (("x", 3, 10), "order must be a real number"),
    ((1, 0, 10), "count"), ((1, -2, 10), "count"), ((1, 2.5, 10), "count"), ((1, True, 10), "count"),
    ((1, 3, 0), "dps"), ((1, 3, 10_001), "dps"), ((1, 3, 2.0), "dps"), ((301, 3, 10), "at most"),
    ((float("nan"), 3, 10), "order"),
])
def test_bad_arguments(args, fragment):
    with pytest.raises(InputError, match=fragment):
        bessel_zeros(*args)


# -- regressions: non-integer orders above 75, low dps, arb's method bound near x ~ 1.4 nu --------

def _mpmath_zeros(nu, count, digits):
    """The first ``count`` zeros of J_nu by mpmath alone, independently of the code under test:
    sign changes of mpmath.besselj on the grid max(nu, 1/2) + k/2 (J_nu > 0 on (0, nu] and
    zeros are more than 1/2 apart, so none is missed), each then solved by mpmath.findroot
    (Anderson's bracketing method) at ``digits`` digits."""
    nu = Fraction(nu)
    with mpmath.workdps(digits):
        order = mpmath.mpf(nu.numerator) / nu.denominator
        f = lambda x: mpmath.besselj(order, x)  # noqa: E731
        x = max(order, mpmath.mpf(1) / 2)
        fx, out = f(x), []
        while len(out) < count:
            y = x + mpmath.mpf(1) / 2
            fy = f(y)
            if fx * fy < 0:
                out.append(mpmath.findroot(f, (x, y), solver="anderson"))
            x, fx = y, fy
    return out


def _same_number(ours, ref, dps):
    """``ours`` has ``dps`` significant digits and equals ``ref`` rounded to them (by mpmath)."""
    mantissa = ours.split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa) == dps and Fraction(ours) == Fraction(mpmath.nstr(ref, dps))


@pytest.mark.parametrize("nu", ["99.9", "150.5", "200.25", "250.7", "299.5", "299.99"])
def test_non_integer_orders_beyond_75_are_certified(nu):
    """These failed with "cannot decide the sign of J_nu": the bracket search evaluated J_nu
    at sums rounded at 53 bits (balls of radius ~1e-13), and arb's J_nu of a non-integer
    order turns such a radius into an enclosure too wide for any sign, at every precision.
    Reference: mpmath alone (besselj's sign changes, then findroot at 50 digits)."""
    res = bessel_zeros(nu, 3, 30)
    ref = _mpmath_zeros(nu, 3, 50)
    for k in range(3):
        assert _same_number(res.strings[k], ref[k], 30), (nu, k + 1, res.strings[k], ref[k])
    assert check_index(nu, res.balls)


@pytest.mark.slow
def test_non_integer_order_where_arb_uses_its_asymptotic_expansion():
    """For nu = 299.99 the Newton iterates near x ~ 407 (zero 17) are where arb evaluates J_nu
    by an asymptotic expansion up to ~1000 bits, whose truncation bound (2^-25 here) does not
    shrink as the precision grows by small steps: the evaluation gave up ("cannot be evaluated
    accurately").  Reference: mpmath alone, as above."""
    res = bessel_zeros("299.99", 17, 20)
    ref = _mpmath_zeros("299.99", 17, 40)
    for k in (0, 15, 16):
        assert _same_number(res.strings[k], ref[k], 20), (k + 1, res.strings[k], ref[k])


@pytest.mark.parametrize("nu, dps", [(100, 1), (300, 1), (100, 2), (300, 3), (0, 1), (1, 2),
                                     ("299.99", 1), ("1/3", 1)])
def test_low_dps_is_computed_at_a_working_precision(nu, dps):
    """dps = 1 gave 24 working bits: the certificate's interval (2^-9 |x| wide at first, then
    widened) was wider than the gap between zeros for large orders ("interval [+/- 1.50e+4]
    ... is not positive").  Reference: mpmath.besseljzero for integer orders, mpmath alone
    (sign changes and findroot) for the others, at 30 digits, rounded by mpmath.nstr."""
    res = bessel_zeros(nu, 3, dps)
    if isinstance(nu, int):
        with mpmath.workdps(30):
            ref = [mpmath.besseljzero(nu, k) for k in (1, 2, 3)]
    else:
        ref = _mpmath_zeros(nu, 3, 30)
    for k in range(3):
        assert _same_number(res.strings[k], ref[k], dps), (nu, dps, k + 1, res.strings[k], ref[k])
