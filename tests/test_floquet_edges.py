"""Points on and next to the characteristic curves, too-low dps, size guards and
the inverse near integer nu (audit items 1-4).

References: the characteristic values a_m(q), b_m(q) at 50-90 digits
(mathieu_a/mathieu_b: eigenvalue of the DLMF 28.4 matrices refined by the
continued fraction in a -- a different route from the three exponent methods),
the three exponent methods against one another, and the ordering
a_0 < b_1 < a_1 < b_2 < ... for q > 0 (DLMF 28.2(v)): a_m is the lower edge
of band m, b_{m+1} its upper edge.
"""

import json

import mpmath
import numpy as np
import pytest

from pendulab.analyses.floquet import (
    characteristic_exponent,
    is_stable,
    mathieu_a,
    mathieu_b,
    stability_limits,
    theta0_of_exponent,
)
from pendulab.cli import main
from pendulab.errors import InputError

# (kind, m, q) with q > 0 in DLMF notation, so theta1 = -q
EDGES = [("a", 0, "0.2"), ("a", 1, "0.2"), ("b", 1, "5"), ("a", 0, "5")]


def _edge_text(kind, m, q, digits):
    f = mathieu_a if kind == "a" else mathieu_b
    with mpmath.workdps(digits + 10):
        return mpmath.nstr(f(m, q, dps=digits + 5), digits)


@pytest.mark.parametrize("dps", [None, 30])
@pytest.mark.parametrize("kind,m,q", EDGES)
def test_all_methods_on_a_boundary_to_60_digits(kind, m, q, dps):
    # theta0 = the curve rounded to 60 digits: 1e-61 off it, resolvable within
    # the default max_dps; cf used to fail here with "root is not bracketed"
    t0 = _edge_text(kind, m, q, 60)
    with mpmath.workdps(100):
        above = mpmath.mpf(t0) > (mathieu_a if kind == "a" else mathieu_b)(m, q, dps=90)
    expected_stable = above if kind == "a" else not above   # a_m lower, b_m upper edge
    methods = ("hill", "cf") + (("monodromy",) if dps is None and q == "0.2" else ())
    res = {meth: characteristic_exponent(t0, "-" + q, dps=dps, method=meth) for meth in methods}
    for r in res.values():
        assert r.stable is expected_stable and not r.on_boundary
        lam = complex(r.lam)
        assert abs(lam - m) < 1e-25            # |lam - m| ~ sqrt(1e-61)
        assert (lam.imag == 0) is r.stable     # lambda and verdict agree
        assert (abs(abs(complex(r.multipliers[0])) - 1) < 1e-12) is True
    assert complex(res["hill"].lam) == pytest.approx(complex(res["cf"].lam), rel=1e-12)


@pytest.mark.parametrize("method", ["hill", "cf"])
def test_on_boundary_only_when_max_dps_cannot_decide(method):
    # a_0(0.2) to 100 digits with max_dps = 60: the side cannot be decided, so
    # the point is on the curve: lam = 0 exactly, multipliers 1, unstable (Ince)
    t0 = _edge_text("a", 0, "0.2", 100)
    r = characteristic_exponent(t0, "-0.2", dps=25, method=method, max_dps=60)
    assert r.on_boundary and not r.stable
    assert r.lam == 0 and r.multipliers == (1, 1)
    r = characteristic_exponent(_edge_text("b", 1, "0.2", 100), "-0.2", dps=25,
                                method=method, max_dps=60)
    assert r.on_boundary and not r.stable and r.lam == 1 and r.multipliers == (-1, -1)


