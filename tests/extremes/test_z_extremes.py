"""The Bessel identities at z = 1e-300 and 1e300 (the ends of the double range).

References: DLMF 10.5.1, W{J_n, Y_n}(z) = 2/(pi z), and the cross product
J_n Y_{n+1} - J_{n+1} Y_n = -2/(pi z) (002 "Afirmacao"; DLMF 10.5.2 with
10.6.2), exact; D = lim z W = 2/pi (002 "Demonstracao").  mpmath's
hypergeometric/asymptotic besselj, bessely (and their derivatives) are the
second engine: every value must lie in arb's ball.  Before the fix in
bessel_identities._arb_values the check at z >= ~1e19 never returned (the
64-bit bound on f'''' was NaN, so the derivative loop doubled its precision
without end).
"""

import mpmath
import pytest

from pendulab.analyses import bessel_identities as bi
from pendulab.errors import InputError

EXTREMES = [1e-300, 1e300]


@pytest.mark.parametrize("z", EXTREMES + [1e20])
def test_every_identity_certified_at_the_ends_of_the_double_range(z):
    rep = bi.check_identities(2, 30, [z], engines=("arb",))
    assert rep.arb_certified
    assert rep.worst[0] < mpmath.mpf(10) ** -30          # relative to 2/(pi z)


def test_both_engines_agree_at_both_ends():
    # mpmath's values (its own formulas) lie in arb's balls widened by 1e-35 relative, at
    # z where J, Y are ~1e-150 (1e300) and Y_3 ~ 1e900 (1e-300)
    rep = bi.check_identities(2, 30, EXTREMES)
    assert rep.arb_certified and rep.agreements == 2 * (4 + 4 + 3 + 3)   # J_0..3, Y_0..3, J_0..2', Y_0..2'
    assert rep.worst[0] < mpmath.mpf(10) ** -30
    with mpmath.workdps(40):                               # D = 2/pi, read at z = 1e-300
        for engine in ("arb", "mpmath"):
            assert abs(rep.limit_D[engine] - 2 / mpmath.pi) < mpmath.mpf(10) ** -30


def test_a_wrong_value_at_1e300_is_caught(monkeypatch):
    # the certificate refuses a candidate off by 1e-25 relative: mpmath's Y_1 perturbed
    real = bi._mp_values

    def broken(n_top, z, dps, derivatives=True):
        J, Y, dJ, dY = real(n_top, z, dps, derivatives)
        Y[1] = Y[1] * (1 + mpmath.mpf("1e-25"))
        return J, Y, dJ, dY
    monkeypatch.setattr(bi, "_mp_values", broken)
    with pytest.raises(bi.EngineDisagreement, match="disagree on Y_1"):
        bi.check_identities(2, 30, [1e300])


@pytest.mark.parametrize("z", [0.0, -1e-300, float("inf"), float("nan")])
def test_beyond_the_ends_is_refused_in_one_line(z):
    with pytest.raises(InputError, match="z must be a positive number"):
        bi.check_identities(1, 20, [z])


def test_the_check_at_1e300_returns_within_a_minute():
    # before the fix the derivative loop at z >= ~1e19 never ended: run it where a hang
    # is a failure, not a stuck suite
    import subprocess
    import sys
    code = ("from pendulab.analyses.bessel_identities import check_identities\n"
            "r = check_identities(2, 30, [1e300], engines=('arb',))\n"
            "print(r.arb_certified)\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.strip() == "True", p.stderr
