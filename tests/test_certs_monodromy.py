"""The proof steps of the monodromy verdict, of Hill's determinant and of the sweep, each fed
a wrong candidate: two working precisions that disagree, a trace too close to 2 to decide,
a determinant that is not 1, extrapolations that do not converge, a shift that would divide
by zero, a rectangular grid read the wrong way round, cells next to the Floquet boundary.

Independent references: the continued fractions of characteristic_exponent (method "cf",
000 eqs. 8-10) at 20-30 digits; SciPy's solve_ivp (DOP853, rtol 1e-12) integrating the
fundamental matrix of theta'' + P(tau) theta = 0 written here from the Fourier
coefficients; for the point mass with the source's drive theta0 = -4 (omega0/omega)^2 and
theta1 = 2 a/l (000 eqs. 5-6).
"""

import math
import warnings
from fractions import Fraction
from functools import lru_cache

import mpmath
import numpy as np
import pytest

from pendulab.analyses import hill_general as HG
from pendulab.analyses.floquet import characteristic_exponent
from pendulab.analyses.floquet import _hill as H
from pendulab.analyses.floquet import _vectorised as V
from pendulab.errors import AccuracyWarning, ConvergenceError, PrecisionError
from pendulab.numerics import monodromy as MD
from pendulab.numerics import sweep as S


@lru_cache(maxsize=None)
def _point_fos():
    from pendulab.canonical import periodic_form
    from pendulab.equations import derive
    from pendulab.numerics.model import pivot_system
    from pendulab.systems import DrivenPivot

    eqs = derive(DrivenPivot(body="point"))
    return pivot_system(eqs, periodic_form(eqs))


PARAMS = {"a_over_l": "1/10", "w0_over_w": "1/20"}


def _matrix(tr, det, w):
    """A 2 x 2 mpf matrix with trace tr and determinant det at dps w:
    [[t/2, 1], [t^2/4 - det, t/2]]."""
    with mpmath.workdps(w):
        t = mpmath.mpf(tr)
        h = t / 2
        return [[h, mpmath.mpf(1)], [h * h - mpmath.mpf(det), h]]


def _fake_taylor(monkeypatch, traces, det="1"):
    """_taylor_monodromy returning traces[0], traces[1], traces[0], ... (the two working
    precisions of each round alternate), det as given."""
    calls = []

    def fake(entries, time, T, w):
        calls.append(w)
        return _matrix(traces[(len(calls) - 1) % 2], det, w + 5), 10
    monkeypatch.setattr(MD, "_taylor_monodromy", fake)
    return calls


# ---------------------------------------------------------------------------
# floquet_verdict, method "mp": agreement of two precisions, the margin, det M
# ---------------------------------------------------------------------------

def test_two_precisions_that_disagree_are_refused(monkeypatch):
    # the two working precisions differ by 5e-19 |tr| at every round; agreement is asked to
    # 1e-(16 + 3) |tr|: refused at max_dps (a 10x looser agreement would accept it)
    with mpmath.workdps(40):
        t = mpmath.mpf("1.5")
        calls = _fake_taylor(monkeypatch, (t, t + 5 * mpmath.mpf(10) ** -19 * t))
    with pytest.raises(PrecisionError, match="cannot resolve the trace"):
        MD.floquet_verdict(_point_fos(), PARAMS, method="mp")
    assert len(calls) > 2                       # the precision was raised before refusing


def test_two_precisions_that_agree_are_accepted(monkeypatch):
    with mpmath.workdps(40):
        t = mpmath.mpf("1.5")
        _fake_taylor(monkeypatch, (t, t + mpmath.mpf("0.3e-19") * t))
    v = MD.floquet_verdict(_point_fos(), PARAMS, method="mp")
    assert v.stable and not v.on_boundary and abs(v.trace - mpmath.mpf("1.5")) < 1e-18


