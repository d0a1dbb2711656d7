"""The acceptance tests of the exponent's precision loop, each handed an answer it must refuse.

:func:`pendulab.analyses.floquet._precision.autoprec` ends the growth of the working precision
only when the caller's test passes: two mpmath precisions that agree (``agree``, and the
exponent's own test that the band, the sign of u = (lam - e)^2 and its digits agree), or a
ball-arithmetic proof that succeeded.  At the ceiling a point is declared on a characteristic
curve only when u is below 10^-(2 dps).  The brackets of the mpmath routes must change sign.
Each test below feeds a candidate a factor of 3 past the tolerance it guards (a tolerance ten
times looser would let it through) and, where it makes sense, one a factor of 3 inside.
"""

from fractions import Fraction

import mpmath
import pytest

from pendulab.analyses.floquet import _arb, _cf, _exponent, _precision, characteristic_exponent
from pendulab.errors import ConvergenceError, PrecisionError


# -- agree: two precisions agree to 10^-(want + 2), relative above 1 ------------------------

@pytest.mark.parametrize("size", ["0.5", "1", "1e5"])
def test_agree_refuses_a_difference_three_times_its_tolerance(size):
    want = 20
    with mpmath.workdps(40):
        b = mpmath.mpf(size)
        tol = mpmath.mpf(10) ** -(want + 2) * max(1, b)
        assert not _precision.agree(b + 3 * tol, b, want)
        assert not _precision.agree(b - 3 * tol, b, want)
        assert _precision.agree(b + tol / 3, b, want)
        # a tuple agrees only when every member does
        assert not _precision.agree((b, b + 3 * tol), (b, b), want)
        assert _precision.agree((b - tol / 3, b + tol / 3), (b, b), want)


# -- autoprec: the loop returns only what its test accepted ---------------------------------

def test_autoprec_returns_the_first_accepted_pair_and_nothing_before_it():
    """want = 20: the precisions are 30, 42, 64 (w -> max(w + 12, 2 w - want)), each with a
    second one 12 digits above.  The pairs (30, 42) and (42, 54) made to differ by 3 times
    the tolerance 10^-22, the pair (64, 76) by a third of it: the loop returns the value at
    76, having computed nothing beyond it."""
    seen = []

    def compute(w):
        seen.append(w)
        second = len(seen) % 2 == 0
        with mpmath.workdps(w):
            return 1 + (0 if not second else 3 * mpmath.mpf(10) ** -(22 if w < 60 else 23))

    def accept(a, b, w2):
        with mpmath.workdps(w2):
            return _precision.agree(a, b, 20)
    value, w2 = _precision.autoprec(compute, 20, 200, accept)
    assert seen == [30, 42, 42, 54, 64, 76]
    assert w2 == 76
    with mpmath.workdps(80):
        assert abs(value - 1 - 3 * mpmath.mpf(10) ** -23) < mpmath.mpf(10) ** -70


def test_autoprec_raises_at_the_ceiling_when_nothing_is_accepted():
    """Two precisions that always differ by 3 times the tolerance: a one-line
    PrecisionError, and no working precision above max_dps is tried."""
    seen = []

    def compute(w):
        seen.append(w)
        with mpmath.workdps(w):
            return 1 + 3 * mpmath.mpf(10) ** -22 * (len(seen) % 2)

    def accept(a, b, w2):
        with mpmath.workdps(w2):
            return _precision.agree(a, b, 20)
    with pytest.raises(PrecisionError, match="not resolved to 20 digits") as err:
        _precision.autoprec(compute, 20, 100, accept, what="x")
    assert "\n" not in str(err.value)
    assert max(seen) <= 100


def test_autoprec_of_a_proof_goes_on_until_the_proof_succeeds():
    seen = []

    def prove(w):
        seen.append(w)
        return "proved" if w >= 70 else None
    assert _precision.autoprec(prove, 20, 200, two=False) == ("proved", seen[-1])
    assert all(w < 70 for w in seen[:-1]) and seen[-1] >= 70
    with pytest.raises(PrecisionError):
        _precision.autoprec(lambda w: None, 20, 100, two=False)


# -- the exponent's mpmath routes: band, sign and digits must agree at two precisions --------

def _perturbed_core(monkeypatch, relative=None, fixed_u=None):
    """_core with the second of every two evaluations moved by ``relative`` (of u), or with u
    replaced by ``fixed_u`` (count and edge kept)."""
    real = _exponent._core
    calls = []

    def core(method, X0, X1, w):
        count, e, u, depth = real(method, X0, X1, w)
        calls.append(w)
        with mpmath.workdps(w):
            if fixed_u is not None:
                u = mpmath.mpf(fixed_u)
            elif len(calls) % 2 == 0:
                u = u * (1 + mpmath.mpf(relative))
        return count, e, u, depth
    monkeypatch.setattr(_exponent, "_core", core)
    return calls


