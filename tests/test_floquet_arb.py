"""Method "arb": certified exponent, characteristic values and first band.

References (independent of the ball-arithmetic route):
* the mpmath routes of the package ("cf", "hill", method="mpmath" of the
  characteristic values and the band): other algorithms, other arithmetic;
* MathieuCharacteristicA[0, -1] to 56 digits (Wolfram|Alpha, quoted in the GSL
  bug report "Different Value for MathieuCe in Mathematica and GSL", 2017) and
  Zhang & Jin, "Computation of Special Functions" (1996), CVA1 output at q = 25;
* the eigenvalues of the truncated DLMF 28.4 matrices by mpmath.eigsy;
* the source's truncated characteristic equation and the recurrence matrix,
  derived symbolically by pendulab.analyses.phelps_hunter (000 eqs. 9-10) and
  lambdified, for the hand-written kernel.
"""

from fractions import Fraction

import mpmath
import pytest
import sympy as sp

from pendulab.analyses.floquet import (
    characteristic_exponent,
    first_band,
    mathieu_a,
    mathieu_b,
    stability_limits,
)
from pendulab.analyses.floquet import _arb
from pendulab.errors import InputError, PrecisionError

# the reference table of tests/test_floquet.py: band 0 (the source's Fig. 2
# point), its mirror, gap 1 at large q, gap 2, band 1, below a_0
POINTS = [("-0.002", "0.2"), ("-0.002", "-0.2"), ("-100", "60"), ("3", "10"),
          ("2", "0.3"), ("-0.5", "0.2")]

A0_Q1 = "-0.45513860410741354823263318752888586691651984219666547103"
ZHANG_JIN_Q25 = {("a", 0): "-40.256779547", ("b", 1): "-40.256778985",
                 ("a", 3): "12.964079444", ("b", 8): "69.057988351"}


def _rounded(x, digits):
    """x (a number, or a decimal string read at digits + 30) rounded to ``digits``."""
    with mpmath.workdps(digits + 30):
        return mpmath.nstr(mpmath.mpmathify(x), digits, strip_zeros=False)


@pytest.mark.parametrize("theta0,theta1", POINTS)
def test_certified_lambda_is_the_correctly_rounded_cf_value_at_50_digits(theta0, theta1):
    r = characteristic_exponent(theta0, theta1, dps=50)
    assert r.method == "arb" and r.certified_digits == 50 and not r.on_boundary
    ref = characteristic_exponent(theta0, theta1, dps=80, method="cf")
    hill = characteristic_exponent(theta0, theta1, dps=50, method="hill")
    assert r.stable == ref.stable == hill.stable and r.band_edge == ref.band_edge
    part = (lambda z: z) if r.stable else mpmath.im
    # every certified digit is the correctly rounded digit of the 80-digit cf value
    assert _rounded(part(r.lam), 50) == _rounded(part(ref.lam), 50)
    if not r.stable:
        assert mpmath.re(r.lam) == r.band_edge


@pytest.mark.parametrize("theta0,theta1", [("-1/500", "1/5"), ("1/3", "1/2"), ("-100", "60")])
def test_certified_lambda_at_1000_digits_against_cf(theta0, theta1):
    r = characteristic_exponent(theta0, theta1, dps=1000)
    ref = characteristic_exponent(theta0, theta1, dps=1000, method="cf")
    assert r.certified_digits == 1000 and r.stable == ref.stable
    with mpmath.workdps(1010):
        assert abs(r.lam - ref.lam) <= mpmath.mpf(10) ** -999 * max(1, abs(ref.lam))


@pytest.mark.parametrize("theta0", ["4", "16", "36", "100"])
@pytest.mark.parametrize("theta1", ["0.1", "1e-3", "2.5"])
def test_hill_near_even_squares_agrees_with_cf_and_arb(theta0, theta1):
    # Hill's shift s = 1 next to theta0 = (2n)^2 (the s = 0 normalisation divides
    # by (2n)^2 - theta0 = 0 there); the references are cf and arb, other routes.
    # Small q: b_2 = 4 - q^2/12 < 4 < a_2 = 4 + 5 q^2/12 (DLMF 28.6.5-28.6.6), so
    # theta0 = 4 lies in gap 2 (Re lam = 2); for m >= 3, a_m and b_m are
    # m^2 + q^2/(2(m^2 - 1)) + O(q^4) (DLMF 28.6.14 to that order), above m^2:
    # theta0 = m^2 lies in band m - 1, just below its upper edge (lam < m).
    hill = characteristic_exponent(theta0, theta1, method="hill")
    cf = characteristic_exponent(theta0, theta1, method="cf")
    assert hill.stable == cf.stable
    assert abs(complex(hill.lam) - complex(cf.lam)) <= 1e-12 * abs(complex(cf.lam))
    r = characteristic_exponent(theta0, theta1, dps=30)
    assert r.stable == cf.stable and r.certified_digits == 30
    if theta1 != "2.5":
        m = int(int(theta0) ** 0.5)
        assert r.band_edge == m
        if m == 2:
            assert not r.stable and mpmath.re(r.lam) == 2
        else:
            assert r.stable and m - 1e-3 < r.lam < m
    h30 = characteristic_exponent(theta0, theta1, dps=30, method="hill")
    with mpmath.workdps(40):
        assert abs(h30.lam - r.lam) < mpmath.mpf(10) ** -28 * abs(r.lam)


