"""Tests that kill the surviving mutants of the ball-arithmetic modules (docs/mutation.md).

Each test closes a gap that mutation testing found in pendulab.analyses.floquet._arb,
pendulab.analyses.floquet._exponent or pendulab.analyses.mathieu_branch: an edit of a proof
step or of a documented result that no other test noticed.

References, independent of the code under test:
* theta1 = 0 is the free oscillator theta'' + theta0 theta = 0, solved by exp(+-i sqrt(theta0) tau):
  lam = sqrt(theta0) (imaginary for theta0 < 0), multipliers exp(+-i pi lam); theta0 = 0 has
  the solution tau, unbounded (unstable), and theta0 = k^2 > 0 has cos k tau, sin k tau, bounded
  (FloquetResult's docstring states the same convention); computed here with plain mpmath;
* a_0(1) by mpmath.eigsy on the 60-row DLMF 28.4.5 matrix (far past where a_0 moves);
* exact binary arithmetic for the rounding of a ball to a double.
"""

import functools
from fractions import Fraction

import mpmath
import pytest
from flint import arb, ctx

from pendulab.analyses.floquet import _arb, characteristic_exponent


@pytest.fixture(autouse=True)
def _flint_precision():
    saved = ctx.prec
    yield
    ctx.prec = saved


# -- is_tiny: the bound of the "on a curve" verdict of the ball route -------------------------

def test_is_tiny_reads_the_upper_end_of_a_ball_and_includes_its_bound():
    """|u| <= 10^-digits for every point of the ball: a ball [-10^-60, 10^-60] (about) is not
    below 10^-61 though its lower end of |u| is 0, and is below 10^-59; u = 1 is within
    10^-0 (the bound is included); no estimate at all is not tiny."""
    ctx.prec = 300
    b = arb(10) ** -70 + arb(0, 1) * arb(10) ** -60
    assert _arb.is_tiny(b, 61) is False
    assert _arb.is_tiny(b, 59) is True
    assert _arb.is_tiny(1.0, 0) is True
    assert _arb.is_tiny(1.5, 0) is False
    assert _arb.is_tiny(None, 5) is False


# -- nearest_double: a radius far below half an ulp ---------------------------------------------

def test_nearest_double_of_a_ball_whose_radius_is_far_below_half_an_ulp():
    """Radius about 2^-60 around 1 and around 3/2: both ends lie within half an ulp (2^-53)
    of the centre, so the centre is the proved double; a radius about 2^-50 (more than half
    an ulp) proves none."""
    ctx.prec = 200
    assert _arb.nearest_double(arb(1, 2.0 ** -60)) == 1.0
    assert _arb.nearest_double(arb(1.5, 2.0 ** -60)) == 1.5
    assert _arb.nearest_double(arb(1.5, 2.0 ** -50)) is None


def _a0_of_q1(n=60):
    """a_0(1): lowest eigenvalue of the n-row DLMF 28.4.5 matrix (diagonal (2i)^2, off-diagonal
    q, the first one q sqrt 2 after symmetrising) by mpmath.eigsy at the current precision."""
    A = mpmath.zeros(n)
    for i in range(n):
        A[i, i] = (2 * i) ** 2
        if i:
            A[i, i - 1] = A[i - 1, i] = mpmath.sqrt(2) if i == 1 else 1
    return min(mpmath.eigsy(A, eigvals_only=True))


# -- char_value_at: no text, no answer --------------------------------------------------------

def test_char_value_at_returns_nothing_when_its_ball_does_not_prove_the_digits_asked():
    """a_0(1) at 20 working digits gives a ball about 10^-20 wide: 15 digits are proved (the
    eigensolver's value), 60 are not, and then no (text, ball) pair is returned at all."""
    ctx.prec = 200
    got = _arb.char_value_at("a_even", 0, Fraction(1), 15, 20)
    assert got is not None
    with mpmath.workdps(50):
        assert got[0] == mpmath.nstr(_a0_of_q1(), 15)
    assert _arb.char_value_at("a_even", 0, Fraction(1), 60, 20) is None


# -- theta1 = 0: the free oscillator ----------------------------------------------------------

