"""Each proof step of the ball-arithmetic engines is handed a wrong candidate and refuses it.

The engines: the band count and the Sturm counts (pendulab.analyses.floquet._arb), the
continued-fraction tails and the sign change that bracket u = (lam - e)^2, the digits a ball
proves, the characteristic values and the first band's ends, and the adaptive-precision loop
that accepts an answer (pendulab.analyses.floquet._precision).  Each step was switched off
once (made to pass always) and the test that guards it was seen to fail; docs/certificates.md
lists them.

References, independent of the code under test:
* the eigenvalues of the truncated DLMF 28.4.5-28.4.8 matrices (60 rows, far past where the
  eigenvalues asked for move) by mpmath.eigsy at 50 digits;
* the block determinant of 000 eq. 10 closed by 400 continued-fraction levels each side,
  evaluated in plain mpmath at 60 digits (the neglected tail is below 10^-1000 there);
* the trace of the monodromy matrix of 000 eq. 7 over one period pi, integrated by
  mpmath.odefun (Taylor series) at 40 digits: 2 cos(pi lam).
"""

import functools
from fractions import Fraction

import mpmath
import pytest
from flint import acb, arb, ctx

from pendulab.analyses.floquet import _arb, characteristic_exponent
from pendulab.errors import PrecisionError


@pytest.fixture(autouse=True)
def _flint_precision():
    saved = ctx.prec
    yield
    ctx.prec = saved


# -- independent references ----------------------------------------------------------------

# MathieuCharacteristicA[0, 1] to 56 digits (Wolfram|Alpha, the same value as the q = -1
# reference of tests/test_floquet_arb.py; a_0 is even in q, DLMF 28.2.26)
A0_Q1_TEXT = "-0.45513860410741354823263318752888586691651984219666547103"


@functools.lru_cache(maxsize=None)
def family_eigenvalues(family, q, n=60, dps=50):
    """Sorted eigenvalues of the n-row DLMF 28.4 matrix of ``family`` at q (a decimal string),
    by mpmath.eigsy (the a_even matrix symmetrised by sqrt 2 in its first off-diagonal)."""
    with mpmath.workdps(dps):
        q = mpmath.mpf(q)
        A = mpmath.zeros(n)
        for i in range(n):
            if family == "a_even":
                d = (2 * i) ** 2
            elif family == "b_even":
                d = (2 * i + 2) ** 2
            else:
                d = mpmath.mpf((2 * i + 1) ** 2)
                if i == 0:
                    d += q if family == "a_odd" else -q
            A[i, i] = d
            if i:
                A[i, i - 1] = A[i - 1, i] = q * (mpmath.sqrt(2) if family == "a_even" and i == 1
                                                 else 1)
        return tuple(sorted(mpmath.eigsy(A, eigvals_only=True)))


def deep_block_value(th0, th1, u, M, depth=400, dps=60):
    """f_e(u) of 000 eq. 10: the block m = -M, -M+2, ..., M of theta1 b_{m-2} +
    (theta0 - (m + t)^2) b_m + theta1 b_{m+2} = 0 (t^2 = u), closed on each side by the
    continued fraction of the minimal solution taken ``depth`` levels deep."""
    with mpmath.workdps(dps):
        th0, th1, u = mpmath.mpf(th0), mpmath.mpf(th1), mpmath.mpf(u)
        t = mpmath.sqrt(u) if u >= 0 else mpmath.mpc(0, mpmath.sqrt(-u))

        def C(m):
            return th0 - (m + t) ** 2
        right = left = 0
        for m in range(M + 2 * depth, M, -2):
            right = -th1 / (C(m) + th1 * right)
        for m in range(-M - 2 * depth, -M, 2):
            left = -th1 / (C(m) + th1 * left)
        d = [C(m) for m in range(-M, M + 1, 2)]
        d[0] += th1 * left
        d[-1] += th1 * right
        before, p = 1, d[0]
        for dj in d[1:]:
            before, p = p, dj * p - th1 ** 2 * before
        return mpmath.re(p)


@functools.lru_cache(maxsize=None)
def monodromy_trace(th0, th1, dps=40):
    """2 cos(pi lam): the trace of the monodromy matrix of 000 eq. 7 over [0, pi]."""
    with mpmath.workdps(dps):
        a, b = mpmath.mpf(th0), mpmath.mpf(th1)

        def rhs(t, y):
            return [y[1], -(a + 2 * b * mpmath.cos(2 * t)) * y[0]]
        first = mpmath.odefun(rhs, 0, [1, 0])(mpmath.pi)
        second = mpmath.odefun(rhs, 0, [0, 1])(mpmath.pi)
        return first[0] + second[1]


