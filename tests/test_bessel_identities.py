"""The identity checker (pendulab.analyses.bessel_identities).

The identities are DLMF's: 10.5.3 (Wronskian, giving the cross product
J_n Y_{n+1} - J_{n+1} Y_n = -2/(pi z), 002 "Obs. 2") and 10.6.6 (derivative rules,
002 "Obs. 1"); their exact right-hand sides are the references.  The tests show
the checker reaches the precision asked for, and that it notices when an engine
is wrong.
"""

import math

import mpmath
import pytest

import pendulab.analyses.bessel_identities as bi
from pendulab.errors import InputError

SMALL_GRID = [1e-30, 1e-8, 0.5, 2.404825557695773, 3.8317059702075125, 37.0, 1e4, 1e6]


@pytest.mark.parametrize("dps", [15, 50])
def test_identities_hold_to_the_precision_asked(dps):
    rep = bi.check_identities(3, dps, SMALL_GRID)
    assert rep.worst[0] < mpmath.mpf(10) ** (-dps)
    assert rep.arb_certified and rep.agreements > 0
    assert set(rep.by_rule) == {(e, r) for e in bi.ENGINES for r in bi.RULES}
    with mpmath.workdps(dps + 5):  # D = lim z W = 2/pi (002), read at z = 1e-30
        for engine in bi.ENGINES:
            assert abs(rep.limit_D[engine] - 2 / mpmath.pi) < mpmath.mpf(10) ** (-dps)


def test_derivative_balls_are_certified_next_to_zeros():
    """Where J_0' = -J_1 nearly vanishes (the doubles next to j_1,k) the Taylor step must shrink
    until its remainder is negligible; the balls must hold mpmath's derivative at 30 more digits
    (a different method: its differentiated hypergeometric series) and be 10^-30 narrow."""
    zs = bi.default_grid(2)[1:-1]  # the nine doubles next to j_n,k, n = 0, 1, 2, k <= 3
    rep = bi.check_identities(2, 30, zs)
    assert rep.arb_certified and rep.worst[0] < mpmath.mpf(10) ** -30
    for z in zs:
        J, Y, dJ, dY = bi._arb_values(2, z, bi.bits_for(30))
        with mpmath.workdps(60):
            for n in range(2):
                for ball, ref in ((dJ[n], mpmath.besselj(n, z, derivative=1)),
                                  (dY[n], mpmath.bessely(n, z, derivative=1))):
                    mid, rad = bi._to_mpf(ball.mid()), bi._to_mpf(ball.rad())
                    assert abs(mid - ref) <= rad and rad <= abs(ref) * mpmath.mpf(10) ** -30, (z, n)


def test_cross_product_alone():
    rep = bi.check_identities(20, 50, [1e-30, 0.5, 19.79, 1e6], rules=("cross",))
    assert set(rep.by_rule) == {("arb", "cross"), ("mpmath", "cross")}
    assert rep.worst[0] < mpmath.mpf(10) ** -50 and rep.arb_certified


def test_high_precision_arb_only():
    rep = bi.check_identities(2, 300, [1e-30, 1.0, 1e6], engines=("arb",))
    assert rep.worst[0] < mpmath.mpf(10) ** -300


def test_a_wrong_engine_is_caught(monkeypatch):
    """Perturb mpmath's Y_1 by 3 parts in 10^35, three times the agreement tolerance
    10^-(dps+5) at dps = 30 (a tolerance 10 times looser would let it through): the engines
    no longer agree.  Unperturbed, mpmath's worst error is ~1e-40 (it works at 40 digits)."""
    assert bi.check_identities(2, 30, [0.5], engines=("mpmath",)).worst[0] < mpmath.mpf(10) ** -38
    real = bi._mp_values

    def broken(n_top, z, dps, derivatives=True):
        J, Y, dJ, dY = real(n_top, z, dps, derivatives)
        with mpmath.workdps(bi.mp_digits(dps)):
            Y[1] = Y[1] * (1 + 3 * mpmath.mpf(10) ** -35)
        return J, Y, dJ, dY
    monkeypatch.setattr(bi, "_mp_values", broken)
    with pytest.raises(bi.EngineDisagreement, match="Y_1"):
        bi.check_identities(2, 30, [0.5])
    rep = bi.check_identities(2, 30, [0.5], engines=("mpmath",))
    assert rep.worst[0] > mpmath.mpf(10) ** -35  # and the checker reports the broken identity
    assert rep.worst[2] in ("cross", "derivative_Y", "wronskian")


def test_double_precision_loses_digits_where_the_docs_say():
    """SciPy's jv next to a zero of J_1 has no correct digit; the cross product stays good
    (no cancellation) until Y_n overflows at small z."""
    near = bi.scipy_value_errors(1, [3.8317059702075125])
    assert near[0][1] > 0.1
    far = bi.scipy_value_errors(1, [1e6])
    assert far[0][1] < 1e-14
    cross = bi.scipy_cross_product_errors(12, [1e-30])
    assert math.isinf(cross[-1][2]) or math.isnan(cross[-1][2])


@pytest.mark.parametrize("kwargs, fragment", [
    (dict(nmax=-1, dps=30, points=[1.0]), "nmax"), (dict(nmax=2, dps=0, points=[1.0]), "dps"),
    (dict(nmax=2, dps=30, points=[0.0]), "z must be a positive"),
    (dict(nmax=2, dps=30, points=[-1.0]), "z must be a positive"),
    (dict(nmax=2, dps=30, points=[float("inf")]), "z must be a positive"),
    (dict(nmax=2, dps=30, points=[1.0], engines=("maple",)), "engines"),
    (dict(nmax=2, dps=30, points=[1.0], rules=("wronskian",)), "rules"),
])
def test_bad_arguments(kwargs, fragment):
    with pytest.raises(InputError, match=fragment):
        bi.check_identities(**kwargs)


@pytest.mark.parametrize("dps", [1, 2, 3, 4])
def test_low_dps_engines_agree_next_to_zeros(dps):
    """At dps 1 to 4 mpmath worked at dps + 10 = 11 to 14 digits, where its besselj at the
    doubles next to j_0,1 and j_1,1 (|J| ~ 6e-17) has no correct digit, and the engines
    "disagreed" (mpmath -2.8e-13 against arb's -6.1e-17).  The exact right-hand sides are
    the references: every error below 10^-dps, every arb ball holding its exact value."""
    rep = bi.check_identities(2, dps, SMALL_GRID)
    assert rep.worst[0] < mpmath.mpf(10) ** (-dps)
    assert rep.arb_certified and rep.agreements > 0
    with mpmath.workdps(30):  # mpmath's J_0 next to j_0,1 is now right to many digits
        J = bi._mp_values(0, 2.404825557695773, dps, derivatives=False)[0][0]
        exact = mpmath.besselj(0, mpmath.mpf(2.404825557695773))  # at 30 digits, as a reference
        assert abs(J - exact) < mpmath.mpf(10) ** -10 * abs(exact)