def test_exponent_refuses_two_precisions_three_times_past_the_digit_tolerance(monkeypatch):
    """dps = 20: the two u's must agree to 10^-23 of u.  3 * 10^-23 apart at every precision:
    PrecisionError at the ceiling; 3 * 10^-24 apart: accepted, lam to 20 digits."""
    _perturbed_core(monkeypatch, relative="3e-23")
    with pytest.raises(PrecisionError, match="digits of the exponent"):
        characteristic_exponent("-0.002", "0.2", dps=20, method="cf", max_dps=80)
    monkeypatch.undo()
    ref = characteristic_exponent("-0.002", "0.2", dps=20, method="cf")
    _perturbed_core(monkeypatch, relative="3e-24")
    got = characteristic_exponent("-0.002", "0.2", dps=20, method="cf", max_dps=80)
    with mpmath.workdps(20):
        assert abs(got.lam - ref.lam) <= mpmath.mpf(10) ** -20 * abs(ref.lam)


def test_exponent_calls_a_curve_only_when_u_is_below_ten_to_minus_twice_the_digits(monkeypatch):
    """A u whose sign disagrees with the band count (u < 0 inside band 0) is never accepted.
    At the ceiling the point is put on the curve (lam = e, on_boundary) only when |u| <=
    10^-(2 dps): u = -3 * 10^-40 at dps = 20 is refused with PrecisionError, u = -3 * 10^-41
    is on the curve."""
    _perturbed_core(monkeypatch, fixed_u="-3e-40")
    with pytest.raises(PrecisionError, match="which side of a characteristic curve"):
        characteristic_exponent("-0.002", "0.2", dps=20, method="cf", max_dps=80)
    monkeypatch.undo()
    _perturbed_core(monkeypatch, fixed_u="-3e-41")
    r = characteristic_exponent("-0.002", "0.2", dps=20, method="cf", max_dps=80)
    assert r.on_boundary and not r.stable and r.lam == 0


def test_arb_exponent_calls_a_curve_only_when_u_is_below_ten_to_minus_twice_the_digits(
        monkeypatch):
    """The ball route never proves anything here (exponent_at returns None); its last estimate
    u decides at the ceiling as above: 3 * 10^-40 at dps = 20 raises, 3 * 10^-41 is a curve,
    with no certified digits claimed."""
    for u, on_curve in ((3e-40, False), (3e-41, True)):
        def never(X0, X1, want, w, info, u=u):
            info["e"], info["u"] = 0, u
            return None
        monkeypatch.setattr(_arb, "exponent_at", never)
        if on_curve:
            r = characteristic_exponent("-0.002", "0.2", dps=20, max_dps=80)
            assert r.on_boundary and r.certified_digits is None and r.lam == 0
        else:
            with pytest.raises(PrecisionError, match="cannot prove the digits"):
                characteristic_exponent("-0.002", "0.2", dps=20, max_dps=80)


# -- the brackets of the mpmath routes must change sign ------------------------------------

def test_brent_refuses_an_interval_without_a_sign_change_and_brackets_its_root():
    with mpmath.workdps(40):
        def f(x):
            return x * x - 2
        with pytest.raises(ConvergenceError, match="not bracketed"):
            _cf._illinois(f, mpmath.mpf(2), mpmath.mpf(3), f(2), f(3), mpmath.mpf(10) ** -30)
        tol = mpmath.mpf(10) ** -30
        root, width = _cf._illinois(f, mpmath.mpf(1), mpmath.mpf(2), f(1), f(2), tol)
        assert abs(root - mpmath.sqrt(2)) <= width <= tol + 8 * mpmath.eps * root


@pytest.mark.parametrize("count", [1, 2])
def test_cf_route_refuses_a_characteristic_function_without_a_root(monkeypatch, count):
    """The characteristic function made positive everywhere: no sign change inside the band
    (count 1), nor in the gap (count 2) -- ConvergenceError, not a root."""
    monkeypatch.setattr(_cf._CF, "__call__", lambda self, u, x0=None: mpmath.mpf(1))
    with mpmath.workdps(30):
        with pytest.raises(ConvergenceError, match="no root|could not bracket"):
            _cf._cf_u(mpmath.mpf("-0.002"), mpmath.mpf("0.2"), count, 30)