def ball(text):
    """The decimal ``text`` as a ball at the current precision."""
    return arb(text)


def point(x):
    """An exact input (Fraction) as a ball."""
    return _arb.to_ball(Fraction(x))


# -- the band count: Sturm counts of the four infinite matrices on balls --------------------

def test_band_count_refuses_a_theta0_ball_that_holds_a_characteristic_value():
    """theta0 within 10^-40 of a_0(q), q = -theta1 = 1: a ball of radius 10^-40 around it has
    no decided count; the points 3 * 10^-40 below and above it count 0 and 1."""
    ctx.prec = 300
    a0 = family_eigenvalues("a_even", "1")[0]
    with mpmath.workdps(60):
        centre = ball(mpmath.nstr(a0, 55))
        assert abs(a0 - mpmath.mpf(A0_Q1_TEXT)) < mpmath.mpf(10) ** -45
    x1 = point(-1)
    eps = arb(10) ** -40
    assert _arb.band_count(centre + arb(0, 1) * eps, x1) is None
    assert _arb.band_count(centre - 3 * eps, x1) == 0
    assert _arb.band_count(centre + 3 * eps, x1) == 1
    assert _arb.family_count("a_even", point(1), centre + arb(0, 1) * eps) is None


@pytest.mark.parametrize("family,q,x", [
    ("a_even", "20", "3"),      # a pivot past |q| at row 1, but d_2 - x < 2|q|: rows remain
    ("b_odd", "20", "3"),
    ("a_even", "20", "-30"),    # d_2 - x > 2|q| at row 1, but the pivot there is below |q|
    ("a_even", "20", "150"),
    ("b_even", "20", "150"),
])
def test_sturm_count_goes_on_until_every_later_pivot_is_positive(family, q, x):
    """The count stops at row n only when p_n > |q| and d_{n+1} - x > 2|q| (then every later
    pivot exceeds |q|).  At these points either half of the rule alone stops too early and
    misses an eigenvalue below x."""
    ctx.prec = 200
    expected = sum(1 for e in family_eigenvalues(family, q) if e < mpmath.mpf(x))
    assert _arb.family_count(family, point(q), point(x)) == expected


@pytest.mark.parametrize("family,q,x", [("a_even", "1", "0"), ("b_odd", "1", "0"),
                                         ("a_odd", "-1", "0"), ("b_even", "1", "4")])
def test_sturm_count_reads_an_exactly_zero_pivot_as_its_limit(family, q, x):
    """x exactly the first diagonal entry (0, 1 - q = 0, 1 + q = 0, 4) makes the first pivot
    exactly 0: the count is that of the eigenvalues below x all the same (one of them, a_0(1),
    b_1(1), a_1(-1), b_2(1) below it), not a refusal and not a count off by one."""
    ctx.prec = 200
    expected = sum(1 for e in family_eigenvalues(family, q) if e < mpmath.mpf(x))
    assert expected == 1
    assert _arb.family_count(family, point(q), point(x)) == expected


# -- the continued-fraction tails -----------------------------------------------------------

@pytest.mark.parametrize("u,threshold", [
    ("0.01", Fraction(1521, 200)),   # u > 0, t = 0.1: (4 - t)^2 = 15.21 = 2|theta1|
    ("-0.01", Fraction(1599, 200)),  # u < 0, s = 0.1: 4^2 - s^2 = 15.99 = 2|theta1|
    ("-25", Fraction(20)),           # u < 0, s = 5: the imaginary part, 4 s = 20 = 2|theta1|
])
def test_tail_condition_refuses_a_theta1_five_percent_past_its_bound(u, threshold):
    """The tail ratios lie in the unit disk only where |C_j| >= 2|theta1| for every j beyond
    the last level (j = 4 here, theta0 = 0): 5 % past the bound is refused, 5 % inside
    accepted; a bound 10 times looser would accept both."""
    ctx.prec = 200
    U, x0 = point(u), point(0)
    assert not _arb._tail_ok(4, U, x0, point(threshold * Fraction(105, 100)))
    assert not _arb._tail_ok(4, U, x0, point(-threshold * Fraction(105, 100)))
    assert _arb._tail_ok(4, U, x0, point(threshold * Fraction(95, 100)))
    assert _arb._tail_ok(4, U, x0, point(-threshold * Fraction(95, 100)))