def test_a_trace_closer_to_2_than_its_error_is_not_decided(monkeypatch):
    # |tr| - 2 = -1.5e-20 with the two precisions 1e-20 apart: 2 err > margin, the side of
    # the edge is not decided; the margin is below 1e-16, so the point is on the boundary
    # (verdict unstable), not stable
    with mpmath.workdps(60):
        e, m = mpmath.mpf(10) ** -20, mpmath.mpf("1.5e-20")
        _fake_taylor(monkeypatch, (2 - m + e, 2 - m))
    v = MD.floquet_verdict(_point_fos(), PARAMS, method="mp")
    assert v.on_boundary and not v.stable


def test_a_trace_three_times_its_error_bound_from_2_is_decided(monkeypatch):
    # margin 6e-20 = 3 (2 err): decided, stable (a rule 10x stricter would call it undecided)
    with mpmath.workdps(60):
        e, m = mpmath.mpf(10) ** -20, mpmath.mpf("6e-20")
        _fake_taylor(monkeypatch, (2 - m + e, 2 - m))
    v = MD.floquet_verdict(_point_fos(), PARAMS, method="mp")
    assert v.stable and not v.on_boundary


def test_an_undecided_trace_with_a_margin_is_refused(monkeypatch):
    # |tr| - 2 = -1e-15 but the precisions differ by 6e-16: neither decided nor on the
    # boundary (a margin above 10^-16 is a number that more digits would decide)
    with mpmath.workdps(60):
        m = mpmath.mpf("1e-15")
        _fake_taylor(monkeypatch, (2 - m + mpmath.mpf("6e-16"), 2 - m))
    with pytest.raises(PrecisionError, match="cannot resolve"):
        MD.floquet_verdict(_point_fos(), PARAMS, method="mp")


@pytest.mark.parametrize("side", [+1, -1])
def test_mp_verdict_at_double_precision_keeps_the_decided_side(side):
    # theta0 = a_0(0.4) +- 1e-20 with dps None (16 digits): the side is decided on the trace
    # at the working precision (|tr| - 2 ~ 1e-21, two precisions ~1e-37 apart); rounded to
    # 16 digits the trace is 2, so a verdict read after rounding calls the point inside the
    # band unstable.  The continued fractions at 30 digits are the reference.
    import sympy as sp

    from pendulab.analyses.floquet import mathieu_a

    with mpmath.workdps(60):
        theta0 = mathieu_a(0, "0.4", dps=60) + side * mpmath.mpf(10) ** -20
        sign, man, exp, _ = theta0._mpf_
    exact = (-1) ** sign * sp.Integer(int(man)) * sp.Integer(2) ** int(exp)
    v = MD.floquet_verdict(_point_fos(), {"a_over_l": sp.Rational(1, 5),
                                          "w0_over_w": sp.sqrt(-exact / 4)}, method="mp")
    ref = characteristic_exponent(theta0, "0.4", dps=30, method="cf")
    assert ref.stable is (side > 0)
    assert v.stable is ref.stable and not v.on_boundary


@pytest.mark.parametrize("off,stable", [("3e-8", False), ("3e-9", True)])
def test_mp_stable_needs_det_1(monkeypatch, off, stable):
    # det M = 1 + off with |tr| = 1.5 < 2: stable only when |det - 1| < 10^-(16 // 2);
    # a 10x looser det check would call 1 + 3e-8 stable
    with mpmath.workdps(40):
        t = mpmath.mpf("1.5")
        _fake_taylor(monkeypatch, (t, t), det=1 + mpmath.mpf(off))
    assert MD.floquet_verdict(_point_fos(), PARAMS, method="mp").stable is stable


# ---------------------------------------------------------------------------
# floquet_verdict, method "dop853": the margin against the error estimate, det M
# ---------------------------------------------------------------------------

def _fake_dop853(monkeypatch, tr, det, error):
    h = tr / 2
    M = ((h, 1.0), (h * h - det, h))
    monkeypatch.setattr(MD, "_dop853_monodromy", lambda fos, values, T: (M, det, error))


