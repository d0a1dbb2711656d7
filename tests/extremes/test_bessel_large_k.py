"""Bessel zeros with k = 10^5: McMahon's expansion (DLMF 10.21.19) as the reference.

At k = 10^5, a = (k + nu/2 - 1/4) pi ~ 3.1e5 and the first omitted term of five is
O((8a)^-9) ~ 1e-50 (the error of the five terms falls like k^-9: 8.7e-22 at k = 100,
8.5e-31 at k = 1000 against mpmath.besseljzero at 60 digits), so the expansion typed
from DLMF in tests/extremes/_dlmf.py is good to ~45 digits there.

The whole chain of 10^5 certified zeros takes about a minute (the index of each is
proved from the one before); here the zero number 10^5 alone is certified by the
pieces the chain uses: McMahon's start as derived by the code (series reversion of
Hankel's expansion, not the DLMF coefficients), interval Newton (a proof that the
ball holds exactly one zero) and the asymptotic phase for its index.  Each certificate
is fed a wrong candidate too.
"""

from fractions import Fraction

import mpmath
import pytest

from pendulab.analyses.bessel_zeros import (
    CertificationError,
    ball_digits,
    bessel_zeros,
    interval_newton,
    mcmahon_start,
    phase_index,
)

from ._dlmf import mcmahon

K = 100_000
BITS = 200


@pytest.mark.parametrize("nu", [Fraction(0), Fraction(1), Fraction(2), Fraction(1, 3)])
def test_zero_number_1e5_against_dlmf_10_21_19(nu):
    x, acc = mcmahon_start(nu, K, BITS)
    assert acc >= 150                              # the derived expansion is this good here
    ball = interval_newton(nu, x, mpmath.mpf(2) ** -150 * 4e5, BITS)   # proves one zero in it
    assert phase_index(nu, ball.mid()) == K
    text = ball_digits(ball, 45)
    assert text is not None
    with mpmath.workdps(60):
        ref = mcmahon(mpmath.mpf(nu.numerator) / nu.denominator, K)
        assert abs(mpmath.mpf(text) - ref) < mpmath.mpf(10) ** -44 * ref


def test_wrong_candidates_are_refused():
    nu = Fraction(1)
    x, _ = mcmahon_start(nu, K, BITS)
    with mpmath.workdps(60):
        off = mpmath.mpf(x.str(60, radius=False)) + mpmath.mpf("1e-20")
    # a ball of radius 1e-30 around a point 1e-20 from the zero holds none: refused
    with pytest.raises(CertificationError, match="not inside it"):
        interval_newton(nu, mpmath.nstr(off, 60), "1e-30", BITS)
    # half a spacing away (pi/2): the phase gives no index and Newton no certificate
    with mpmath.workdps(60):
        half = mpmath.mpf(x.str(60, radius=False)) + mpmath.pi / 2
    assert phase_index(nu, mpmath.nstr(half, 30)) is None
    with pytest.raises(CertificationError):
        interval_newton(nu, mpmath.nstr(half, 60), "1e-30", BITS)


def test_the_chain_agrees_with_the_single_zero_at_k_2000():
    # the chain's last zero (2000 of them, each index proved) is the single-zero route's
    z = bessel_zeros(1, 2000, 30)
    x, _ = mcmahon_start(Fraction(1), 2000, BITS)
    ball = interval_newton(Fraction(1), x, mpmath.mpf(2) ** -140 * 1e4, BITS)
    assert ball_digits(ball, 30) == z.strings[-1] and z.phase_checked == 2000