def _disk_ball_without_the_check(u, x0, x1, M, T):
    """What _value_ball would return if its tail condition were not checked."""
    if u > 0:
        g, _ = _arb.cf_kernel_t(u.sqrt(), x0, x1, M, T, tails=(arb(0, 1), arb(0, 1)),
                                deriv=False)
        return g
    disk = acb(arb(0, 1), arb(0, 1))
    g, _ = _arb.cf_kernel_t(acb(0, (-u).sqrt()), acb(x0), acb(x1), M, T, tails=(disk, disk),
                            deriv=False)
    return g.real


@pytest.mark.parametrize("th0,th1,u,M", [("0", "3", "0.1", 0), ("1", "8", "0.1", 1),
                                         ("0", "30", "0.1", 2)])
def test_value_ball_refuses_a_tail_too_short_for_the_unit_disk(th0, th1, u, M):
    """No level kept (T = 0) at large theta1: the neglected ratio need not lie in the unit
    disk, and here it does not -- the ball the disk would give misses the true f_e(u).  The
    tail check refuses it."""
    ctx.prec = 200
    x0, x1, U = point(th0), point(th1), point(u)
    truth = ball(mpmath.nstr(deep_block_value(th0, th1, u, M), 50))
    assert not _disk_ball_without_the_check(U, x0, x1, M, 0).overlaps(truth)   # a wrong ball
    assert _arb._value_ball(U, x0, x1, M, 0) is None


@pytest.mark.parametrize("u", ["0.01", "-0.01"])
def test_value_ball_holds_the_deep_fraction_and_a_dropped_tail_does_not(u):
    """theta0 = -0.002, theta1 = 0.2, block M = 4 with 2 levels kept: the ball carrying the
    unit disk for the neglected tail contains f_e(u) of the 400-level fraction; the same
    levels with the tail dropped (set to 0) give a ball that misses it."""
    ctx.prec = 200
    x0, x1, U = point("-0.002"), point("0.2"), point(u)
    truth = ball(mpmath.nstr(deep_block_value("-0.002", "0.2", u, 4), 50))
    got = _arb._value_ball(U, x0, x1, 4, 2)
    assert got is not None and got.contains(truth)
    assert got.rad() < 1e-2 * abs(truth.mid())
    if U > 0:
        dropped, _ = _arb.cf_kernel_t(U.sqrt(), x0, x1, 4, 2, deriv=False)
    else:
        dropped = _arb.cf_kernel_t(acb(0, (-U).sqrt()), acb(x0), acb(x1), 4, 2,
                                   deriv=False)[0].real
    assert not dropped.overlaps(truth)


# -- the sign change that brackets u = (lam - e)^2 ------------------------------------------

X0, X1 = Fraction(-2, 1000), Fraction(2, 10)     # band 0 (the source's Fig. 2 point)
GAP = (Fraction(1), Fraction(1, 2))               # gap 1: lam = 1 + i mu


def _lam_band0():
    """lam of (X0, X1) from the monodromy trace: cos(pi lam) = trace / 2, lam in (0, 1)."""
    with mpmath.workdps(40):
        return mpmath.acos(monodromy_trace("-0.002", "0.2") / 2) / mpmath.pi


def _prove_at(um, count=1, band=True, r0="1e-40"):
    prec = _arb.bits_of(30) + _arb.loss_bits(float(X0), float(X1))
    with _arb._Prec(prec + 16):
        return _arb._prove(X0, X1, count, 0, band, arb(um), arb(r0), arb(r0), prec,
                           float(X0), float(X1), arb(1000))


def test_certified_lambda_ball_holds_the_monodromy_value():
    ctx.prec = 200
    lam_ref = _lam_band0()
    lam, U, _ = _arb.certify(X0, X1, 1, 0, 0.0183, 30)
    with mpmath.workdps(40):
        assert lam.contains(ball(mpmath.nstr(lam_ref, 38)))
        assert U.contains(ball(mpmath.nstr(lam_ref ** 2, 38)))
    assert lam.rad() < arb(10) ** -30