@pytest.mark.parametrize("method", ["arb", "cf"])
@pytest.mark.parametrize("dps", [None, 30])
def test_free_exponent_below_zero_is_imaginary_with_real_multipliers(method, dps):
    """theta0 = -2: lam = i sqrt 2, multipliers exp(-+pi sqrt 2), unstable, not on a curve,
    band edge 0 (the integer nearest Re lam = 0), no truncation; the fields method and dps
    are those asked, the working precision at least dps."""
    r = characteristic_exponent("-2", "0", dps=dps, method=method)
    with mpmath.workdps(50):
        s = mpmath.sqrt(2)
        tol = mpmath.mpf(10) ** -(29 if dps else 15)
        assert mpmath.re(r.lam) == 0
        assert abs(mpmath.im(r.lam) - s) < tol
        up, down = r.multipliers
        assert abs(up - mpmath.exp(-mpmath.pi * s)) < tol
        assert abs(down - mpmath.exp(mpmath.pi * s)) < tol * 100
        assert mpmath.im(up) == 0 and mpmath.im(down) == 0
    assert not r.stable and not r.on_boundary
    assert r.band_edge == 0 and r.depth == 0
    assert r.method == method and r.dps == dps
    assert r.working_dps >= (dps or 15)


def test_free_exponent_verdicts_at_zero_at_squares_and_between():
    """theta0 = 0: the solution tau grows, unstable, on the curve a_0 = 0; theta0 = 1/2:
    stable, lam = sqrt(1/2) (band edge 1); theta0 = 8: band edge 3 (sqrt 8 = 2.83);
    theta0 = 9: on the curve and stable (cos 3 tau, sin 3 tau)."""
    r = characteristic_exponent("0", "0", dps=30)
    assert r.lam == 0 and not r.stable and r.on_boundary
    r = characteristic_exponent("1/2", "0", dps=30)
    assert r.stable and not r.on_boundary and r.band_edge == 1
    with mpmath.workdps(40):
        assert abs(r.lam - mpmath.sqrt(mpmath.mpf(1) / 2)) < mpmath.mpf(10) ** -29
    r = characteristic_exponent("8", "0", dps=30)
    assert r.band_edge == 3 and r.stable
    r = characteristic_exponent("9", "0", dps=30)
    assert r.on_boundary and r.stable and r.band_edge == 3


@pytest.mark.parametrize("method", ["cf", "hill"])
def test_free_exponent_by_an_mpmath_route_claims_no_certified_digits(method):
    """Only method "arb" proves digits; with theta1 = 0 the mpmath routes report none."""
    assert characteristic_exponent("2", "0", dps=30, method=method).certified_digits is None
    assert characteristic_exponent("2", "0", dps=30, method="arb").certified_digits == 30


# -- the radii table: writing it ----------------------------------------------------------------

def test_radii_table_is_written_whole_and_then_checks_up_to_date(monkeypatch, tmp_path, capsys):
    """`python -m pendulab.analyses.mathieu_branch` (no --check) writes the fresh text to
    mathieu_radii.py beside the module, through a temporary file that does not stay; --check
    then says up to date (exit 0), and a changed fresh text differs (exit 1)."""
    from pendulab.analyses import mathieu_branch as mb
    monkeypatch.setattr(mb, "__file__", str(tmp_path / "mathieu_branch.py"))
    monkeypatch.setattr(mb, "table_source", lambda: "RADII = 1\n")
    assert mb._main([]) == 0
    assert (tmp_path / "mathieu_radii.py").read_text() == "RADII = 1\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mathieu_radii.py"]
    assert capsys.readouterr().out == "wrote mathieu_radii.py\n"
    assert mb._main(["--check"]) == 0
    assert capsys.readouterr().out == "mathieu_radii.py: up to date\n"
    monkeypatch.setattr(mb, "table_source", lambda: "RADII = 2\n")
    assert mb._main(["--check"]) == 1
    assert capsys.readouterr().out == "mathieu_radii.py: differs from a fresh computation\n"
    assert (tmp_path / "mathieu_radii.py").read_text() == "RADII = 1\n"


# -- nearest_double: exact ends for every exponent ----------------------------------------------

def test_nearest_double_forms_the_ends_exactly_at_every_exponent():
    """Integers 24 (3 * 2^3) and 4 (exponent >= 0) are their own doubles; 2^-900 (1 + 2^-200)
    rounds to 2^-900 although its lowest bit, 2^-1100, is below the smallest double; a ball
    about 1 + 2^-100 whose radius, about 2^-43, ends in a bit coarser than its midpoint's last
    bit holds 1 - 2^-44 and 1 + 2^-44, different doubles: none is proved."""
    ctx.prec = 300
    assert _arb.nearest_double(arb(24)) == 24.0
    assert _arb.nearest_double(arb(4)) == 4.0
    assert _arb.nearest_double(arb(2) ** -900 + arb(2) ** -1100) == 2.0 ** -900
    wide = arb(1) + arb(2) ** -100 + arb(0, 1) * arb(2) ** -43
    assert _arb.nearest_double(wide) is None


