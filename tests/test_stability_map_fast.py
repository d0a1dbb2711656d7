"""The inverted pendulum's stable/unstable map: equal to the pointwise
exact verdicts, right for every stable band in the grid's range, and right for
the rod (I/(m l^2) = 4/3).

References, independent of the code under test:

* the pointwise verdict of characteristic_exponent (Sturm count of the band
  plus the sign of u from Hill's determinant, at exact rational inputs) with
  theta0 = -4 (omega0/omega)^2 (000 eq. 5) and theta1 = 2 (a/l)/(I/(m l^2))
  (000 eq. 6) typed here from the source, in exact Fractions of the grid's
  doubles;
* SciPy's characteristic values scipy.special.mathieu_a / mathieu_b (Zhang &
  Jin's algorithm; relative error below 5e-15 for a_0 and b_1 up to q = 1e4,
  docs/floquet.md) for the band edges, solved for q with scipy.optimize.brentq;
  the first stable band of the inverted pendulum is a_0(|q|) < theta0 <
  b_1(|q|), the next one a_1(|q|) < theta0 < b_2(|q|) (DLMF 28.2(v), 28.17).
"""

from fractions import Fraction as F

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

from pendulab import symbols as S
from pendulab.analyses.floquet import characteristic_exponent, is_stable
from pendulab.analyses.stability_map import map_stability, stability_limits, stability_map
from pendulab.errors import InputError


def _exact(ratio, al, inertia=1.0):
    """Pointwise verdict at the exact values of the doubles (000 eqs. 5-6)."""
    th0 = -4 * F(float(ratio)) ** 2
    th1 = 2 * F(float(al)) / F(float(inertia))
    return characteristic_exponent(th0, th1).stable


def _edge_q(fn, m, theta0, hi=60.0):
    """|q| > 0 where SciPy's characteristic value fn(m, q) equals theta0."""
    return brentq(lambda q: fn(m, q) - theta0, 1e-9, hi, xtol=1e-15, rtol=1e-15)


def test_cells_next_to_the_curves_are_decided_exactly():
    # columns at the exact limits of three rows and 1, 2 ulps either side:
    # those cells lie within double-precision resolution of a_0 or b_1, so
    # the map must decide them exactly, and match the pointwise verdict
    rows = np.array([0.05, 0.1, 0.3])
    cols = [0.02, 0.3, 0.9]
    for r in rows:
        for lim in stability_limits(str(r), 1, dps=30):
            x = float(lim)
            cols += [x, np.nextafter(x, 0), np.nextafter(x, 1),
                     np.nextafter(np.nextafter(x, 0), 0), np.nextafter(np.nextafter(x, 1), 1)]
    cols = np.array(cols)
    m = stability_map(cols, rows)
    assert m.shape == (3, cols.size)
    near = 3 * 2 * 5
    assert near <= map_stability.last_exact <= near + 6
    for i, r in enumerate(rows):
        for j, a in enumerate(cols):
            assert m[i, j] == _exact(r, a), (r, a)
    # both verdicts occur among the near cells of each limit
    for i in range(3):
        block = m[i, 3 + 10 * i: 13 + 10 * i]
        assert block.any() and not block.all()


def test_map_equals_pointwise_exact_on_a_sample(rng):
    al = np.linspace(0.0, 1.0, 301)
    ra = np.linspace(0.0, 1.0, 211)
    m = stability_map(al, ra)
    # (0, 0): theta0 = 0 = a_0(0) exactly, on the curve: unstable (decided exactly)
    assert not m[0, 0] and map_stability.last_exact >= 1
    for _ in range(60):
        i, j = int(rng.integers(0, ra.size)), int(rng.integers(0, al.size))
        assert m[i, j] == _exact(ra[i], al[j])
    # away from the curves the double-precision verdict of is_stable agrees everywhere
    assert np.array_equal(m, is_stable(-4 * ra[:, None] ** 2, 2 * al[None, :]))


def test_rod_map_follows_the_inertia_ratio():
    # the rod's limits are those of the Mathieu plane times
    # I/(m l^2)/2 (000 eq. 6); SciPy's a_0, b_1 give them independently
    inertia = 4.0 / 3.0
    rows = np.array([0.0, 0.05, 0.1, 0.2])
    cols, expect = [], []
    for r in rows:
        th0 = -4.0 * r * r
        lo = 0.0 if r == 0 else inertia / 2 * _edge_q(mathieu_a, 0, th0)
        up = inertia / 2 * _edge_q(mathieu_b, 1, th0)
        for a, inside in ((lo * (1 - 1e-6), False), (lo * (1 + 1e-6) + 1e-9, True),
                          (0.5 * (lo + up), True), (up * (1 - 1e-6), True),
                          (up * (1 + 1e-6), False)):
            cols.append(a)
            expect.append((r, inside))
    cols = np.array(cols)
    m = stability_map(cols, rows, inertia_ratio=inertia)
    point = stability_map(cols, rows, inertia_ratio=1.0)
    for j, (r, inside) in enumerate(expect):
        i = int(np.nonzero(rows == r)[0][0])
        assert bool(m[i, j]) is inside, (r, cols[j])
    # the point mass's map differs on those columns (its band is 3/4 as wide in a/l)
    assert not np.array_equal(m, point)
    # and the rod's map is the point mass's map at a/l scaled by 3/4
    al = np.linspace(0.0, 1.0, 97)
    assert np.array_equal(stability_map(al, rows, inertia), stability_map(al * 0.75, rows, 1.0))