@pytest.mark.parametrize("offset", ["0.01", "-0.01", "1e-12"])
def test_sign_change_refuses_a_bracket_beside_the_root(offset):
    """The proof's bracket around a candidate u that is not the root (off by ``offset``,
    start half-width 10^-40, widened by 2^10 at most five times) never changes sign: no
    lam is returned, where a bracket believed without the sign test would give a ball that
    misses the true lam."""
    ctx.prec = 200
    with mpmath.workdps(40):
        u_true = _lam_band0() ** 2
        um = mpmath.nstr(u_true + mpmath.mpf(offset), 40)
    assert _prove_at(um) is None
    got = _prove_at(mpmath.nstr(u_true, 40))      # the root itself passes
    assert got is not None


def test_sign_change_is_looked_for_only_on_the_side_the_count_names():
    """A band point (u > 0) with the count of a gap (u < 0 asked), and a gap point with the
    count of a band: no ball -- not the root on the other side, nor the square root of a
    negative ball."""
    ctx.prec = 200
    assert _arb.certify(X0, X1, 0, 0, -0.0183, 30) is None
    assert _arb.certify(*GAP, 3, 1, 0.0591, 30) is None
    assert _arb.certify(*GAP, 2, 1, -0.0591, 30) is not None       # the right count passes


@pytest.mark.parametrize("e,u0", [(2, 0.0183), (-1, 0.748), (-2, 0.0183)])
def test_sign_change_refuses_an_edge_the_band_count_does_not_name(e, u0):
    """Band 0 (count 1) names the edges 0 and 1 only.  f_e depends on e only through its
    parity, so edge 2 has the same root u = t^2 and edge -1 the root (1 - t)^2: read with
    lam = e -+ sqrt(u) they gave "proved" balls 1.8648 and -1.8648, which miss the
    monodromy value 0.1352 of the band.  Refused; the edges 0 and 1 give balls that hold it."""
    ctx.prec = 200
    lam_ref = _lam_band0()
    assert _arb.certify(X0, X1, 1, e, u0, 30) is None
    with mpmath.workdps(40):
        ref = ball(mpmath.nstr(lam_ref, 38))
    for edge, start in ((0, 0.0183), (1, 0.748)):
        lam, _, _ = _arb.certify(X0, X1, 1, edge, start, 30)
        assert lam.contains(ref)


def test_gap_proof_refuses_an_edge_the_gap_count_does_not_name():
    """Gap 1 (count 2) has lam = 1 + i mu: edge 3 (the same parity) finds the same mu and
    would report lam = 3 + i mu; refused."""
    ctx.prec = 200
    assert _arb.certify(*GAP, 2, 3, -0.0591, 30) is None
    assert _arb.certify(*GAP, 2, 1, -0.0591, 30) is not None


def test_gap_ball_holds_the_monodromy_value():
    """Gap 1 at (1, 1/2): lam = 1 + i mu, cos(pi lam) = -cosh(pi mu) = trace / 2."""
    ctx.prec = 200
    mu, U, _ = _arb.certify(*GAP, 2, 1, -0.0591, 30)
    with mpmath.workdps(40):
        ref = mpmath.acosh(-monodromy_trace("1", "0.5") / 2) / mpmath.pi
        assert mu.contains(ball(mpmath.nstr(ref, 38)))
    assert mu.rad() < arb(10) ** -30


# -- the digits a ball proves -----------------------------------------------------------------

def test_lam_text_refuses_a_ball_whose_ends_round_apart():
    """0.1234567890|5 is the tie between two 10-digit decimals: a ball around it of radius
    3 * 10^-16 (3 times its distance to the tie, 10^-16 above) has ends that round apart; the
    same ball moved to 10^-15 above the tie (3 times its radius) proves the upper decimal."""
    ctx.prec = 200
    tie = ball("0.12345678905")
    r = arb(10) ** -16
    assert _arb.lam_text(tie + r + arb(0, 1) * 3 * r, 10) is None
    assert _arb.lam_text(tie - r + arb(0, 1) * 3 * r, 10) is None
    assert _arb.lam_text(tie + 10 * r + arb(0, 1) * 3 * r, 10) == "0.1234567891"
    assert _arb.lam_text(tie - 10 * r + arb(0, 1) * 3 * r, 10) == "0.1234567890"


