"""Tests that close the gaps mutation testing found in the band counts, the stability map and
Hill's determinant (docs/mutation.md): each pins a behaviour that a small edit of the code
changed without any earlier test noticing.

References, independent of the code under test:

* eigenvalues of small symmetric matrices by numpy.linalg.eigvalsh;
* the continued-fraction tail ratio theta1^2 / (C_m C_{m+2}), C_m = theta0 - m^2 (000 eq. 10),
  multiplied out here in exact Fractions;
* the band edges a_0(q), b_1(q) of SciPy (scipy.special.mathieu_a / mathieu_b, Zhang & Jin's
  algorithm): the first stable band of theta'' + (theta0 + 2 theta1 cos 2 tau) theta = 0 is
  a_0(|theta1|) < theta0 < b_1(|theta1|) (DLMF 28.2(v), 28.17);
* the monodromy matrix of theta'' + P(tau) theta = 0 integrated by mpmath.odefun (Taylor
  series), and theta'' = 0, whose monodromy matrix [[1, T], [0, 1]] has trace exactly 2;
* the pointwise verdict of characteristic_exponent at exact Fractions of the grid's doubles,
  with theta0 = -4 (omega0/omega)^2 (000 eq. 5) and theta1 = 2 (a/l)/(I/(m l^2)) (000 eq. 6)
  typed here from the source.
"""

import math
from fractions import Fraction as F

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy.special import mathieu_a, mathieu_b

from pendulab import symbols as S
from pendulab.analyses import hill_general as H
from pendulab.analyses.floquet import _bands as B
from pendulab.analyses.floquet import characteristic_exponent
from pendulab.analyses.stability_map import _exact_verdict, map_limits, map_stability, stability_map
from pendulab.errors import ConvergenceError, InputError

# ---------------------------------------------------------------------------
# _bands: the Sturm count on doubles, the continued-fraction depth rule
# ---------------------------------------------------------------------------


def test_sturm_count_on_doubles_reads_an_exactly_zero_pivot_as_a_tiny_one():
    """d = (0, -0.5), e2 = (0.01,), x = 0: the first pivot is exactly 0.  The matrix
    [[0, 0.1], [0.1, -0.5]] has one eigenvalue below 0 (eigvalsh); a zero pivot replaced by a
    number of order 1 (instead of a tiny one) would make the second pivot negative too."""
    d, e2 = [0.0, -0.5], [0.01]
    M = np.array([[0.0, 0.1], [0.1, -0.5]])
    expected = int(np.sum(np.linalg.eigvalsh(M) < 0.0))
    assert expected == 1
    assert B._sturm_count(d, e2, 0.0) == expected


def test_sturm_count_at_working_precision_reads_an_exactly_zero_pivot_as_a_tiny_one():
    """The same matrix in mpf (the input of _edge_count): the zero pivot is replaced by a
    number below every rounding of the working precision, not by a large one."""
    with mpmath.workdps(30):
        d, e2 = [mpmath.mpf(0), mpmath.mpf("-0.5")], [mpmath.mpf("0.01")]
        assert B._sturm_count(d, e2, mpmath.mpf(0)) == 1


@pytest.mark.parametrize("theta0,theta1,digits", [
    (30.0, 1.0, 30),      # theta0 > 0: |theta0 + m^2| would overstate |C_m| = m^2 - theta0
    (99.0, 0.5, 50),
    (0.5, 0.3, 20),       # |theta1| < 1: log theta1 < 0
    (-50.0, 5.0, 40),
    (-20.0, 1.0, 20),     # the product ends just below 10^-digits: one level fewer misses it
    (-19.0, 2.0, 30),
])
def test_tail_steps_reach_the_asked_digits_before_their_margin(theta0, theta1, digits):
    """The levels counted by _tail_steps, without the 2 it adds as a margin, already bring the
    product of the tail ratios theta1^2 / |C_m C_{m+2}| (m = m0, m0 + 2, ...; 000 eq. 10)
    below 10^-digits.  A rule that counted the ratios too small (|theta0 + m^2|, a wrong
    index) stops too early."""
    m0 = B._edge_index(theta0, theta1)
    levels = B._tail_steps(theta0, theta1, m0, digits) - 2
    t0, t1 = F(theta0), F(abs(theta1))
    prod, m = F(1), m0
    for _ in range(levels):
        prod *= t1 * t1 / (abs(t0 - m * m) * abs(t0 - (m + 2) * (m + 2)))
        m += 2
    assert prod < F(1, 10 ** digits)