def test_theta1_zero_is_certified_and_exact():
    r = characteristic_exponent("2", "0", dps=40)
    assert r.certified_digits == 40 and r.stable
    with mpmath.workdps(60):
        assert _rounded(r.lam, 40) == _rounded(mpmath.sqrt(2), 40)
    r = characteristic_exponent("9", 0, dps=20)
    assert r.on_boundary and r.lam == 3


def test_mpmath_routes_and_double_report_no_certified_digits():
    assert characteristic_exponent("-0.002", "0.2").certified_digits is None
    assert characteristic_exponent("-0.002", "0.2", dps=20, method="cf").certified_digits is None


def test_on_a_curve_beyond_max_dps_is_on_boundary():
    # a_0(0.2) to 100 digits is 1e-101 off the curve; max_dps = 60 cannot tell the side
    with mpmath.workdps(110):
        t0 = mpmath.nstr(mathieu_a(0, "0.2", dps=105, method="mpmath"), 100)
    r = characteristic_exponent(t0, "-0.2", dps=25, max_dps=60)
    assert r.on_boundary and not r.stable and r.lam == 0 and r.certified_digits is None


def test_unreachable_precision_is_one_line():
    # 1e-45 above a_0(0.2): at most 40 working digits cannot tell the side, and
    # |u| ~ 1e-45 is not below 10^-(2 dps): a PrecisionError, not "on the curve"
    with mpmath.workdps(110):
        t0 = mpmath.nstr(mathieu_a(0, "0.2", dps=105, method="mpmath") + mpmath.mpf("1e-45"), 100)
    from pendulab.errors import PrecisionError
    with pytest.raises(PrecisionError) as exc:
        characteristic_exponent(t0, "-0.2", dps=25, max_dps=40)
    assert "method 'arb'" in str(exc.value) and "\n" not in str(exc.value)
    r = characteristic_exponent(t0, "-0.2", dps=25)      # the default ceiling resolves it
    assert r.stable and not r.on_boundary and r.certified_digits == 25


def test_huge_q_is_certified_and_agrees_with_hill():
    r = characteristic_exponent("-0.01", "1.49e4", dps=30)
    h = characteristic_exponent("-0.01", "1.49e4", dps=30, method="hill")
    assert r.certified_digits == 30 and r.stable == h.stable and r.band_edge == h.band_edge
    with mpmath.workdps(40):
        assert abs(r.lam - h.lam) < mpmath.mpf(10) ** -28 * abs(h.lam)
    with pytest.raises(InputError, match="too large for method 'arb'"):
        characteristic_exponent("-0.01", "2e4", dps=30, method="arb")
    # beyond the ball route's size the default with dps is Hill's determinant, as before
    big = characteristic_exponent("-0.01", "1e5", dps=20)
    assert big.method == "hill" and big.certified_digits is None


# -- characteristic values and the band -----------------------------------------------

def test_a0_certified_digits_are_the_published_ones():
    for q in ("1", "-1"):
        v = mathieu_a(0, q, dps=50)
        assert _rounded(v, 50) == _rounded(A0_Q1, 50)


@pytest.mark.parametrize("key,ref", sorted(ZHANG_JIN_Q25.items()))
def test_certified_values_at_q25_match_zhang_jin_and_the_mpmath_route(key, ref):
    kind, m = key
    f = mathieu_a if kind == "a" else mathieu_b
    v = f(m, 25, dps=40)
    assert abs(float(v) - float(ref)) <= 1.5e-9
    w = f(m, 25, dps=40, method="mpmath")
    with mpmath.workdps(50):
        assert abs(v - w) <= mpmath.mpf(10) ** -38 * max(1, abs(w))


def test_values_at_1000_digits_and_huge_q_agree_with_mpmath():
    v, w = mathieu_b(1, "1/3", dps=1000), mathieu_b(1, "1/3", dps=1000, method="mpmath")
    with mpmath.workdps(1010):
        assert abs(v - w) < mpmath.mpf(10) ** -998
    v, w = mathieu_a(1, 10000, dps=30), mathieu_a(1, 10000, dps=30, method="mpmath")
    with mpmath.workdps(40):
        assert abs(v - w) < mpmath.mpf(10) ** -26 * abs(w)
    with pytest.raises(InputError, match="method"):
        mathieu_a(0, 1, dps=10, method="flint")