def test_exponent_refuses_digits_its_ball_does_not_prove(monkeypatch):
    """A proof that returns a ball 10^-20 wide when 30 digits are asked: no text at any
    working precision, and characteristic_exponent raises instead of printing them."""
    ctx.prec = 200
    real = _arb.certify

    def wide(*args, **kwargs):
        got = real(*args, **kwargs)
        if got is None:
            return None
        lam, U, depth = got
        return lam + arb(0, 1) * arb(10) ** -20, U, depth
    monkeypatch.setattr(_arb, "certify", wide)
    assert _arb.exponent_at(X0, X1, 30, 40) is None
    with pytest.raises(PrecisionError, match="cannot prove the digits"):
        characteristic_exponent("-0.002", "0.2", dps=30, max_dps=100)


def test_certified_digits_are_the_correctly_rounded_ones_of_the_monodromy_value():
    r = characteristic_exponent("-0.002", "0.2", dps=30)
    assert r.certified_digits == 30
    with mpmath.workdps(40):
        assert mpmath.nstr(r.lam, 30) == mpmath.nstr(_lam_band0(), 30)


# -- characteristic values and the ends of the first band: two Sturm counts ----------------

def _shifted_newton(monkeypatch, shift=None, start=None, scale=None):
    """_newton_on_pivots made to return a wrong candidate: its own root moved by ``shift``,
    multiplied by ``scale``, or Newton's iteration begun at ``start`` (another root)."""
    real = _arb._newton_on_pivots

    def wrong(family, q, x, n, bits_list, var_is_q, begin):
        got = real(family, q, x, n, bits_list, var_is_q, begin if start is None else start)
        v, delta = got
        with _arb._Prec(bits_list[-1] + 16):
            if shift is not None:
                v = v + arb(shift)
            if scale is not None:
                v = v * arb(scale)
        return v, delta
    monkeypatch.setattr(_arb, "_newton_on_pivots", wrong)


def test_char_value_ball_holds_the_eigensolver_value():
    ctx.prec = 200
    text, got = _arb.char_value_at("a_even", 0, Fraction(1), 30, 40)
    with mpmath.workdps(50):
        ref = family_eigenvalues("a_even", "1")[0]
        assert got.contains(ball(mpmath.nstr(ref, 48)))
        assert text == mpmath.nstr(ref, 30)


@pytest.mark.parametrize("shift", ["1e-20", "-1e-20"])
def test_char_value_refuses_a_candidate_beside_the_eigenvalue(monkeypatch, shift):
    """A candidate 10^-20 off a_0(1), 30 digits asked: the Sturm counts at the ends of every
    bracket tried (at most 2^40 times 10^-40 wide) are not 0 and 1."""
    _shifted_newton(monkeypatch, shift=shift)
    assert _arb.char_value_at("a_even", 0, Fraction(1), 30, 40) is None


def test_char_value_refuses_the_neighbouring_eigenvalue(monkeypatch):
    """Newton's iteration begun at the double nearest to a_2(1) = 4.3713... (eigensolver)
    when a_0 is asked (a shifted index): the counts there are 1 and 2, and no ball is
    returned; the same candidate proves a_2 when a_2 is asked."""
    _shifted_newton(monkeypatch, start=float(family_eigenvalues("a_even", "1")[1]))
    assert _arb.char_value_at("a_even", 0, Fraction(1), 30, 40) is None
    ctx.prec = 200
    text, got = _arb.char_value_at("a_even", 1, Fraction(1), 30, 40)   # it is a_2
    with mpmath.workdps(50):
        assert got.contains(ball(mpmath.nstr(family_eigenvalues("a_even", "1")[1], 48)))


def test_mathieu_a_by_arb_raises_where_nothing_is_proved_and_the_default_falls_back(monkeypatch):
    """Every candidate wrong: method "arb" asked raises PrecisionError (no digits claimed);
    the default route falls back on the mpmath route, which gives the published value."""
    from pendulab.analyses.floquet import mathieu_a
    _shifted_newton(monkeypatch, shift="1e-8")
    with pytest.raises(PrecisionError):
        mathieu_a(0, 1, dps=30, method="arb")
    with mpmath.workdps(40):
        assert abs(mathieu_a(0, 1, dps=30) - mpmath.mpf(A0_Q1_TEXT)) < mpmath.mpf(10) ** -30


def _a0_at(q_text):
    return family_eigenvalues("a_even", q_text)[0]