@pytest.mark.parametrize("dps", [1, 2, 3, 15])
def test_low_dps_gives_the_verdict_of_the_point(dps, capsys):
    # theta0 = -0.002 is 0.018 above a_0(0.2) = -0.0199 and inside band 0 (the
    # source's Fig. 2 point); dps = 1 used to say "on boundary, unstable"
    ref = characteristic_exponent("-0.002", "0.2", dps=40, method="cf")
    assert main(["floquet", "--theta0", "-0.002", "--theta1", "0.2", "--dps", str(dps),
                 "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["stable"] is True and rec["on_boundary"] is False
    with mpmath.workdps(50):
        assert abs(mpmath.mpf(rec["lambda"]) - ref.lam) <= 0.51 * mpmath.mpf(10) ** (-dps) \
            * 10 ** int(mpmath.floor(mpmath.log10(ref.lam)) + 1)


def test_just_inside_a_band_at_dps_15_is_stable_with_real_lambda():
    # 7.5e-21 above a_0(0.2): lam ~ 1e-10 real; verdict, lambda and
    # multipliers agree (they used to contradict), and cf agrees with hill
    with mpmath.workdps(60):
        t0 = mathieu_a(0, "0.2", dps=50) + mpmath.mpf("7.5e-21")
    r = characteristic_exponent(t0, "-0.2", dps=15)
    assert r.stable and not r.on_boundary
    assert isinstance(r.lam, mpmath.mpf) and 1e-11 < r.lam < 1e-9
    assert all(abs(abs(z) - 1) < 1e-14 for z in r.multipliers)
    cf = characteristic_exponent(t0, "-0.2", dps=30, method="cf")
    with mpmath.workdps(40):
        assert abs(cf.lam - r.lam) < mpmath.mpf(10) ** -14 * r.lam
    below = characteristic_exponent(t0 - mpmath.mpf("1.5e-20"), "-0.2", dps=15)
    assert not below.stable and mpmath.re(below.lam) == 0 and mpmath.im(below.lam) > 0


@pytest.mark.parametrize("argv", [
    ["--theta0", "1e400", "--theta1", "1"],
    ["--theta0", "1e20", "--theta1", "1"],
    ["--theta0", "1", "--theta1", "1e12"],
    ["--theta0", "1", "--theta1", "1e300"],
    ["--theta0", "-0.01", "--theta1", "1e4", "--method", "monodromy"],
    ["--theta0", "-0.01", "--theta1", "1e5", "--method", "cf"],
])
def test_size_guards_give_one_line(argv, capsys):
    assert main(["floquet", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1
    # beyond the widest method's size each number's own range (pendulab.limits) refuses it;
    # within it, the method's size limit
    assert ("too large" in err and "limit" in err) or "must be a number from -" in err


def test_size_guards_of_the_other_entry_points():
    for call in (lambda: mathieu_a(0, 1e7), lambda: mathieu_b(1, "1e400"),
                 lambda: theta0_of_exponent(0.5, 1e5), lambda: theta0_of_exponent(1e4, 1),
                 lambda: is_stable(np.array([1e20]), 1.0), lambda: stability_limits(1e4)):
        with pytest.raises(InputError, match="too large|must be <="):
            call()


def test_theta1_1e6_still_works_with_hill():
    # S = 2e6 is inside hill's limit; the verdict agrees with the vectorised map
    r = characteristic_exponent("-0.01", "1e6")
    assert r.stable == bool(is_stable(-0.01, 1e6))


# -- the inverse near integers and at huge q -----------------------------------------

@pytest.mark.parametrize("nu,theta1,dps,kind,m", [
    (1e-30, "0.2", None, "a", 0),                         # used to raise ConvergenceError
    (1e-12, "100", None, "a", 0),
    ("0.99999999999999999999", "0.2", 10, "b", 1),        # dps=30 worked, dps=10 did not
    ("1.00000000000000000001", "0.2", 10, "a", 1),        # the other one-sided limit
    ("1.99999999999999999999", "0.7", 12, "b", 2),
    ("2.00000000000000000001", "0.7", 12, "a", 2),
    (0.5, 1e4, None, "a", 0),                             # band width ~e^-400 (DLMF 28.8.2)
    (0.5, "1e4", 30, "a", 0),
])
def test_inverse_tends_to_the_edge(nu, theta1, dps, kind, m):
    # as nu -> n from below (above) theta0 -> the lower (upper) edge of gap n at
    # |q|: b_n(|q|) (a_n(|q|)) for |q| > 0; within rounding of the edge here
    got = theta0_of_exponent(nu, theta1, dps=dps)
    absq = theta1.lstrip("-") if isinstance(theta1, str) else abs(theta1)
    ref = (mathieu_a if kind == "a" else mathieu_b)(m, absq, dps=50)
    digits = 15 if dps is None else dps
    with mpmath.workdps(60):
        assert abs(mpmath.mpf(got) - ref) <= mpmath.mpf(10) ** (-digits) * max(1, abs(ref))


def test_inverse_near_an_integer_against_the_forward_exponent():
    # 1e-6 below nu = 1: theta0 is ~1e-12 below b_1(0.2); the forward exponent of
    # the returned theta0 (Hill's determinant, not the cf root finder) gives nu back
    with mpmath.workdps(40):
        nu = 1 - mpmath.mpf("1e-6")
    t0 = theta0_of_exponent(nu, "0.2", dps=30)
    with mpmath.workdps(40):
        assert 0 < mathieu_b(1, "0.2", dps=35) - t0 < 1e-10
    r = characteristic_exponent(t0, "0.2", dps=30, method="hill")
    with mpmath.workdps(40):
        # theta0 to 30 digits -> lam - 1 ~ sqrt(theta0 - b_1) to ~1e-24 absolute
        assert r.stable and abs(r.lam - nu) < mpmath.mpf("1e-22")