def test_dop853_trace_within_its_error_of_2_is_flagged(monkeypatch):
    # |tr| - 2 = -5 error, within 10 error: AccuracyWarning and on_boundary
    _fake_dop853(monkeypatch, 2.0 - 5e-12, 1.0, 1e-12)
    with pytest.warns(AccuracyWarning, match="not reliable"):
        v = MD.floquet_verdict(_point_fos(), PARAMS)
    assert v.on_boundary


def test_dop853_trace_beyond_its_error_bound_is_not_flagged(monkeypatch):
    # |tr| - 2 = -30 error: decided without a warning (a bound 10x looser would flag it)
    _fake_dop853(monkeypatch, 2.0 - 3e-11, 1.0, 1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        v = MD.floquet_verdict(_point_fos(), PARAMS)
    assert v.stable and not v.on_boundary


@pytest.mark.parametrize("off,stable", [(3e-6, False), (3e-7, True)])
def test_dop853_stable_needs_det_1(monkeypatch, off, stable):
    _fake_dop853(monkeypatch, 1.5, 1.0 + off, 1e-12)
    assert MD.floquet_verdict(_point_fos(), PARAMS).stable is stable


# ---------------------------------------------------------------------------
# Hill's determinant for several harmonics (analyses.hill_general.hill_trace)
# ---------------------------------------------------------------------------

def _trace_by_ivp(fourier, period):
    """tr M of theta'' + P theta = 0 by solve_ivp (DOP853, rtol 1e-12) over one period."""
    from scipy.integrate import solve_ivp

    def P(t):
        return sum(A * math.cos(k * t) + B * math.sin(k * t) for k, (A, B) in fourier.items())

    def rhs(t, z):
        y1, v1, y2, v2 = z
        p = P(t)
        return [v1, -p * y1, v2, -p * y2]
    sol = solve_ivp(rhs, (0.0, period), [1.0, 0.0, 0.0, 1.0], method="DOP853",
                    rtol=1e-12, atol=1e-14)
    y1, v1, y2, v2 = sol.y[:, -1]
    return y1 + v2


def _with_second_extrapolation_moved(monkeypatch, shift_of):
    """hill_trace with the second extrapolation D2 moved by shift_of(D1, D2)."""
    real = HG._extrapolate
    calls = []

    def moved(values):
        out = real(values)
        calls.append(out)
        return out + shift_of(calls) if len(calls) == 2 else out
    monkeypatch.setattr(HG, "_extrapolate", moved)


FOURIER = {0: (-0.01, 0.0), 2: (0.4, 0.0)}       # theta0 = -0.01, theta1 = 0.2
# Hill's relation with s = 1 (chosen here: s = 0 leaves c_0 - 0^2 = -0.01 next to zero):
# y = -1 + D (cosh(pi sqrt(0.01)) + 1), the trace 2 y
_CS = math.cosh(math.pi * 0.1) + 1.0


@pytest.mark.parametrize("factor,refused", [(3.0, True), (0.3, False)])
def test_hill_trace_refuses_extrapolations_that_disagree(monkeypatch, factor, refused):
    # The two extrapolations made to differ so that the error 2 |y2 - y1| is 3 (refused)
    # or 0.3 (accepted) times the tolerance 1e-6 max(1, |y2|); a 10x looser tolerance
    # would accept the first.
    # (|y2| = 0.95 < 1 here, so the tolerance is 1e-6)
    assert HG.hill_trace(FOURIER, math.pi).shift == 1.0
    _with_second_extrapolation_moved(monkeypatch, lambda c: factor * 1e-6 / 2 / _CS)
    if refused:
        with pytest.raises(ConvergenceError, match="did not converge"):
            HG.hill_trace(FOURIER, math.pi)
    else:
        r = HG.hill_trace(FOURIER, math.pi)
        assert abs(r.error - factor * 1e-6) < 1e-9 and abs(r.trace / 2) < 1


def test_hill_trace_refuses_an_overflowed_determinant(monkeypatch):
    monkeypatch.setattr(HG, "_det", lambda c, d, s, N: float("inf"))
    with pytest.raises(ConvergenceError, match="overflowed"):
        HG.hill_trace(FOURIER, math.pi)


@pytest.mark.parametrize("fourier,period,shift", [
    ({0: (4.0, 0.0), 2: (0.2, 0.0)}, math.pi, 1.0),          # theta0 = (d n)^2, d = 2, n = 1
    ({0: (16.0, 0.0), 2: (0.6, 0.0)}, math.pi, 1.0),         # d = 2, n = 2
    ({0: (1.0, 0.0), 1: (0.3, 0.1)}, 2 * math.pi, 0.5),      # d = 1, n = 1 (2 pi periodic)
    ({0: (2.25, 0.0), 1: (0.3, 0.0)}, 2 * math.pi, 0.0),     # (n + 1/2)^2: s = 0 is safe
])
def test_hill_trace_shifts_away_from_a_zero_diagonal(fourier, period, shift):
    # At c_0 = (d n)^2 the row n of the s = 0 matrix divides by zero; the shift s = d/2
    # keeps every c_0 - (s + d n)^2 away from zero and the trace agrees with solve_ivp
    r = HG.hill_trace(fourier, period)
    assert r.shift == shift
    ref = _trace_by_ivp(fourier, period)
    assert abs(r.trace - ref) < 1e-8 * max(1.0, abs(ref)), (r.trace, ref)


# ---------------------------------------------------------------------------
# Hill's determinant of the Mathieu routes (floquet._hill, _vectorised.trace_monodromy)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("theta0,theta1", [("4", "0.1"), ("16", "-0.3"), ("1", "0.2"),
                                           ("36", "0.05"), ("-0.5", "0.4")])