def test_inverse_refuses_a_characteristic_function_without_a_root(monkeypatch):
    from pendulab.analyses.floquet import _inverse
    monkeypatch.setattr(_cf._CF, "__call__", lambda self, u, x0=None: mpmath.mpf(1))
    with pytest.raises(ConvergenceError, match="no root of the characteristic function"):
        _inverse._theta0_of_exponent_mp(Fraction(3, 10), Fraction(1, 2), Fraction(1, 2), 30)


def test_free_exponent_claims_certified_digits_only_where_the_ball_proves_them(monkeypatch):
    """theta1 = 0: lam = sqrt(theta0) (2/3 here) is proved digit by digit from a ball; where no
    ball proves the digits, certified_digits is None (the value is still the exact root)."""
    r = characteristic_exponent("4/9", 0, dps=30)
    assert r.certified_digits == 30
    with mpmath.workdps(40):
        assert mpmath.nstr(r.lam, 30) == mpmath.nstr(mpmath.mpf(2) / 3, 30)
    monkeypatch.setattr(_arb, "lam_text", lambda ball, digits: None)
    r = characteristic_exponent("4/9", 0, dps=30)
    assert r.certified_digits is None
    with mpmath.workdps(30):
        assert abs(r.lam - mpmath.mpf(2) / 3) < mpmath.mpf(10) ** -30


# -- exact rational functions of the series: a factor cancels only where it divides ----------

def test_reduce_cancels_a_factor_only_where_the_numerator_vanishes():
    """(nu + 3)(nu + 1) / (2 (nu + 1)^2 (nu + 2)) keeps one factor (nu + 1) and (nu + 2);
    (nu + 5) / (nu + 1) keeps its factor.  Values checked with Fractions at nu = 1/7."""
    from pendulab.analyses.series_ratfun import RatFun, reduce
    nu = Fraction(1, 7)
    x = RatFun((3, 4, 1), 2, ((1, 2), (2, 1)))           # nu^2 + 4 nu + 3 = (nu + 1)(nu + 3)
    r = reduce(x)
    assert r.exps == ((1, 1), (2, 1)) and r.num == (3, 1) and r.den == 2
    assert r.evaluate(nu) == (nu + 3) * (nu + 1) / (2 * (nu + 1) ** 2 * (nu + 2))
    y = reduce(RatFun((5, 1), 1, ((1, 1),)))
    assert y.exps == ((1, 1),) and y.evaluate(nu) == (nu + 5) / (nu + 1)


# -- every mpmath route accepts only two precisions that agree -------------------------------

def _every_second_moved(monkeypatch, module, name, by):
    """module.name made to return, at every second call, its value moved by ``by`` times
    10^-(want + 2) max(1, |value|) (want = 20), each member of a tuple alike."""
    real = getattr(module, name)
    calls = []

    def moved(*args, **kwargs):
        value = real(*args, **kwargs)
        calls.append(1)
        if len(calls) % 2:
            return value
        with mpmath.workdps(300):      # the value carries its working precision
            shift = mpmath.mpf(by) * mpmath.mpf(10) ** -22

            def one(v):
                return v + shift * max(1, abs(v))
            return tuple(one(v) for v in value) if isinstance(value, tuple) else one(value)
    monkeypatch.setattr(module, name, moved)


def _routes():
    from pendulab.analyses.floquet import _charvalues, _inverse, first_band, mathieu_a
    from pendulab.analyses.floquet import theta0_of_exponent
    return [
        (_inverse, "_theta0_of_exponent_mp",
         lambda: theta0_of_exponent("0.3", "0.5", dps=20)),
        (_charvalues, "_char_value_mp", lambda: mathieu_a(0, 1, dps=20, method="mpmath")),
        (_charvalues, "_first_band_mp", lambda: first_band("-1/100", dps=20, method="mpmath")),
    ]


@pytest.mark.parametrize("route", range(3), ids=["inverse", "mathieu_a", "first_band"])
def test_mpmath_routes_refuse_two_precisions_three_times_past_the_tolerance(monkeypatch, route):
    """theta0_of_exponent, mathieu_a and first_band by mpmath at dps = 20, their two working
    precisions made to differ by 3 times 10^-22 (relative above 1): PrecisionError; by a third
    of it: accepted."""
    from pendulab.analyses.floquet import _charvalues
    module, name, call = _routes()[route]
    _charvalues._BANDS.clear()
    _every_second_moved(monkeypatch, module, name, 3)
    with pytest.raises(PrecisionError):
        call()
    monkeypatch.undo()
    _charvalues._BANDS.clear()
    _every_second_moved(monkeypatch, module, name, "0.3")
    assert call() is not None
    _charvalues._BANDS.clear()