def test_lam_text_of_an_exact_zero_is_zero():
    ctx.prec = 200
    assert _arb.lam_text(arb(0), 10) == "0"


# -- the sign-change proof: the bracket stays below u = 1, and an end without a ball refuses ----

X0, X1 = Fraction(-2, 1000), Fraction(2, 10)     # band 0, lam = 0.1352 (tests/test_certs_arb.py)


@functools.lru_cache(maxsize=None)
def _lam_band0():
    """lam of (X0, X1) from the monodromy trace over [0, pi] (mpmath.odefun): 2 cos(pi lam)."""
    with mpmath.workdps(40):
        a, b = mpmath.mpf(X0.numerator) / X0.denominator, mpmath.mpf(X1.numerator) / X1.denominator

        def rhs(t, y):
            return [y[1], -(a + 2 * b * mpmath.cos(2 * t)) * y[0]]
        trace = (mpmath.odefun(rhs, 0, [1, 0])(mpmath.pi)[0]
                 + mpmath.odefun(rhs, 0, [0, 1])(mpmath.pi)[1])
        return mpmath.acos(trace / 2) / mpmath.pi


def _prove(um, e):
    prec = _arb.bits_of(30) + _arb.loss_bits(float(X0), float(X1))
    with _arb._Prec(prec + 16):
        return _arb._prove(X0, X1, 1, e, True, arb(um), arb("1e-40"), arb("1e-40"), prec,
                           float(X0), float(X1), arb(1000))


def test_sign_change_refuses_the_root_of_f_past_u_one():
    """Band 0, edge 1: f_1 has the root u = (1 - lam)^2 = 0.748 (lam = 1 - sqrt u = 0.1352)
    and also u = (1 + lam)^2 = 1.289, the same exponent shifted by 2, which read as
    lam = 1 - sqrt u gives -0.1352, outside the band.  A candidate at the second root is
    refused (no bracket reaches u >= 1); the first one is proved and holds the monodromy
    value."""
    ctx.prec = 200
    lam = _lam_band0()
    with mpmath.workdps(40):
        near, far = (mpmath.nstr(v, 40) for v in ((1 - lam) ** 2, (1 + lam) ** 2))
        ref = arb(mpmath.nstr(lam, 38))
    assert _prove(far, 1) is None
    got = _prove(near, 1)
    assert got is not None and got[0].contains(ref)


@pytest.mark.parametrize("end", ["lo", "hi"])
def test_sign_change_refuses_a_bracket_with_one_end_unproved(monkeypatch, end):
    """f at one end of the bracket without a ball (its tail condition not shown): no lam, and
    no error -- the other end's sign alone proves nothing."""
    ctx.prec = 200
    lam = _lam_band0()
    with mpmath.workdps(40):
        um = mpmath.nstr(lam ** 2, 40)
    assert _prove(um, 0) is not None
    real = _arb._value_ball
    centre = arb(um)

    def one_end(u, *args):
        if (u > centre) == (end == "hi"):
            return None
        return real(u, *args)
    monkeypatch.setattr(_arb, "_value_ball", one_end)
    assert _prove(um, 0) is None


@pytest.mark.parametrize("offset", ["-1e-12", "1e-12"])
def test_sign_change_refuses_a_bracket_beside_the_root_where_f_is_small(offset):
    """A candidate 10^-12 below (or above) the root u = lam^2 of f_0: the bracket, at most
    2^50 10^-40 wide, lies on one side and f has one sign at both ends, smaller than 1 in
    size there (f'(u) 10^-12); a rule that took "small" for "of the other sign" would prove
    it.  Refused; the root itself is proved."""
    ctx.prec = 200
    lam = _lam_band0()
    with mpmath.workdps(40):
        um = mpmath.nstr(lam ** 2 + mpmath.mpf(offset), 40)
        root = mpmath.nstr(lam ** 2, 40)
    assert _prove(um, 0) is None
    assert _prove(root, 0) is not None


# -- the tail condition with theta0 != 0, a large imaginary t, and a ball of u ------------------

def _point(x):
    return _arb.to_ball(Fraction(x))