def test_mathieu_hill_trace_at_squares_against_the_continued_fractions(theta0, theta1):
    # theta0 = 4, 16, 36 (even squares: s = 0 would divide by zero at n = 1, 2, 3) and 1
    # (odd: s = 1 would divide by zero at n = 0): the shift keeps clear of both
    ref = characteristic_exponent(theta0, theta1, dps=30, method="cf")
    with mpmath.workdps(30):
        y_ref = mpmath.re(ref.multipliers[0] + ref.multipliers[1]) / 2
    y, _ = H._hill_y(Fraction(theta0), Fraction(theta1), 25)
    with mpmath.workdps(30):
        assert abs(y - y_ref) < mpmath.mpf(10) ** -23
    tr = float(V.trace_monodromy(np.array([float(theta0)]), np.array([float(theta1)]))[0])
    assert abs(tr - 2 * float(y_ref)) < 1e-10 * max(1.0, abs(tr))


# ---------------------------------------------------------------------------
# The sweep on rectangular grids (numerics.sweep)
# ---------------------------------------------------------------------------

POINT = S.SystemSpec("point")
# 7 values of a/l, 4 of omega0/omega (not square), not in increasing order
AL = (0.02, 0.3, 0.11, 0.5, 0.7, 0.05, 0.23)
W0 = (0.05, 0.21, 0.0, 0.12)


def _reference_stable(al, w):
    """The Floquet verdict of the point mass by the continued fractions (000 eqs. 5-6)."""
    t0 = -4 * Fraction(w) ** 2
    t1 = 2 * Fraction(al)
    return bool(characteristic_exponent(t0, t1, dps=20, method="cf").stable)


@lru_cache(maxsize=None)
def _reference_map():
    return np.array([[_reference_stable(a, w) for a in AL] for w in W0])


def test_floquet_sweep_on_a_rectangular_grid_against_pointwise_verdicts():
    spec = S.make_spec(POINT, a_over_l=AL, w0_over_w=W0, criterion="floquet",
                       initial=[(0.06, 0.01), (0.1, 0.0)])
    res = S.sweep(spec, quiet=True)
    assert res.stable.shape == (2, len(W0), len(AL))
    ref = _reference_map()
    assert ref.any() and not ref.all()
    assert np.array_equal(res.stable[0], ref) and np.array_equal(res.stable[1], ref)
    # one cell by its index k = c n_w n_a + i n_a + j
    k = np.arange(spec.cells)
    got = S.floquet_verdict(spec, k)
    c, rest = np.divmod(k, len(W0) * len(AL))
    i, j = np.divmod(rest, len(AL))
    assert np.array_equal(got, ref[i, j])