@pytest.mark.parametrize("theta0", ["-0.01", "-1/25", "0.5", "-4"])
def test_first_band_certified_against_mpmath_and_on_the_curves(theta0):
    lo, up = band = first_band(theta0, dps=40)
    assert band.certified_digits == 40
    ref = first_band(theta0, dps=40, method="mpmath")
    assert ref.certified_digits is None
    with mpmath.workdps(50):
        for a, b in zip(band, ref):
            assert abs(a - b) <= mpmath.mpf(10) ** -38 * max(1, abs(b))
        x0 = mpmath.mpf(Fraction(theta0).numerator) / Fraction(theta0).denominator
        assert abs(mathieu_b(1, up, dps=45, method="mpmath") - x0) < mpmath.mpf(10) ** -36
        if x0 < 0:
            assert abs(mathieu_a(0, lo, dps=45, method="mpmath") - x0) < mpmath.mpf(10) ** -36
        else:
            assert lo == 0


def test_arb_in_double_precision_gives_floats():
    band = first_band("-0.01", method="arb")
    assert band.certified_digits is None and all(isinstance(x, float) for x in band)
    assert band == pytest.approx(first_band("-0.01"), rel=1e-15)
    assert mathieu_a(0, 1, method="arb") == pytest.approx(mathieu_a(0, 1), rel=1e-15)
    r = characteristic_exponent("-0.002", "0.2", method="arb")
    assert isinstance(r.lam, float) and r.certified_digits is None


def test_stability_limits_certified_at_200_digits():
    lim = stability_limits("1/10", 1, dps=200)
    ref = stability_limits("1/10", 1, dps=200, method="mpmath")
    assert lim.certified_digits == 200 and ref.certified_digits is None
    with mpmath.workdps(210):
        assert all(abs(a - b) < mpmath.mpf(10) ** -199 for a, b in zip(lim, ref))
    # a ratio given as a float is exact too (its binary value)
    assert stability_limits(0.1, "4/3", dps=20).certified_digits == 20


@pytest.mark.parametrize("inertia_ratio", [1.0, 4 / 3])
def test_double_limits_are_the_correctly_rounded_ends(inertia_ratio):
    """stability_limits in double precision (the default, the arb route): each end is
    the double nearest to the exact end; the reference is the independent mpmath route
    at 40 digits, rounded to double by mpmath."""
    for ratio in (0.0, 0.05, 0.35, 0.6, 1.0, 5.0):
        got = stability_limits(ratio, inertia_ratio)
        ref = stability_limits(ratio, inertia_ratio, dps=40, method="mpmath")
        assert got.certified_digits is None and all(isinstance(x, float) for x in got)
        assert tuple(got) == tuple(float(x) for x in ref), ratio


def test_double_limits_fall_back_on_mpmath_when_nothing_is_proved(monkeypatch):
    from pendulab.analyses.floquet import _charvalues
    ref = stability_limits(0.15, 1, method="mpmath")
    _charvalues._ENDS.clear()
    monkeypatch.setattr(_arb, "band_end_guess", lambda family, x: None)
    assert stability_limits(0.15, 1) == ref
    with pytest.raises(PrecisionError):
        stability_limits(0.15, 1, method="arb")
    _charvalues._ENDS.clear()


def test_nearest_double_only_where_the_ball_proves_it():
    from flint import arb, ctx
    saved = ctx.prec
    try:
        ctx.prec = 200
        assert _arb.nearest_double(arb(1) / 3) == 1 / 3
        assert _arb.nearest_double(-(arb(2).sqrt())) == -(2 ** 0.5)
        assert _arb.nearest_double(arb(0)) == 0.0
        # a ball around the midpoint of 1 and its successor 1 + 2^-52 proves neither
        mid = arb(1) + arb(2) ** -53
        assert _arb.nearest_double(mid + arb(0, 2.0 ** -120)) is None
        assert _arb.nearest_double(mid + arb(2) ** -100) == 1 + 2 ** -52
    finally:
        ctx.prec = saved


# -- the hand kernels against the derivation and an eigensolver --------------------------

def _lambdified(depth):
    from pendulab.analyses import phelps_hunter as ph
    from pendulab import symbols as S
    args = (ph.lam, S.theta0, S.theta1)
    eq = sp.lambdify(args, ph.lambda_equation(depth), "mpmath")
    deq = sp.lambdify(args, sp.diff(ph.lambda_equation(depth), ph.lam), "mpmath")
    H = ph.hill_matrix(depth)
    cs = sp.Mul(*[ph.C(k) for k in range(-depth, depth + 1)])
    det = sp.lambdify(args, H.det(method="berkowitz") * cs, "mpmath")
    return eq, deq, det