def test_band_end_ball_holds_the_crossing_and_refuses_a_moved_one(monkeypatch):
    """theta0 = -1/100: the ball [q_lo, q_hi] of the lower end of the first band has
    a_0(q_lo) >= theta0 > a_0(q_hi) by the eigensolver (a_0 decreases in q > 0); a candidate
    moved by 10^-20 of itself is refused."""
    ctx.prec = 200
    X = Fraction(-1, 100)
    start = _arb.band_end_guess("a_even", float(X))
    got, _ = _arb.band_end_ball("a_even", X, 40, start)
    with mpmath.workdps(50):
        lo, hi = (mpmath.nstr(mpmath.mpf(v.str(60, radius=False)), 50)
                  for v in (arb(got.lower()), arb(got.upper())))
        assert _a0_at(lo) >= mpmath.mpf(X.numerator) / X.denominator > _a0_at(hi)
    assert got.rad() < arb(10) ** -38
    _shifted_newton(monkeypatch, scale="1.00000000000000000001")
    assert _arb.band_end_ball("a_even", X, 40, start) is None


def test_nearest_double_refuses_a_ball_across_a_rounding_tie():
    """1 + 2^-53 is the tie between 1 and its successor: a ball 3 * 2^-60 wide around a point
    2^-60 above the tie rounds both ways and proves no double; moved 2^-57 above (or below)
    it proves the successor (or 1)."""
    ctx.prec = 200
    tie = arb(1) + arb(2) ** -53
    r = arb(2) ** -60
    assert _arb.nearest_double(tie + r + arb(0, 1) * 3 * r) is None
    assert _arb.nearest_double(tie + 8 * r + arb(0, 1) * 3 * r) == 1 + 2 ** -52
    assert _arb.nearest_double(tie - 8 * r + arb(0, 1) * 3 * r) == 1.0


def test_first_band_by_arb_in_double_precision_raises_where_no_double_is_proved(monkeypatch):
    from pendulab.analyses.floquet import _charvalues, first_band
    _charvalues._ENDS.clear()
    monkeypatch.setattr(_arb, "nearest_double", lambda b: None)
    with pytest.raises(PrecisionError, match="not proved to double precision"):
        first_band("-1/100", method="arb")
    lo, up = first_band("-1/100")           # the default falls back on the mpmath route
    assert abs(lo - 0.1415759161) < 1e-10 and abs(up - 0.9164371642) < 1e-10
    _charvalues._ENDS.clear()


# -- the branch points of a_m(q), b_m(q) ------------------------------------------------------

@pytest.fixture
def a0_point():
    from pendulab.analyses import mathieu_branch as mb
    return mb.branch_point("a0", digits=30)


@pytest.mark.parametrize("which", ["q", "a"])
def test_branch_point_check_refuses_a_candidate_three_times_past_its_tolerance(a0_point, which):
    """digits = 20: q or a moved by 3 * 10^-20 of itself is refused by the size of Newton's
    correction; a moved by 3 * 10^-21 passes (a tolerance 10 times looser would let 3 * 10^-20
    through the Newton test, and q's would then be refused for its pair, not its correction)."""
    from pendulab.analyses import mathieu_branch as mb
    from pendulab.errors import ConvergenceError
    p = a0_point
    with mpmath.workdps(40):
        bad = 1 + 3 * mpmath.mpf(10) ** -20
        q, a = (p.q * bad, p.a) if which == "q" else (p.q, p.a * bad)
        with pytest.raises(ConvergenceError, match="Newton's correction"):
            mb.check_branch_point("a0", q, a, digits=20)
        rel = mb.check_branch_point("a0", p.q, p.a * (1 + 3 * mpmath.mpf(10) ** -21), digits=20)
        assert 1e-21 < rel < 1e-20


def test_branch_point_pair_test_refuses_eigenvalues_three_times_too_far_apart(a0_point):
    """q moved by 3 * 10^-21: Newton's correction (3e-21) passes at 20 digits, but the two
    eigenvalues nearest to a_b are c sqrt(3e-21 |q|) = 3.1e-10 apart, 1.5 times the
    10^-10 |a_b| = 2.1e-10 allowed; moved by 3 * 10^-23 they are 3.1e-11 apart and pass."""
    from pendulab.analyses import mathieu_branch as mb
    from pendulab.errors import ConvergenceError
    p = a0_point
    with mpmath.workdps(40):
        with pytest.raises(ConvergenceError, match="apart"):
            mb.check_branch_point("a0", p.q * (1 + 3 * mpmath.mpf(10) ** -21), p.a, digits=20)
        mb.check_branch_point("a0", p.q * (1 + 3 * mpmath.mpf(10) ** -23), p.a, digits=20)


