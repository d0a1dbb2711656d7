"""002's quarter periods, the claim about them and its large-k limits (pendulab.analyses.bessel_periods).

References: 002_19b336b29bb1f03b.txt (last page: the table 22.8438, 21.6315, ...);
A&S Table 9.5 (zeros to 10 decimals, for durations computed here by hand);
the limits 6 -+ pi^2/2 come out of the derivation, and are checked against margins
computed from certified zeros, a method independent of the expansion.
"""

from fractions import Fraction

import mpmath
import pytest
import sympy as sp

from pendulab.analyses.bessel_periods import (GROWING, SHORTENING, direction_of, margin_limits,
                                              quarter_periods)
from pendulab.analyses.bessel_identities import _to_mpf
from pendulab.errors import InputError

# 002, last page (differences of squares, unit v0/(4g)), in time order.
SOURCE_INWARD = ["22.8438", "32.6495", "42.5001"]
SOURCE_OUTWARD = ["21.6315", "31.5213", "41.3994"]
# A&S Table 9.5
J11, J12, J13 = Fraction("3.8317059702"), Fraction("7.0155866698"), Fraction("10.1734681351")
J21, J22, J23 = Fraction("5.1356223018"), Fraction("8.4172441404"), Fraction("11.6198411721")


def test_the_sources_table_to_every_printed_digit():
    q = quarter_periods(3, 6)
    assert q.inward == SOURCE_INWARD and q.outward == SOURCE_OUTWARD
    assert q.claim_holds is True


def test_durations_agree_with_abramowitz_stegun():
    q = quarter_periods(2, 9)
    by_hand = [J12 ** 2 - J21 ** 2, J13 ** 2 - J22 ** 2]  # inward: j_{1,k+2}^2 - j_{2,k+1}^2
    for ours, ref in zip(q.inward, by_hand):
        assert abs(Fraction(ours) - ref) < Fraction(1, 10 ** 7)
    assert abs(Fraction(q.outward[0]) - (J22 ** 2 - J12 ** 2)) < Fraction(1, 10 ** 7)


def test_claim_for_a_thousand_swings_and_the_derived_limits():
    q = quarter_periods(1000, 25)
    assert q.claim_holds is True and all(b > 0 for b in q.after_balls + q.before_balls)
    after, before, asym = margin_limits()
    assert sp.simplify(after - (6 - sp.pi ** 2 / 2)) == 0  # derived, checked against the closed value
    assert sp.simplify(before - (6 + sp.pi ** 2 / 2)) == 0
    k = asym["k"]
    with mpmath.workdps(30):
        for idx in (100, 500, 999):
            for name, balls, kk in (("margin_after", q.after_balls, idx), ("margin_before", q.before_balls, idx)):
                ball = balls[idx] if name == "margin_after" else balls[idx - 1]
                pred = mpmath.mpf(str(sp.N(asym[name].subs(k, kk), 40)))
                got = _to_mpf(ball)
                # the expansion is cut after k^-4: the rest is O(k^-5)
                assert abs(got - pred) < 50 * mpmath.mpf(kk) ** -5, (name, kk, got, pred)
        # and the leading terms of the durations: pi^2 k + 2 pi^2 + 3, pi^2 k + 5 pi^2/2 - 3
        lead_in = sp.pi ** 2 * k + 2 * sp.pi ** 2 + 3
        assert sp.limit(asym["inward"] - lead_in, k, sp.oo) == 0
        assert sp.limit(asym["outward"] - (sp.pi ** 2 * k + 5 * sp.pi ** 2 / 2 - 3), k, sp.oo) == 0


def test_shortening_string_reverses_the_swings():
    q = quarter_periods(5, 8, SHORTENING)
    assert q.start == 3  # z0 = j_{2,3}: 2*3 - 1 = 5 quarter periods before L = 0
    # in time order: j23^2-j13^2 (inward), j13^2-j22^2 (outward), j22^2-j12^2, j12^2-j21^2, j21^2-j11^2
    ref_in = [J23 ** 2 - J13 ** 2, J22 ** 2 - J12 ** 2, J21 ** 2 - J11 ** 2]
    ref_out = [J13 ** 2 - J22 ** 2, J12 ** 2 - J21 ** 2]
    for ours, ref in zip(q.inward + q.outward, ref_in + ref_out):
        assert abs(Fraction(ours) - ref) < Fraction(1, 10 ** 5)
    assert len(q.inward) == 3 and len(q.outward) == 2
    assert abs(Fraction(q.time_to_zero_length) - J23 ** 2) < Fraction(1, 10 ** 5)
    assert q.claim_holds is False  # here the outward swings are the longer ones
    growing = quarter_periods(5, 8, GROWING)
    assert q.inward != growing.inward[:3]


