"""The vectorised inverse and exponent against MathieuFunctions.jl's lambda grid
: lambda_nu(q) for nu = 0, 0.01, ..., 2 and q = -5 ... 5, computed
with Mathematica (tests/data/mathieu_lambda_grid.csv says which rows and
columns are kept, and where they come from).

Our theta0_of_exponent(nu, theta1) is lambda_nu(q) with q = -theta1
(DLMF 28.2.16-17: lambda_n = a_n at integer nu).  The whole grid (201 x 1001
points) was measured with ``python benchmarks/bench_map.py`` given the full
file (docs/floquet.md); here the kept rows include the hardest ones, next to
the integers.
"""

import os

import numpy as np
import pytest

from pendulab.analyses.floquet import exponent, theta0_of_exponent

DATA = os.path.join(os.path.dirname(__file__), "data", "mathieu_lambda_grid.csv")


@pytest.fixture(scope="module")
def grid():
    nu, q, lam = np.loadtxt(DATA, delimiter=",", comments="#", unpack=True)
    return nu, q, lam


def test_inverse_on_the_lambda_grid(grid):
    nu, q, lam = grid
    assert nu.size == 17 * 251
    got = theta0_of_exponent(nu, -q)
    err = np.abs(got - lam) / np.maximum(1.0, np.abs(lam))
    # docs/floquet.md: 1.4e-15 on the whole grid (Mathematica's values carry
    # rounding of their own, up to ~1e-15 against our 30-digit values)
    assert err.max() <= 2e-15
    # the scalar double path gives the same numbers to rounding
    for i in (3, 400, 1200, 2100, 2500):
        assert abs(theta0_of_exponent(float(nu[i]), float(-q[i])) - lam[i]) <= 2e-15 * max(1, abs(lam[i]))


def test_exponent_on_the_lambda_grid(grid):
    nu, q, lam = grid
    frac = nu % 1 != 0
    got = exponent(lam, -q)
    assert np.all(got[frac].imag == 0)
    # next to a band edge nu moves like the square root of theta0, so the
    # error is measured backwards: |lam - nu| times d lambda/d nu, the slope
    # from the grid's own rows 0.01 and 0.02 away on the side inside the band
    # (three-point one-sided difference, exact for the parabola at an edge)
    table = {(round(a, 2), round(b, 2)): c for a, b, c in zip(nu, q, lam)}
    checked = 0
    for a, b, c, g in zip(nu, q, lam, got.real):
        a, b = round(a, 2), round(b, 2)
        if a % 1 == 0 or abs(a - round(a) - 0.5) < 1e-9:
            continue
        h = 0.01 if a - np.floor(a) < 0.5 else -0.01
        k1, k2 = (round(a + h, 2), b), (round(a + 2 * h, 2), b)
        if k1 not in table or k2 not in table or k2[0] % 1 == 0:
            continue
        f1, f2 = table[k1], table[k2]
        slope = abs(-3 * c + 4 * f1 - f2) / (2 * 0.01)
        assert abs(g - a) * slope <= 4e-15 * max(1.0, abs(c)), (a, b)
        checked += 1
    assert checked == 4 * 251  # rows 0.01, 0.99, 1.01, 1.99: next to the edges
    # and forwards where the band is wide (|q| <= 2: d lambda/d nu >= 0.5 at nu = 1/2, 3/2)
    mid = (np.abs(nu - np.rint(nu)) >= 0.4) & (np.abs(q) <= 2)
    assert np.max(np.abs(got.real - nu)[mid]) <= 1e-14
