"""nu within 1e-12 of an integer: the source's series refuses, the Floquet methods stay right.

References: the characteristic values b_n(q), a_n(q) at 50 digits (the edges the
inverse tends to: as nu -> n from below theta0 -> min(a_n, b_n) at |q|, from above
max(a_n, b_n); docs/floquet.md), and the forward exponent by three methods that
share no code with the inverse's root finder (Hill's determinant, the ball
arithmetic route, the Taylor monodromy): each must give nu back.  Near the edge
lam - n ~ sqrt(theta0 - edge), so theta0 is computed at 45 digits to give lam to ~1e-26.
"""

import mpmath
import numpy as np
import pytest

from pendulab.analyses import series as se
from pendulab.analyses.floquet import characteristic_exponent, mathieu_a, mathieu_b, theta0_of_exponent
from pendulab.errors import SeriesDomainError

# (nu as text, theta1, the edge it tends to: kind, order, |q|)
NEAR = [
    ("0.999999999999", "0.2", "b", 1),
    ("1.000000000001", "0.2", "a", 1),
    ("1.999999999999", "0.7", "b", 2),
    ("2.000000000001", "0.7", "a", 2),
    ("3.000000000001", "-1.5", "a", 3),
]


@pytest.mark.parametrize("nu,theta1,kind,m", NEAR)
@pytest.mark.parametrize("dps", [None, 30])
def test_the_series_refuses_nu_near_an_integer(nu, theta1, kind, m, dps):
    x = nu if dps else float(nu)
    t1 = theta1 if dps else float(theta1)
    for call, args in ((se.theta0_of_nu, ()), (se.theta_c, (0.3,)), (se.theta_s, (0.3,))):
        with pytest.raises(SeriesDomainError, match=rf"^nu = {float(nu)!r} is within 1e-06 of the "
                                                    rf"integer {m}: the series \(000 sec. 3\) is "
                                                    r"singular there; use the integer-order series"):
            call(*args, x, t1, 8, dps=dps)


def test_the_sine_series_refuses_nu_near_zero_the_others_do_not():
    with pytest.raises(SeriesDomainError, match=r"^nu = 1e-12 is within 1e-06 of the integer 0"):
        se.theta_s(0.3, 1e-12, 0.2, 6)
    # theta0 and theta_c have no pole at nu = 0: alpha_n(0) = (-1)^n [q^n] a_0(q) (DLMF 28.6.1)
    v, est = se.theta0_of_nu(1e-12, 0.2, 12)
    assert abs(v - float(mathieu_a(0, "0.2", dps=30))) <= 2 * est + 1e-15


@pytest.mark.parametrize("nu,theta1,kind,m", NEAR)
def test_the_inverse_tends_to_the_edge(nu, theta1, kind, m):
    edge = (mathieu_a if kind == "a" else mathieu_b)(m, theta1.lstrip("-"), dps=50)
    for dps in (None, 30):
        got = theta0_of_exponent(nu if dps else float(nu), theta1 if dps else float(theta1), dps=dps)
        with mpmath.workdps(60):
            d = mpmath.mpf(got) - edge
            # theta0 - edge ~ (nu - m)^2 d theta0/d(lam^2)...: below 1e-22 here, the side by kind
            assert abs(d) < mpmath.mpf(10) ** -(15 if dps is None else 22) * max(1, abs(edge))
            if dps:
                assert (d < 0) == (kind == "b") or d == 0


@pytest.mark.parametrize("nu,theta1,kind,m", NEAR[:4])
@pytest.mark.parametrize("method", ["hill", "arb"])
def test_the_forward_exponent_gives_nu_back(nu, theta1, kind, m, method):
    t0 = theta0_of_exponent(nu, theta1, dps=45)
    r = characteristic_exponent(t0, theta1, dps=30, method=method)
    with mpmath.workdps(50):
        assert r.stable and abs(r.lam - mpmath.mpf(nu)) < mpmath.mpf(10) ** -24


def test_the_taylor_monodromy_gives_nu_back():
    t0 = theta0_of_exponent("0.999999999999", "0.2", dps=45)
    r = characteristic_exponent(t0, "0.2", dps=30, method="monodromy")
    with mpmath.workdps(50):
        assert r.stable and abs(r.lam - mpmath.mpf("0.999999999999")) < mpmath.mpf(10) ** -24


def test_the_vectorised_inverse_near_integers():
    nus = np.array([1 - 1e-12, 1 + 1e-12, 2 - 1e-12, 2 + 1e-12])
    got = theta0_of_exponent(nus, np.full(4, 0.2))
    ref = [mathieu_b(1, "0.2", dps=30), mathieu_a(1, "0.2", dps=30),
           mathieu_b(2, "0.2", dps=30), mathieu_a(2, "0.2", dps=30)]
    for g, r in zip(got, ref):
        assert abs(g - float(r)) < 1e-14 * max(1, abs(float(r)))