@pytest.mark.parametrize("u,threshold", [
    ("1/100", Fraction(1221, 200)),  # u > 0, t = 0.1: (4 - t)^2 - theta0 = 12.21 = 2|theta1|
    ("-1", Fraction(6)),             # u < 0, s = 1: 4^2 - theta0 - s^2 = 12 = 2|theta1|
])
def test_tail_condition_with_theta0_three_refuses_five_percent_past_its_bound(u, threshold):
    """theta0 = 3, j = 4: C_j = theta0 - (j + t)^2 on both sides; the bound on |theta1| moves
    down by theta0 (and by s^2 = -u for u < 0, where the second rule, j^2 s^2 > theta1^2,
    needs |theta1| < 4, below the first).  5 % past it is refused, 5 % inside accepted; a
    rule that added theta0 or s^2 instead would accept both."""
    ctx.prec = 200
    U, x0 = _point(u), _point(3)
    for sign in (1, -1):
        assert not _arb._tail_ok(4, U, x0, _point(sign * threshold * Fraction(105, 100)))
        assert _arb._tail_ok(4, U, x0, _point(sign * threshold * Fraction(95, 100)))


def test_tail_condition_holds_for_every_u_of_a_ball():
    """u = 1/2 +- 10^-30, theta0 = 0, j = 4: (4 - sqrt u)^2 changes by about 5 10^-30 across
    the ball; with 2|theta1| its value at the centre the rule fails at the upper end of u and
    is refused; 10^-25 lower it holds over the whole ball (mpmath at 60 digits gives the
    centre value)."""
    ctx.prec = 200
    with mpmath.workdps(60):
        edge = (4 - mpmath.sqrt(mpmath.mpf(1) / 2)) ** 2 / 2
        at_centre = Fraction(mpmath.nstr(edge, 55))
        inside = Fraction(mpmath.nstr(edge - mpmath.mpf(10) ** -25, 55))
    U = arb(0.5) + arb(0, 1) * arb(10) ** -30
    x0 = _point(0)
    assert not _arb._tail_ok(4, U, x0, _point(at_centre))
    assert _arb._tail_ok(4, U, x0, _point(inside))


# -- the Sturm count: an exactly zero pivot after a negative one -------------------------------

def test_sturm_count_reads_a_zero_pivot_below_the_first_row_as_its_limit():
    """a_even at q = 4, x = 8: the pivots are p_0 = -8 (one eigenvalue below x so far) and
    p_1 = 4 - 8 - 2 q^2 / p_0 = 0 exactly; read as the limit x - 0 the count goes on from 1
    (not from 0, nor from row 1 again).  Reference: the eigenvalues of the 60-row DLMF 28.4.5
    matrix at q = 4 (mpmath.eigsy, 50 digits) below 8."""
    ctx.prec = 200
    with mpmath.workdps(50):
        n, q = 60, mpmath.mpf(4)
        A = mpmath.zeros(n)
        for i in range(n):
            A[i, i] = (2 * i) ** 2
            if i:
                A[i, i - 1] = A[i - 1, i] = q * (mpmath.sqrt(2) if i == 1 else 1)
        expected = sum(1 for e in mpmath.eigsy(A, eigvals_only=True) if e < 8)
    assert expected == 2
    assert _arb.family_count("a_even", _point(4), _point(8)) == expected


def _a_even_eigenvalues(q, n=60, dps=50):
    """Eigenvalues of the n-row DLMF 28.4.5 matrix at q (mpmath.eigsy, symmetrised)."""
    with mpmath.workdps(dps):
        q = mpmath.mpf(q)
        A = mpmath.zeros(n)
        for i in range(n):
            A[i, i] = (2 * i) ** 2
            if i:
                A[i, i - 1] = A[i - 1, i] = q * (mpmath.sqrt(2) if i == 1 else 1)
        return mpmath.eigsy(A, eigvals_only=True)


@pytest.mark.parametrize("q,x,expected", [
    (12, 23, 3),   # the stop rule's next diagonal is d_{n+1} = (2n + 2)^2 of a_even, not (2n + 3)^2
    (22, 0, 2),    # p_0 = 0 exactly: the next pivot is -inf, then the recurrence starts again
])
def test_sturm_count_of_a_even_at_large_q_against_the_eigenvalues(q, x, expected):
    """Two more points where a Sturm count that stops one row early, or skips a row after an
    exactly zero pivot, misses an eigenvalue (found by a search over integer q and x)."""
    ctx.prec = 200
    with mpmath.workdps(50):
        assert sum(1 for e in _a_even_eigenvalues(q) if e < x) == expected
    assert _arb.family_count("a_even", _point(q), _point(x)) == expected
