"""Vectorised double-precision lambda(theta0, theta1) and theta0(nu, theta1)
(audit item 5) against the scalar multi-precision API on seeded random grids.

References: characteristic_exponent(method="cf", dps=25) -- the source's
continued fractions, a different route from the vectorised Hill determinant
-- and the scalar theta0_of_exponent at dps=20 (cf root in theta0).
Measured worst errors (one run): 1.1e-13 for lam on the random grid, 5e-12 at
1e-8 from an edge, 3.5e-10 at 1e-12 from an edge (arccos of the trace alone:
3.3e-9); 2.5e-14 (relative) for the inverse.  The tolerances below are a few
times those.
"""

import mpmath
import numpy as np
import pytest

from pendulab.analyses.floquet import (
    characteristic_exponent,
    exponent,
    mathieu_a,
    mathieu_b,
    theta0_of_exponent,
    trace_monodromy,
)
from pendulab.errors import InputError


def _ref(t0, t1):
    return complex(characteristic_exponent(float(t0), float(t1), dps=25, method="cf").lam)


def test_exponent_on_a_random_grid(rng):
    # bands and gaps (about half of the points are unstable), theta1 of both signs
    t0 = rng.uniform(-3, 20, 40)
    t1 = rng.uniform(-10, 10, 40)
    lam = exponent(t0, t1)
    assert lam.dtype == complex and lam.shape == (40,)
    unstable = 0
    for a, b, got in zip(t0, t1, lam):
        ref = _ref(a, b)
        assert abs(got - ref) <= 1e-12
        unstable += ref.imag != 0
    assert 5 <= unstable <= 35


def test_exponent_next_to_the_edges():
    # lam - m ~ sqrt(theta0 - edge): near an edge 1 - |cos(pi lam)| cancels; the
    # edge-referenced trace difference keeps the error below ~4e-10 absolute
    naive_worst = 0.0
    for kind, m, q in (("a", 0, 0.5), ("b", 1, 0.5), ("a", 1, 2.0), ("b", 2, 3.0)):
        edge = (mathieu_a if kind == "a" else mathieu_b)(m, q)
        for rel, tol in ((1e-4, 1e-12), (1e-8, 1e-10), (1e-12, 1e-9)):
            for sgn in (1, -1):
                x = edge + sgn * rel * max(1.0, abs(edge))
                got = exponent(np.array([x]), -q)[0]
                ref = _ref(x, -q)
                assert abs(got - ref) <= tol
                if rel == 1e-12 and sgn == -1 and kind == "b":  # inside the band
                    y = trace_monodromy(x, -q) / 2
                    naive = np.arccos(np.clip((-1) ** m * y, -1, 1)) / np.pi
                    naive_worst = max(naive_worst, abs(naive - abs(ref - m)))
    # lam from arccos(trace/2) alone is worse there (3.3e-9 measured at b_2(3)):
    # the tolerance is tight enough to tell the two apart
    assert naive_worst > 1e-9


def test_exponent_broadcasts_and_matches_scalar_types():
    t0 = np.linspace(-1, 5, 4)[:, None]
    t1 = np.array([0.0, 0.3, -2.0])[None, :]
    lam = exponent(t0, t1)
    assert lam.shape == (4, 3)
    # theta1 = 0: lam = sqrt(theta0) exactly (imaginary for theta0 < 0)
    np.testing.assert_allclose(lam[:, 0], np.sqrt(t0[:, 0] + 0j), rtol=1e-14, atol=1e-14)
    with pytest.raises(InputError, match="exponent\\(theta0, theta1\\)"):
        characteristic_exponent(np.array([0.1, 0.2]), 0.1)
    with pytest.raises(InputError, match="broadcast"):
        exponent(np.zeros(3), np.zeros(4))


def test_inverse_on_a_random_grid(rng):
    nu = np.concatenate([rng.uniform(0, 3, 24), [1 - 1e-9, 1 + 1e-9, 2.0, 1.0, 1e-12]])
    th = np.concatenate([rng.uniform(-6, 6, 24), [0.2, 0.2, 0.7, 0.2, 100.0]])
    got = theta0_of_exponent(nu, th)
    assert got.shape == nu.shape
    for n, t, g in zip(nu, th, got):
        ref = float(theta0_of_exponent(float(n), float(t), dps=20))
        assert abs(g - ref) <= 2e-13 * max(1.0, abs(ref))
    # forward and back: the vectorised exponent of the vectorised inverse
    inner = (nu % 1 > 1e-3) & (nu % 1 < 1 - 1e-3)
    np.testing.assert_allclose(exponent(got[inner], th[inner]).real, nu[inner], atol=1e-11)
    with pytest.raises(InputError, match="double precision"):
        theta0_of_exponent(nu, th, dps=20)