def test_shortening_string_has_finitely_many_quarter_periods():
    with pytest.raises(InputError, match="only 3 quarter periods"):
        quarter_periods(4, 10, SHORTENING, start=2)


def test_direction_from_the_rate():
    v0 = sp.Symbol("v0", positive=True)
    c = sp.Symbol("c", real=True)
    assert direction_of(v0) == GROWING and direction_of(-v0) == SHORTENING
    with pytest.raises(InputError, match="unknown"):
        direction_of(c)
    with pytest.raises(InputError, match="does not change"):
        direction_of(0)


@pytest.mark.parametrize("nu,shift,order", [(1, 2, 4), (2, 1, 4), (2, 2, 6), (0, 1, 3)])
def test_scaled_square_is_the_expanded_square_of_mcmahons_zero(nu, shift, order):
    """The ring arithmetic of _scaled_square against SymPy's own expansion of the square of
    McMahon's u j_{nu, 1/u + shift} (the route it replaced), truncated at u^(order+2)."""
    from pendulab.analyses.bessel_asymptotics import _scaled_square, _scaled_zero
    u = sp.Symbol("u", positive=True)
    p = sp.Poly(sp.expand(_scaled_zero(nu, shift, u, order) ** 2), u)
    slow = sp.expand(sum(p.coeff_monomial(u ** i) * u ** i for i in range(order + 3)))
    assert _scaled_square(nu, shift, u, order) == slow


@pytest.mark.parametrize("order", [2, 4, 6])
def test_quarter_period_asymptotics_equal_sympys_route(order):
    """Differences taken in the exact ring and written out in k once, against the route they
    replaced: SymPy expressions in u substituted u = 1/k, expanded, and SymPy's limit."""
    from pendulab.analyses.bessel_asymptotics import _scaled_square, quarter_period_asymptotics
    u, k = sp.Symbol("u", positive=True), sp.Symbol("k", positive=True)
    sq = {key: _scaled_square(*key, u, order) for key in ((1, 1), (1, 2), (2, 1), (2, 2))}
    slow = {name: sp.expand(e.subs(u, 1 / k) * k ** 2) for name, e in (
        ("inward", sq[1, 2] - sq[2, 1]), ("outward", sq[2, 2] - sq[1, 2]),
        ("outward_before", sq[2, 1] - sq[1, 1]))}
    slow["margin_after"] = sp.expand(slow["inward"] - slow["outward"])
    slow["margin_before"] = sp.expand(slow["inward"] - slow.pop("outward_before"))
    slow["limit_margin_after"] = sp.limit(slow["margin_after"], k, sp.oo)
    slow["limit_margin_before"] = sp.limit(slow["margin_before"], k, sp.oo)
    fast = quarter_period_asymptotics(order)
    assert fast["k"] == k
    for name, expr in slow.items():
        assert fast[name] == expr, name  # the same tree, so the same text in bessel.json
        assert sp.sstr(fast[name], order=None) == sp.sstr(expr, order=None), name


def test_limit_of_a_growing_expansion_is_left_to_sympy():
    """_in_k: a term in a positive power of k that survives makes the limit SymPy's (oo here)."""
    from pendulab.analyses.bessel_asymptotics import _in_k, _square_ring
    _, U, P, R = _square_ring()
    k = sp.Symbol("k", positive=True)
    expr, limit = _in_k(P * P * U + 3 * U * U - P * R * U ** 2, k)  # pi^2 k + 3 - 1
    assert expr == sp.pi ** 2 * k + 2 and limit == sp.oo
    expr, limit = _in_k(P * R * U - U + 5 * U * U + U ** 3, k)  # k - k + 5 + 1/k
    assert limit == 5