def test_branch_point_refuses_two_truncations_that_disagree(monkeypatch, a0_point):
    """_refine's second Newton (2N rows, digits + 22) made to land 3 * 10^-(digits + 2) of
    |q| away from the first: refused; 3 * 10^-(digits + 3) away: accepted."""
    from pendulab.analyses import mathieu_branch as mb
    from pendulab.errors import ConvergenceError
    p = a0_point
    real = mb._newton_mp
    moved = {}

    def second_moved(rows, a, q, digits, iterations=30):
        a, q = real(rows, a, q, digits, iterations)
        moved["n"] = moved.get("n", 0) + 1
        if moved["n"] == 2:
            q = q * (1 + moved["by"])
        return a, q
    monkeypatch.setattr(mb, "_newton_mp", second_moved)
    for by, refused in (("3e-17", True), ("3e-18", False)):
        moved.clear()
        moved["by"] = mpmath.mpf(by)
        if refused:
            with pytest.raises(ConvergenceError, match="changes with the truncation"):
                mb._refine("a", 0, complex(p.q), complex(p.a), 15)
        else:
            mb._refine("a", 0, complex(p.q), complex(p.a), 15)


def test_branch_point_refuses_a_refined_point_that_fails_the_check(monkeypatch):
    """The point _refine returns moved by 10^-12 of itself: the final check refuses it and
    no radius is returned."""
    from pendulab.analyses import mathieu_branch as mb
    from pendulab.errors import ConvergenceError
    real = mb._refine

    def moved(letter, m, q0, a0, digits):
        a, q, n = real(letter, m, q0, a0, digits)
        return a, q * (1 + mpmath.mpf(10) ** -12), n
    mb._branch.cache_clear()
    monkeypatch.setattr(mb, "_refine", moved)
    try:
        with pytest.raises(ConvergenceError, match="not a branch point"):
            mb.branch_point("a0", digits=12)
    finally:
        mb._branch.cache_clear()


def test_radii_table_check_sees_a_changed_digit_and_a_missing_row(monkeypatch, capsys):
    """`python -m pendulab.analyses.mathieu_branch --check` against a fresh table that differs
    from the shipped file in one digit, or lacks one kind: exit 1; the same text: exit 0."""
    from pathlib import Path
    from pendulab.analyses import mathieu_branch as mb, mathieu_radii
    shipped = Path(mathieu_radii.__file__).read_text()
    one_digit = shipped.replace('"a0": ("1.46876861378514"', '"a0": ("1.46876861378515"')
    no_row = "".join(line for line in shipped.splitlines(True) if '"b7":' not in line)
    assert one_digit != shipped and no_row != shipped
    for text, status in ((shipped, 0), (one_digit, 1), (no_row, 1)):
        monkeypatch.setattr(mb, "table_source", lambda text=text: text)
        assert mb._main(["--check"]) == status
    assert "differs from a fresh computation" in capsys.readouterr().out


@pytest.mark.parametrize("letter,m", [("a", 0), ("a", 1)])
def test_branch_point_is_put_on_the_axis_only_within_its_rounding(letter, m):
    """At dps 40 a real part up to 10^-32 |q| is rounding and the point is put on the
    imaginary axis; 3 * 10^-32 |q| is kept (a rule 10 times looser would snap it too), as is
    the image with Im q > 0 (and Re q >= 0 for the even a_0)."""
    from pendulab.analyses import mathieu_branch as mb
    with mpmath.workdps(40):
        y = mpmath.mpf("1.46876861378514")
        for by, snapped in (("0.3e-32", True), ("3e-32", False)):
            q = mpmath.mpc(mpmath.mpf(by) * y, y)
            got, _ = mb._representative(letter, m, q, mpmath.mpc(2, 0))
            assert (got.real == 0) == snapped
            assert got.imag == y
        # q = -1 - 2i: the image asked for is 1 + 2i (a_0, even in q) or -1 + 2i (a_1); the
        # even kind's image was -(conj q) = 1 - 2i, below the axis, before the order was fixed
        got, a = mb._representative(letter, m, mpmath.mpc(-1, -2), mpmath.mpc(2, 1))
        assert got == (mpmath.mpc(1, 2) if m % 2 == 0 else mpmath.mpc(-1, 2))
        assert a == (mpmath.mpc(2, 1) if m % 2 == 0 else mpmath.mpc(2, -1))