# ---------------------------------------------------------------------------
# stability_map
# ---------------------------------------------------------------------------


def _exact(ratio, al):
    """Pointwise verdict at the exact values of the doubles (000 eqs. 5-6, I/(m l^2) = 1)."""
    return characteristic_exponent(-4 * F(float(ratio)) ** 2, 2 * F(float(al))).stable


def test_map_with_rows_out_of_order_is_a_bool_array_of_the_pointwise_verdicts():
    """Rows neither ascending nor descending take the general reordering of the verdicts."""
    al = np.array([0.02, 0.1, 0.3, 0.45, 0.6])
    ra = np.array([0.3, 0.05, 0.2])
    m = stability_map(al, ra)
    assert m.dtype == np.bool_
    assert [[bool(x) for x in row] for row in m] == [[_exact(r, a) for a in al] for r in ra]


class _NotSeparable:
    """A Mathieu map whose theta0 involves a/l and theta1 omega0/omega."""

    def __init__(self):
        self.theta0 = -4 * S.w0_over_w ** 2 + S.a_over_l
        self.theta1 = 2 * S.a_over_l + S.w0_over_w / 8
        self.symbols = (S.a_over_l, S.w0_over_w)

    def evaluate(self, which, point, module="numpy"):
        expr = {"theta0": self.theta0, "theta1": self.theta1}[which]
        return sp.lambdify(self.symbols, expr, module)(point["a_over_l"], point["w0_over_w"])


@pytest.mark.parametrize("rows,cols", [(1, 24), (24, 1)])
def test_map_that_is_not_separable_on_one_row_or_one_column(rows, cols):
    """One row (or column) of a map whose theta0 varies along a/l: the cells must not share
    the first cell's theta0 (the per-column route is for separable maps only; on the row
    below, 4 of the 24 cells would change their verdict)."""
    al = np.linspace(0.0, 2.0, cols) if cols > 1 else np.array([0.9])
    ra = np.linspace(0.0, 1.0, rows) if rows > 1 else np.array([0.3])
    m = map_stability(_NotSeparable(), al, ra)
    assert m.shape == (rows, cols)
    for i, r in enumerate(ra):
        for j, a in enumerate(al):
            A, R = F(float(a)), F(float(r))
            assert m[i, j] == characteristic_exponent(-4 * R * R + A, 2 * A + R / 8).stable, (i, j)


class _Irrational:
    """A map whose theta0 holds an irrational number (pi) or a SymPy Float."""

    def __init__(self, shift):
        self.theta0 = -4 * S.w0_over_w ** 2 + shift
        self.theta1 = 2 * S.a_over_l
        self.symbols = (S.a_over_l, S.w0_over_w)


def _first_band(theta0, theta1):
    """a_0(|theta1|) < theta0 < b_1(|theta1|) by SciPy's characteristic values."""
    q = abs(theta1)
    return bool(mathieu_a(0, q) < theta0 < mathieu_b(1, q))


@pytest.mark.parametrize("shift", [sp.pi / 100, sp.Float(0.03)])
@pytest.mark.parametrize("al", [0.1, 0.01])
def test_exact_verdict_of_a_map_with_irrational_or_float_terms(shift, al):
    """theta0 = -0.04 + pi/100 (irrational: evaluated to 60 digits) or -0.04 + 0.03 (a SymPy
    Float: its exact binary value); theta1 = 0.2 lies in the first band, 0.02 in the gap
    below it (SciPy's a_0 and b_1, far from either edge)."""
    theta0 = -0.04 + float(shift)
    expected = _first_band(theta0, 2 * al)
    assert expected == (al == 0.1)
    assert _exact_verdict(_Irrational(shift), {}, al, 0.1) is expected