def _chebyshev_near(F, margin):
    """Cells within ``margin`` grid steps (Chebyshev) of a cell with the other verdict."""
    n_w, n_a = F.shape
    near = np.zeros_like(F)
    for i in range(n_w):
        for j in range(n_a):
            for di in range(-margin, margin + 1):
                for dj in range(-margin, margin + 1):
                    ii, jj = i + di, j + dj
                    if 0 <= ii < n_w and 0 <= jj < n_a and F[ii, jj] != F[i, j]:
                        near[i, j] = True
    return near


@pytest.mark.parametrize("margin", [1, 2])
def test_prune_plan_integrates_every_cell_near_the_boundary(margin):
    # A small amplitude (0.001, 0): no cell is integrated for its amplitude; the plan must
    # integrate every cell within margin steps of the reference boundary, on the
    # rectangular grid in its own order (rows omega0/omega, columns a/l)
    al = tuple(round(0.1 * k, 2) for k in range(12))
    w0 = (0.0, 0.04, 0.08, 0.12, 0.16, 0.2, 0.25)
    spec = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="bounded",
                       theta_init=0.001, omega_init=0.0, periods=5)
    predicted, simulate = S.prune_plan(spec, margin)
    F = np.array([[_reference_stable(a, w) for a in al] for w in w0])
    assert np.array_equal(predicted[0], F)
    near = _chebyshev_near(F, margin)
    assert near.any() and not near.all()
    assert np.all(simulate[0][near])
    # a stable cell far from the boundary with a small amplitude is not integrated (the
    # stable band of this grid is 4 to 5 cells wide: such a cell exists for margin 1)
    if margin == 1:
        assert np.any(F & ~near & ~simulate[0])


def test_prune_plan_integrates_stable_cells_of_large_amplitude():
    # theta(0) = 0.2, theta'(0) = 0: A = (1 + theta1) 0.2 >= 0.15 at every cell, so every
    # Floquet-stable cell is integrated; at theta(0) = 0.1 / (1 + max theta1) < 0.15 / (...)
    # those away from the boundary are not
    al, w0 = tuple(sorted(AL)), tuple(sorted(W0))
    big = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="bounded",
                      theta_init=0.2, omega_init=0.0, periods=5)
    F = np.array([[_reference_stable(a, w) for a in al] for w in w0])
    _, sim = S.prune_plan(big, 0)
    assert np.all(sim[0][F])
    t1max = 2 * max(al)
    small = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="bounded",
                        theta_init=0.14 / (1 + t1max), omega_init=0.0, periods=5)
    _, sim = S.prune_plan(small, 0)
    assert not np.any(sim[0][F])


def test_pruned_sweep_on_a_rectangular_grid_against_single_trajectories():
    # every cell of the pruned sweep: the Floquet verdict where not integrated, else the
    # verdict of its own RK4 trajectory (rk4_trajectory of that cell, not the ensemble)
    from pendulab.numerics.integrate import rk4_trajectory

    al, w0 = (0.02, 0.3, 0.5, 0.7, 0.23), (0.05, 0.21, 0.12)
    spec = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="bounded",
                       theta_init=0.3, omega_init=0.0, periods=10, steps_per_period=60)
    res = S.pruned_sweep(spec, 1, quiet=True, executor="serial")
    predicted, simulate = S.prune_plan(spec, 1)
    fos = S.first_order_system(POINT)
    names = [s.name for s in fos.params]
    dt = float(fos.period) / 60
    checked = 0
    for i, w in enumerate(w0):
        for j, a in enumerate(al):
            if not simulate[0, i, j]:
                assert res.stable[0, i, j] == _reference_stable(a, w)
                continue
            p = [{"a_over_l": a, "w0_over_w": w}[n] for n in names]
            _, states = rk4_trajectory(fos, (0.3, 0.0), p, 0.0, dt, 600)
            theta = np.asarray(states, float)[:, 0]
            assert res.stable[0, i, j] == bool(np.max(np.abs(theta)) < math.pi / 2), (i, j)
            checked += 1
    assert checked >= 3 and res.simulated == int(simulate.sum())