def test_rod_map_on_a_grid_against_pointwise_verdicts(rng):
    al = np.linspace(0.0, 1.0, 120)
    ra = np.linspace(0.0, 0.6, 80)
    m = stability_map(al, ra, inertia_ratio=4 / 3)
    for _ in range(40):
        i, j = int(rng.integers(0, ra.size)), int(rng.integers(0, al.size))
        assert m[i, j] == _exact(ra[i], al[j], 4 / 3)
    lo, up = stability_limits("0.3", "4/3", dps=20)
    i = int(np.argmin(np.abs(ra - 0.3)))
    r = ra[i]
    lo, up = (float(x) for x in stability_limits(repr(float(r)), "4/3", dps=20))
    assert m[i].tolist() == [lo < a < up for a in al]


def test_higher_band_at_large_theta1():
    # at |q| = 10 the second stable band a_1 < theta0 < b_2 lies at theta0 < 0
    # (a_1(10) = -2.399, b_2(10) = -2.382); a map fine enough to resolve it
    q = 10.0
    a1, b2 = mathieu_a(1, q), mathieu_b(2, q)
    assert a1 < b2 < 0
    r_lo, r_hi = np.sqrt(-b2 / 4), np.sqrt(-a1 / 4)
    ra = np.linspace(r_lo - 0.002, r_hi + 0.002, 61)
    al = np.array([q / 2])  # theta1 = 2 a/l = q
    m = stability_map(al, ra)[:, 0]
    th0 = -4 * ra ** 2
    inside = (th0 > a1) & (th0 < b2)
    assert inside.sum() >= 20
    clear = np.minimum(np.abs(th0 - a1), np.abs(th0 - b2)) > 1e-9
    assert np.array_equal(m[clear], inside[clear])
    for i in (0, int(np.argmax(inside)), ra.size - 1):
        assert m[i] == _exact(ra[i], al[0])


def test_higher_bands_on_a_wide_grid_against_pointwise(rng):
    # |q| from 7.9 to 8.1: the second band (a_1 < theta0 < b_2, near
    # omega0/omega = 0.32) and the first, thin one (near 1.63: at q = 8 it is
    # 1.3e-3 wide in theta0); rows dense around both
    al = np.linspace(3.95, 4.05, 21)
    ra = np.concatenate([np.linspace(0.25, 0.40, 120), np.linspace(1.61, 1.645, 700)])
    m = stability_map(al, ra)
    toggles = np.abs(np.diff(m.astype(int), axis=0)).sum(axis=0)
    assert toggles.min() >= 4  # every column crosses both bands
    cols = np.nonzero(toggles >= 3)[0]
    for j in cols[:4]:
        for i in np.nonzero(np.diff(m[:, j].astype(int)))[0][:4]:
            for k in (i, i + 1):
                assert m[k, j] == _exact(ra[k], al[j])
    assert np.array_equal(m, is_stable(-4 * ra[:, None] ** 2, 2 * al[None, :]))


class _StubMap:
    """A ParameterMap-like Mathieu map whose theta0 involves a/l (not separable)."""

    def __init__(self):
        self.theta0 = -4 * S.w0_over_w ** 2 + S.a_over_l ** 2 / 4
        self.theta1 = 2 * S.a_over_l + S.w0_over_w / 8
        self.symbols = (S.a_over_l, S.w0_over_w)

    def evaluate(self, which, point, module="numpy"):
        expr = {"theta0": self.theta0, "theta1": self.theta1}[which]
        return sp.lambdify(self.symbols, expr, module)(point["a_over_l"], point["w0_over_w"])


def test_general_path_for_a_map_that_is_not_separable(rng):
    pm = _StubMap()
    al = np.linspace(0.0, 2.0, 90)
    ra = np.linspace(0.0, 1.0, 70)
    m = map_stability(pm, al, ra)
    A, R = np.meshgrid(al, ra)
    th0 = -4 * R ** 2 + A ** 2 / 4
    th1 = 2 * A + R / 8
    assert np.array_equal(m, is_stable(th0, th1))
    for _ in range(30):
        i, j = int(rng.integers(0, ra.size)), int(rng.integers(0, al.size))
        a, r = F(float(al[j])), F(float(ra[i]))
        assert m[i, j] == characteristic_exponent(-4 * r * r + a * a / 4, 2 * a + r / 8).stable


def test_map_input_errors_and_empty_grids():
    assert stability_map([], [0.1]).shape == (1, 0)
    with pytest.raises(InputError, match="finite"):
        stability_map([0.1, np.nan], [0.1])
    with pytest.raises(InputError, match="one-dimensional"):
        stability_map([[0.1]], [0.1])
    with pytest.raises(InputError, match="too large"):
        stability_map([1e7], [0.1])


def test_map_of_a_hill_drive_is_refused_in_one_line():
    from pendulab.analyses.stability import ParameterMap
    from pendulab.canonical import periodic_form
    from pendulab.equations import derive
    from pendulab.exprs import parse
    from pendulab.systems import DrivenPivot

    eqs = derive(DrivenPivot(body="rod", drive=parse("a*cos(omega*t) + a*cos(2*omega*t)")))
    with pytest.raises(InputError, match="hill equation"):
        map_stability(ParameterMap(eqs, periodic_form(eqs)), [0.1], [0.1])


def test_map_at_large_theta1_against_is_stable():
    # |q| up to 4000: hundreds of characteristic values below theta0 = 0 per
    # |q| (the predictor then works with LAPACK at the nodes, the corrector in blocks)
    al = np.linspace(0.0, 2000.0, 60)
    ra = np.linspace(0.0, 1.0, 50)
    m = stability_map(al, ra)
    assert np.array_equal(m, is_stable(-4 * ra[:, None] ** 2, 2 * al[None, :]))
    assert map_stability.last_exact <= 2