# ---------------------------------------------------------------------------
# hill_general
# ---------------------------------------------------------------------------


def test_extrapolation_removes_the_third_to_fifth_powers():
    """D_N = D + a N^-3 + b N^-4 + c N^-5 at N = N0, 2 N0, 4 N0, 8 N0: the extrapolation
    gives D up to rounding (a leftover N^-4 or N^-5 term would be ~1e-5 here)."""
    D, a, b, c, N0 = 0.7, 1.0, -2.0, 3.0, 10
    values = [D + a / N ** 3 + b / N ** 4 + c / N ** 5 for N in (N0, 2 * N0, 4 * N0, 8 * N0)]
    assert abs(H._extrapolate(values) - D) < 1e-12


def _odefun_trace(P, T):
    """tr M of theta'' + P(tau) theta = 0 over [0, T] by mpmath.odefun (Taylor series)."""
    with mpmath.workdps(20):
        def rhs(t, y):
            return [y[1], -P(t) * y[0]]
        first = mpmath.odefun(rhs, 0, [1, 0])(T)
        second = mpmath.odefun(rhs, 0, [0, 1])(T)
        return float(first[0] + second[1])


def test_a_drive_without_a_constant_term_has_a_zero_one():
    """{2: (0.4, 0)} (no A_0 given) is theta'' + 0.4 cos(2 tau) theta = 0."""
    ref = _odefun_trace(lambda t: 0.4 * mpmath.cos(2 * t), mpmath.pi)
    h = H.hill_trace({2: (0.4, 0.0)}, math.pi)
    assert abs(h.trace - ref) < 1e-9
    assert h.stable is (abs(ref) < 2)


def test_theta_double_prime_zero_has_trace_two_and_is_not_stable():
    """theta'' = 0: theta = tau grows, the monodromy matrix [[1, pi], [0, 1]] has trace 2;
    stable means |trace| < 2, so the equation is not stable."""
    h = H.hill_trace({0: (0.0, 0.0)}, math.pi)
    assert h.trace == 2.0
    assert h.stable is False


def test_the_reported_depth_and_period_are_the_ones_used(monkeypatch):
    """depth is the largest truncation N whose determinant was taken; period is T."""
    used = []
    det = H._det

    def recording(c, d, s, N):
        used.append(N)
        return det(c, d, s, N)

    monkeypatch.setattr(H, "_det", recording)
    h = H.hill_trace({0: (-0.01, 0.0), 1: (0.3, 0.1)}, 2 * math.pi)
    assert h.depth == max(used)
    assert h.period == 2 * math.pi
    used.clear()
    h = H.hill_trace({0: (-0.01, 0.0), 2: (0.4, 0.0)}, math.pi)
    assert h.depth == max(used)
    assert h.period == math.pi


@pytest.mark.parametrize("error,refused", [(1.5e-6, True), (0.5e-6, False)])
def test_two_extrapolations_that_differ_are_refused(monkeypatch, error, refused):
    """theta0 = -0.01, theta1 = 0.2 (the trace is about 1.9): the two extrapolations made to
    differ so that the check's error 2 |y2 - y1| is 1.5e-6 (past the tolerance
    1e-6 max(1, |y2|) when |y2| < 1) or 0.5e-6 (inside it).  Hill's relation
    y = cos(T s) + D (cos(T sigma) - cos(T s)) with s = 1 (d/2, farthest from the poles),
    cos(T sigma) = cosh(pi sqrt(0.01)): y2 - y1 = (D2 - D1) (cosh(pi/10) + 1).  D1 = 0.9
    puts y2 near 0.85."""
    span = math.cosh(math.pi / 10) + 1.0
    delta = error / (2 * span)
    out = iter([0.9, 0.9 + delta])
    monkeypatch.setattr(H, "_extrapolate", lambda values: next(out))
    fourier = {0: (-0.01, 0.0), 2: (0.4, 0.0)}
    if refused:
        with pytest.raises(ConvergenceError, match="did not converge"):
            H.hill_trace(fourier, math.pi)
    else:
        h = H.hill_trace(fourier, math.pi)
        assert abs(h.trace / 2 - (-1 + (0.9 + delta) * span)) < 1e-12
        assert abs(h.error - error) < 1e-12