def test_hill_trace_refuses_a_period_its_harmonics_do_not_have():
    from pendulab.errors import InputError

    with pytest.raises(InputError, match="harmonic 1 is not periodic"):
        HG.hill_trace({0: (1.0, 0.0), 1: (0.3, 0.0)}, math.pi)
    with pytest.raises(InputError, match="2 pi/d"):
        HG.hill_trace({0: (1.0, 0.0), 2: (0.3, 0.0)}, 3.0)
    with pytest.raises(InputError, match="too large"):
        HG.hill_trace({0: (1.0, 0.0), 2: (6e4, 0.0)}, math.pi)


def test_a_sweep_refuses_cells_outside_its_rectangular_grid():
    # 3 x 5 cells (one initial condition): index 15 is the first outside
    from pendulab.errors import InputError

    spec = S.make_spec(POINT, a_over_l=(0.0, 0.1, 0.2, 0.3, 0.4), w0_over_w=(0.0, 0.1, 0.2),
                       criterion="bounded", periods=1, steps_per_period=10)
    with pytest.raises(InputError, match=r"0\.\.14"):
        S.sweep(spec, index=[3, 15], quiet=True)
    with pytest.raises(InputError, match=r"0\.\.14"):
        S.sweep(spec, index=[-1, 2], quiet=True)
    res = S.sweep(spec, index=[14], quiet=True, executor="serial")
    assert res.simulated == 1 and np.isfinite(res.stats["max_abs_theta"][0, 2, 4])
    assert np.isnan(res.stats["max_abs_theta"][0, 0, 0])


# ---------------------------------------------------------------------------
# The Taylor series' a posteriori truncation (two working precisions cannot see it: a
# series cut too early is cut the same way at both)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("theta0,theta1", [("-0.04", "0.3"), ("2.5", "-1.7")])
def test_mathieu_monodromy_taylor_series_is_not_cut_early(theta0, theta1):
    from pendulab.analyses.floquet._monodromy import _monodromy_y

    ref = characteristic_exponent(theta0, theta1, dps=35, method="cf")
    with mpmath.workdps(35):
        y_ref = mpmath.re(ref.multipliers[0] + ref.multipliers[1]) / 2
    y, _ = _monodromy_y(Fraction(theta0), Fraction(theta1), 30)
    with mpmath.workdps(35):
        assert abs(y - y_ref) < mpmath.mpf(10) ** -27, (y, y_ref)


def test_mp_monodromy_taylor_series_is_not_cut_early():
    # the point mass at theta0 = -0.04, theta1 = 0.3 (a/l = 3/20, omega0/omega = 1/10),
    # dps 25, against the continued fractions at 35 digits
    ref = characteristic_exponent("-0.04", "0.3", dps=35, method="cf")
    v = MD.floquet_verdict(_point_fos(), {"a_over_l": "3/20", "w0_over_w": "1/10"},
                           dps=25, method="mp")
    with mpmath.workdps(35):
        tr = mpmath.re(ref.multipliers[0] + ref.multipliers[1])
        assert abs(v.trace - tr) < mpmath.mpf(10) ** -23, (v.trace, tr)


