"""10^6 drive periods: the drift of the monodromy map's determinant (Liouville: det = 1)
and of the product of 10^6 maps against the power of the exact multiplier.

The point mass at a/l = 1/10, omega0/omega = 1/20 (theta0 = -0.01, theta1 = 0.2, band 0).
References: Liouville's formula, det M = exp(int tr A) = 1 for the pivot's linear system
(its A has zero trace); the multipliers exp(+-i pi lam) with lam from the ball-arithmetic
exponent at 40 digits (continued fractions, no integration), so tr(M^N) = 2 cos(N pi lam).

Measured (one run): DOP853, det M - 1 = -8.3e-15 and det(M^N) - 1 = -8.3e-9, i.e. the
one-period defect compounds linearly; lam from tr M is 2.7e-14 off, so after 10^6
periods the phase is 8e-8 off and tr(M^N) 3.4e-8 from 2 cos(N pi lam).  The Taylor
monodromy at 20 digits: tr(M^N) within 3.4e-16 of it and det(M^N) - 1 = -3.8e-16.
"""

import mpmath
import pytest

from pendulab.analyses.floquet import characteristic_exponent
from pendulab.canonical import periodic_form
from pendulab.equations import derive
from pendulab.numerics.model import pivot_system
from pendulab.numerics.monodromy import floquet_verdict
from pendulab.systems import DrivenPivot

N = 10 ** 6
POINT = {"a_over_l": "1/10", "w0_over_w": "1/20"}


@pytest.fixture(scope="module")
def fos():
    eqs = derive(DrivenPivot(body="point"))
    return pivot_system(eqs, periodic_form(eqs))


@pytest.fixture(scope="module")
def lam():
    r = characteristic_exponent("-1/100", "1/5", dps=40)
    assert r.stable and r.certified_digits == 40
    return r.lam


def test_taylor_monodromy_over_a_million_periods(fos, lam):
    v = floquet_verdict(fos, POINT, method="mp", dps=20)
    with mpmath.workdps(50):
        M = mpmath.matrix([list(row) for row in v.matrix])
        MN = M ** N                                           # 20 squarings at 50 digits
        drift = abs(MN[0, 0] + MN[1, 1] - 2 * mpmath.cos(N * mpmath.pi * lam))
        assert drift < mpmath.mpf(10) ** -13                  # measured 3.4e-16
        assert abs(mpmath.det(MN) - 1) < mpmath.mpf(10) ** -13


def test_dop853_monodromy_drift_is_the_one_period_defect_times_a_million(fos, lam):
    v = floquet_verdict(fos, POINT)
    (a, b), (c, d) = [[float(x) for x in row] for row in v.matrix]
    with mpmath.workdps(40):
        det1 = mpmath.mpf(a) * d - mpmath.mpf(b) * c      # exact for the doubles
    p, q, r, s = 1.0, 0.0, 0.0, 1.0
    for _ in range(N):                                       # the product of 10^6 maps
        p, q, r, s = a * p + b * r, a * q + b * s, c * p + d * r, c * q + d * s
    detN, trN = p * s - q * r, p + s
    with mpmath.workdps(40):
        # Liouville's defect compounds: det(M^N) = det(M)^N, here N (det M - 1) to 1e-3
        assert abs(detN - 1 - N * (det1 - 1)) <= 1e-3 * abs(N * (det1 - 1)) + 1e-11
        # the power of M's own multipliers, (det M)^(N/2) 2 cos(N theta), cos theta =
        # tr M/(2 sqrt(det M)): the 10^6 products add only rounding (< 1e-9)
        root = mpmath.sqrt(det1)
        theta = mpmath.acos(mpmath.mpf(a + d) / (2 * root))
        own = root ** N * 2 * mpmath.cos(N * theta)
        assert abs(trN - own) < 1e-9
        # against the exact multiplier: the drift is N pi |lam_M - lam| (phase) and the
        # determinant's, both from one period's error (v.error ~ 1e-12 bounds them)
        exact = 2 * mpmath.cos(N * mpmath.pi * lam)
        phase = N * abs(theta - mpmath.pi * lam)
        assert phase < 1e-6 and abs(trN - exact) <= 2 * phase + 2 * abs(N * (det1 - 1)) + 1e-9
        assert abs(trN - exact) > 1e-10                      # and the drift is really there