def _a0(q, dps=60, rows=30):
    """a_0(q) as the least eigenvalue of the DLMF 28.4.5 matrix (diagonal (2j)^2, off-diagonal
    q, sqrt(2) q in the first place), 30 rows at 60 digits by mpmath.eigsy."""
    with mpmath.workdps(dps):
        M = mpmath.zeros(rows)
        for j in range(rows):
            M[j, j] = mpmath.mpf(2 * j) ** 2
            if j + 1 < rows:
                M[j, j + 1] = M[j + 1, j] = q
        M[0, 1] = M[1, 0] = mpmath.sqrt(2) * q
        return min(mpmath.eigsy(M, eigvals_only=True))


@pytest.mark.parametrize("side", [1, -1])
def test_exact_verdict_of_an_irrational_theta0_a_hair_from_an_edge(side):
    """theta0 = a_0(q) +- sqrt(2) 10^-25 (irrational), q = theta1 = 2 * 0.1: above a_0 the
    first band (stable), below it the gap (unstable).  15 significant digits of theta0 (about
    0.02) would round it by up to 5e-18 and put one of the two on the wrong side."""
    al = ra = 0.1
    with mpmath.workdps(60):
        q = 2 * mpmath.mpf(F(al).numerator) / F(al).denominator
        a0 = _a0(q)
        shift_text = mpmath.nstr(a0 + 4 * (mpmath.mpf(F(ra).numerator) / F(ra).denominator) ** 2,
                                 50)
    shift = sp.Rational(shift_text) + side * sp.sqrt(2) / 10 ** 25
    assert _exact_verdict(_Irrational(shift), {}, al, ra) is (side > 0)


def test_a_constant_term_with_an_imaginary_part_is_refused():
    """A_0 = 0.1 + 0.5i: Hill's relation needs a real c_0 (sigma = sqrt(c_0))."""
    with pytest.raises(InputError, match="A_0 must be real"):
        H.hill_trace({0: (0.1 + 0.5j, 0.0), 2: (0.4, 0.0)}, math.pi)


def test_an_extrapolation_that_is_not_a_number_is_refused(monkeypatch):
    """One of the two extrapolations NaN (an overflowed determinant): refused, not returned as
    a NaN trace (NaN passes no comparison, so the convergence check alone would let it by)."""
    out = iter([0.9, float("nan")])
    monkeypatch.setattr(H, "_extrapolate", lambda values: next(out))
    with pytest.raises(ConvergenceError, match="overflowed"):
        H.hill_trace({0: (-0.01, 0.0), 2: (0.4, 0.0)}, math.pi)


class _ThetaZeroIsTheRatio:
    """A Mathieu map with theta0 = omega0/omega and a/l = theta1 / 2 (map_limits' inputs)."""

    def __init__(self):
        self.theta0 = S.w0_over_w
        self.theta1 = 2 * S.a_over_l
        self.scale = sp.Rational(1, 2)
        self.symbols = (S.a_over_l, S.w0_over_w)
        self._fns = {}


def test_map_limits_refuses_theta0_exactly_one():
    """At theta0 = 1 (= a_1(0) = b_1(0), DLMF 28.2(v)) the band that starts at theta1 = 0 is
    not the first one: refused in one line, as for any theta0 > 1."""
    for ratio in (F(1), F(3, 2)):
        with pytest.raises(InputError, match=r"theta0 = .* >= 1"):
            map_limits(_ThetaZeroIsTheRatio(), {"w0_over_w": ratio})


@pytest.mark.parametrize("inertia", [0, -1.0, 0.0])
def test_stability_map_refuses_an_inertia_ratio_that_is_not_positive(inertia):
    """I/(m l^2) must be > 0: zero or negative is refused by name, before any evaluation."""
    with pytest.raises(InputError, match="inertia_ratio must be a positive number"):
        stability_map([0.1], [0.1], inertia_ratio=inertia)