def test_prune_plan_integrates_slowly_growing_cells_of_a_resonance_gap():
    # Every cell of this 2 x 5 grid lies in the first resonance gap (lam = 1 + i mu, the
    # continued fractions at 20 digits); with margin 0 and a small amplitude only the cells
    # with mu < FLUTTER_MU = 0.5 are integrated (mu = 0.23 .. 0.49 at a/l 0.5, 0.6; 0.62 ..
    # 1.0 beyond, which a 10x larger threshold would integrate too)
    al, w0 = (0.5, 0.6, 0.7, 0.9, 1.2), (0.0, 0.1)
    spec = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="bounded",
                       theta_init=0.001, omega_init=0.0, periods=5)
    predicted, simulate = S.prune_plan(spec, 0)
    for i, w in enumerate(w0):
        for j, a in enumerate(al):
            lam = complex(characteristic_exponent(-4 * Fraction(w) ** 2, 2 * Fraction(a),
                                                  dps=20, method="cf").lam)
            assert lam.real == 1.0 and not predicted[0, i, j]
            assert simulate[0, i, j] == (lam.imag < 0.5), (a, w, lam)   # prune_plan's rule
    assert simulate.any() and not simulate.all()


def test_prune_plan_rules_of_the_mean_criteria():
    # "mean": every Floquet-unstable cell is integrated (a falling pendulum can have a small
    # signed mean); "mean-abs": a stable cell is integrated when (2/pi) A >= 0.05, i.e.
    # theta(0) (1 + theta1) >= 0.0785 with theta'(0) = 0 (A of prune_plan's docstring)
    al = (0.02, 0.1, 0.2, 0.3, 0.6, 0.9)
    w0 = (0.0, 0.05, 0.15)
    F = np.array([[_reference_stable(a, w) for a in al] for w in w0])
    assert F.any() and not F.all()
    mean = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="mean",
                       theta_init=0.001, omega_init=0.0, periods=5)
    _, sim = S.prune_plan(mean, 0)
    assert np.all(sim[0][~F]) and not np.any(sim[0][F])
    t1 = 2 * np.array(al)[None, :] * np.ones((len(w0), 1))
    for th in (0.02, 0.05):
        spec = S.make_spec(POINT, a_over_l=al, w0_over_w=w0, criterion="mean-abs",
                           theta_init=th, omega_init=0.0, periods=5)
        _, sim = S.prune_plan(spec, 0)
        big = 2 / math.pi * (1 + t1) * th >= 0.05
        assert np.array_equal(sim[0][F], big[F]), th
        # th = 0.05: the stable cells with theta1 >= pi/2 - 1 are integrated, the others not
        assert (big[F].any() and not big[F].all()) if th == 0.05 else not big[F].any()


def test_hill_trace_shifts_away_from_a_zero_diagonal_beyond_n_200():
    # c_0 = 201^2 with period 2 pi (d = 1): the zero of c_0 - (s + n)^2 at s = 0 lies at
    # n = 201, beyond a search of n up to 200; s = 1/2 must be chosen all the same, and the
    # trace agree with solve_ivp (its own accuracy ~1e-10 here, 201 oscillations)
    fourier = {0: (201.0 ** 2, 0.0), 1: (0.3, 0.0)}
    r = HG.hill_trace(fourier, 2 * math.pi)
    assert r.shift == 0.5
    ref = _trace_by_ivp(fourier, 2 * math.pi)
    assert abs(r.trace - ref) < 1e-8, (r.trace, ref)


def test_sweep_criteria_refuse_just_beyond_their_thresholds():
    # mean |.| < 0.1 and mean of |theta| < 0.1 (000 sec. 4), |theta| < pi/2 throughout:
    # 3% inside is stable, 3% outside and an overflowed (NaN) trajectory are not
    nan = float("nan")
    stats = {"mean_theta": [0.097, -0.097, 0.103, -0.103, nan],
             "mean_abs_theta": [0.097, 0.103, nan, 0.0, 0.05],
             "max_abs_theta": [0.97 * math.pi / 2, 1.03 * math.pi / 2, nan, 0.0, 1.0]}
    with np.errstate(invalid="ignore"):
        assert list(S.verdict("mean", stats)) == [True, True, False, False, False]
        assert list(S.verdict("mean-abs", stats)) == [True, False, False, True, True]
        assert list(S.verdict("bounded", stats)) == [True, False, False, True, True]