@pytest.mark.parametrize("u", ["0.0183", "0.3", "-0.75", "-40"])
def test_cf_kernel_is_the_derived_characteristic_equation(u):
    # block M = 0 closed by N levels each side (zero tails) is the source's truncated
    # equation C_0 + theta1 (b_1 + b_-1)/b_0 (000 eq. 10, b_(+-(N+1)) = 0); a block of
    # M = 2N with no tail is the determinant of the (2N+1) recurrence rows
    N = 3
    eq, deq, det = _lambdified(N)
    with mpmath.workdps(40):
        uu = mpmath.mpf(u)
        lam = mpmath.sqrt(uu) if uu >= 0 else mpmath.mpc(0, mpmath.sqrt(-uu))
        x0, x1 = mpmath.mpf("-0.3"), mpmath.mpf("0.7")
        with _arb._Prec(140):
            ub, x0b, x1b = (_arb.arb(str(v)) for v in (u, "-0.3", "0.7"))
            A, B, dA = _arb.cf_kernel(ub, x0b, x1b, 0, N)
            A2, B2, _ = _arb.cf_kernel(ub, x0b, x1b, 2 * N, 0)
            tb = ub.sqrt() if uu >= 0 else 0
            val, dval = mpmath.mpf((A + B * tb).mid().str(35, radius=False)), mpmath.mpf(
                dA.mid().str(35, radius=False))
            val2 = mpmath.mpf((A2 + B2 * tb).mid().str(35, radius=False))
        ref = eq(lam, x0, x1)
        assert abs(mpmath.im(ref)) < 1e-30 * (1 + abs(ref))
        assert abs(val - mpmath.re(ref)) < 1e-30 * (1 + abs(ref))
        # d/du = (d/dlam) / (2 lam), real for either sign of u
        dref = deq(lam, x0, x1) / (2 * lam)
        assert abs(dval - mpmath.re(dref)) < 1e-28 * (1 + abs(dref))
        dref2 = det(lam, x0, x1)
        assert abs(val2 - mpmath.re(dref2)) < 1e-28 * (1 + abs(dref2))
        # the real-t kernel (band Newton steps and the proof): g(t) and dg/dt, t = lam;
        # with complex balls at t = i s (the proof in a gap)
        with _arb._Prec(140):
            if uu >= 0:
                g, dg = _arb.cf_kernel_t(ub.sqrt(), x0b, x1b, 0, N)
                gv = mpmath.mpf(g.mid().str(35, radius=False))
                dgv = mpmath.mpf(dg.mid().str(35, radius=False))
                assert abs(dgv - mpmath.re(deq(lam, x0, x1))) < 1e-28 * (1 + abs(dgv))
            else:
                t = _arb.acb(0, (-ub).sqrt())
                g, _ = _arb.cf_kernel_t(t, _arb.acb(x0b), _arb.acb(x1b), 0, N, deriv=False)
                assert abs(g.imag).upper() < _arb.arb(10) ** -30 * (1 + abs(g.real).upper())
                gv = mpmath.mpf(g.real.mid().str(35, radius=False))
        assert abs(gv - mpmath.re(ref)) < 1e-30 * (1 + abs(ref))
        # the same kernel in floats (the guess) agrees to double precision
        fA, fB, _ = _arb.cf_kernel(float(u), -0.3, 0.7, 0, N)
        tf = float(abs(uu)) ** 0.5 if uu >= 0 else 0.0
        assert abs(fA + fB * tf - float(val)) < 1e-12 * (1 + abs(float(val)))


def _eigs(family, q, n):
    with mpmath.workdps(40):
        d, e2 = [], []
        for j in range(n):
            d.append({"a_even": (2 * j) ** 2, "b_even": (2 * j + 2) ** 2}.get(family, (2 * j + 1) ** 2))
        if family == "a_odd":
            d[0] += q
        if family == "b_odd":
            d[0] -= q
        A = mpmath.zeros(n, n)
        for j in range(n):
            A[j, j] = d[j]
        for j in range(n - 1):
            off = q * (mpmath.sqrt(2) if (family == "a_even" and j == 0) else 1)
            A[j, j + 1] = A[j + 1, j] = off
        return sorted(mpmath.eigsy(A, eigvals_only=True))


@pytest.mark.parametrize("family", ["a_even", "a_odd", "b_odd", "b_even"])
@pytest.mark.parametrize("q", [-7, 3, 30])
def test_ball_sturm_count_is_the_eigenvalue_count_of_the_infinite_matrix(family, q):
    ev = _eigs(family, q, 30)
    for x in (-80, -3.5, 0.25, 7, 50, 140):
        with _arb._Prec(100):
            got = _arb.family_count(family, _arb.arb(q), _arb.arb(x))
        assert got == sum(1 for v in ev if v < x)
