"""The C kernel of the vectorised band Newton iterations.

pendulab.analyses.floquet._vectorised runs the Newton loops of
``_band_eigen_chunk`` (theta0_of_exponent on arrays) and ``_band_nu_chunk``
(exponent on arrays) in C99 (``_BAND_C``, built by
pendulab.numerics.ckernel.load_source with -ffp-contract=off), with the NumPy
loops as the fallback.  Checked here:

* the two paths give the same bits (random points, and the rows of
  MathieuFunctions.jl's lambda grid in tests/data/mathieu_lambda_grid.csv);
* with no compiler the NumPy path answers, after one notice;
* the kernel's rows are the derived recurrence: its pivots, their signs and
  its log-derivative against the determinant of the rows of 000 eq. 10 as
  derived by pendulab.analyses.phelps_hunter (lambdified, 40-digit mpmath),
  at a few points away from the eigenvalues.
"""

import ctypes
import math
import os

import mpmath
import numpy as np
import pytest
import sympy as sp

from pendulab.analyses.floquet import exponent, theta0_of_exponent, trace_monodromy
from pendulab.analyses.floquet import _vectorised as V
from pendulab.numerics import ckernel

DATA = os.path.join(os.path.dirname(__file__), "data", "mathieu_lambda_grid.csv")


pytestmark = pytest.mark.usefixtures("band_kernel_cache")


def _both(fn, monkeypatch, *args):
    """fn(*args) with the C kernel (required to load) and with the NumPy path."""
    assert V._c_band() is not None, "the C kernel did not build"
    c = fn(*args)
    monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    assert V._c_band() is None
    n = fn(*args)
    monkeypatch.delenv("PENDULAB_BAND_NUMPY")
    return c, n


def _same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert a.dtype == b.dtype and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.mark.needs_cc
def test_random_points_give_the_same_bits(rng, monkeypatch):
    nu = rng.uniform(0.0, 6.0, 4000)
    th1 = rng.uniform(-30.0, 30.0, 4000) * rng.choice([1e-3, 1.0], 4000)
    c, n = _both(theta0_of_exponent, monkeypatch, nu, th1)
    assert np.all(np.isfinite(c))
    _same_bits(c, n)
    # exponent at random theta0 (bands, gaps, below a_0) and at the inverse's values
    th0 = rng.uniform(-20.0, 40.0, 4000)
    c, n = _both(exponent, monkeypatch, th0, th1)
    _same_bits(c, n)
    band = np.abs(c.imag) == 0
    assert 0.2 < band.mean() < 0.9       # both routes are exercised
    c, n = _both(exponent, monkeypatch, theta0_of_exponent(nu, th1), th1)
    _same_bits(c, n)


@pytest.mark.needs_cc
def test_lambda_grid_rows_give_the_same_bits(monkeypatch):
    nu, q, lam = np.loadtxt(DATA, delimiter=",", comments="#", unpack=True)
    c, n = _both(theta0_of_exponent, monkeypatch, nu, -q)
    _same_bits(c, n)
    c, n = _both(exponent, monkeypatch, lam, -q)
    _same_bits(c, n)


@pytest.mark.needs_cc
def test_trace_continuants_give_the_same_bits(rng, monkeypatch):
    # the gap route's Hill determinant (pendulab_trace_continuants) against the
    # NumPy continuants, also where the trace is huge (large |theta1|)
    th0 = rng.uniform(-20.0, 40.0, 3000)
    th1 = rng.uniform(-30.0, 30.0, 3000) * rng.choice([1e-3, 1.0, 30.0], 3000)
    c, n = _both(trace_monodromy, monkeypatch, th0, th1)
    _same_bits(c, n)
    assert np.isfinite(c).all() and np.abs(c).max() > 1e10


@pytest.mark.needs_cc
def test_trace_continuants_against_mpmath():
    # the four depths kept by the C recurrence against the same continuants of
    # Hill's rows in 40-digit mpmath (pendulab.analyses.floquet._hill.continuants)
    from pendulab.analyses.floquet._hill import continuants

    lib = V._c_band()
    assert lib is not None
    f0 = np.array([0.3, 2.7, -1.5, 9.2, 30.0])
    f1 = np.array([0.8, -2.0, 1.25, 4.0, -7.5])
    s = np.array([1, 0, 0, 0, 1])
    N0 = 30
    D = V._c_continuants(lib, f0, f1, s, N0)
    with mpmath.workdps(40):
        for p in range(f0.size):
            x0, x1, sp_ = mpmath.mpf(f0[p]), mpmath.mpf(f1[p]), int(s[p])
            seq = list(continuants(lambda n: x1 / ((2 * n + sp_) ** 2 - x0), 8 * N0,
                                   mpmath.mpf(1), mpmath.mpf(0)))
            for j in range(4):
                ref = seq[N0 * 2 ** j - 1]
                assert abs(D[j][p] - ref) <= 1e-13 * max(1, abs(ref)), (p, j, D[j][p], ref)


def test_guess_polynomials_are_accurate():
    # the guesses' arccos (Abramowitz & Stegun 4.4.46, |error| <= 2e-8 before
    # dividing by pi) and cos(pi x) (Taylor series to z^15) against the C library
    x = np.linspace(0.0, 1.0, 100001)
    ref = np.array([math.acos(t) / math.pi for t in (2 * x - 1)])
    assert np.abs(V._acos_over_pi(2 * x - 1) - ref).max() <= 2.5e-8 / math.pi
    ref = np.array([math.cos(math.pi * t) for t in x])
    assert np.abs(V._cospi01(x) - ref).max() <= 1e-11


@pytest.mark.needs_cc
def test_portable_build_gives_the_same_bits(rng, tmp_path, monkeypatch):
    # the last flag set (no -march=native: SSE2 on x86-64) against the first
    # that built (AVX-512 or AVX2 vectors where the CPU has them)
    nu = rng.uniform(0.0, 4.0, 2000)
    th1 = rng.uniform(-12.0, 12.0, 2000)
    assert V._c_band() is not None
    ref_inv, ref_exp = theta0_of_exponent(nu, th1), exponent(nu * nu + 0.3, th1)
    cmd = ckernel.compiler_command()
    target = tmp_path / "band-portable.so"
    assert ckernel._compile(V._BAND_C, cmd, ckernel.FLAG_SETS[-1], target) is None
    lib = V._bind(ctypes.CDLL(str(target)))
    monkeypatch.setitem(V._C_STATE, "lib", lib)
    assert V._c_band() is lib
    _same_bits(theta0_of_exponent(nu, th1), ref_inv)
    _same_bits(exponent(nu * nu + 0.3, th1), ref_exp)


@pytest.mark.needs_cc
def test_missing_compiler_takes_the_numpy_path_with_one_notice(rng, tmp_path, monkeypatch,
                                                                capsys):
    nu = rng.uniform(0.0, 3.0, 300)
    th1 = rng.uniform(-5.0, 5.0, 300)
    assert V._c_band() is not None
    ref_inv, ref_exp = theta0_of_exponent(nu, th1), exponent(nu * nu, th1)
    capsys.readouterr()
    ckernel.clear_loaded()
    monkeypatch.setenv("PENDULAB_CC", str(tmp_path / "no-such-cc"))
    assert V._c_band() is None
    got_inv = theta0_of_exponent(nu, th1)
    got_exp = exponent(nu * nu, th1)
    theta0_of_exponent(nu, th1)
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("pendulab: notice: C kernel 'floquet band Newton' unavailable")
    assert lines[0].endswith("using the NumPy path")
    _same_bits(got_inv, ref_inv)
    _same_bits(got_exp, ref_exp)
    assert not list(tmp_path.rglob("*.so"))


def test_without_a_compiler_the_numpy_path_answers_after_one_notice(rng, tmp_path,
                                                                     monkeypatch, capsys):
    """Runs on every machine: the compiler forced missing gives the NumPy path's own bits
    (the path PENDULAB_BAND_NUMPY=1 chooses) and one notice, written once per process."""
    nu = rng.uniform(0.0, 3.0, 300)
    th1 = rng.uniform(-5.0, 5.0, 300)
    monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    ref_inv, ref_exp = theta0_of_exponent(nu, th1), exponent(nu * nu, th1)
    monkeypatch.delenv("PENDULAB_BAND_NUMPY")
    capsys.readouterr()
    ckernel.clear_loaded()
    V._C_STATE.clear()
    monkeypatch.setenv("PENDULAB_CC", str(tmp_path / "no-such-cc"))
    got_inv = theta0_of_exponent(nu, th1)
    got_exp = exponent(nu * nu, th1)
    V._C_STATE.clear()  # asked again: the C library is not, and says nothing more
    assert V._c_band() is None
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("pendulab: notice: C kernel 'floquet band Newton' unavailable")
    assert "no-such-cc" in lines[0] and lines[0].endswith("using the NumPy path")
    _same_bits(got_inv, ref_inv)
    _same_bits(got_exp, ref_exp)
    assert not list(tmp_path.rglob("*.so"))


# -- the kernel's rows against the derived recurrence (000 eq. 10) --------------------------

def _derived_rows():
    """The coefficients of b_{n-1}, b_n, b_{n+1} in row n of the recurrence, lambdified."""
    from pendulab import symbols as S
    from pendulab.analyses import phelps_hunter as ph

    rec = ph.recurrence()
    args = (ph.n, ph.lam, S.theta0, S.theta1)
    return [sp.lambdify(args, rec.coefficients[k], "mpmath") for k in (-1, 0, 1)]


def _rows_det(rows, ns, lam, theta0, theta1):
    """det of the recurrence rows n in ns (b outside them set to 0) and its leading minors."""
    lo, mid, up = rows
    size = len(ns)
    M = mpmath.zeros(size, size)
    for i, n in enumerate(ns):
        M[i, i] = mid(n, lam, theta0, theta1)
        if i > 0:
            M[i, i - 1] = lo(n, lam, theta0, theta1)
        if i + 1 < size:
            M[i, i + 1] = up(n, lam, theta0, theta1)
    return [mpmath.det(M[:j, :j]) for j in range(1, size + 1)]


def _kernel_rows(fn, a, e2, c, n0, L):
    u, g = np.empty(L), np.empty(L)
    cnt, sm = ctypes.c_long(), ctypes.c_double()
    PD = ctypes.POINTER(ctypes.c_double)
    fn(a, e2, c, n0, L, u.ctypes.data_as(PD), g.ctypes.data_as(PD), ctypes.byref(cnt),
       ctypes.byref(sm))
    return u, g, cnt.value, sm.value


# (nu or lam, theta1, theta0 or x): theta1 with an exact square, points off the eigenvalues
ROW_POINTS = [(0.37, 0.75, 1.3), (1.6, -2.5, 0.4), (2.25, 3.0, 7.7), (0.9, 0.125, -0.6)]


@pytest.mark.parametrize("a, theta1, x", ROW_POINTS)
@pytest.mark.parametrize("kind", ["eigen", "nu"])
@pytest.mark.needs_cc
def test_kernel_rows_are_the_derived_recurrence(kind, a, theta1, x):
    lib = V._c_band()
    assert lib is not None
    rows = _derived_rows()
    R, L = 9, 11
    n0 = 2.0 * np.floor((-R - a) / 2.0)
    fn = lib.pendulab_eigen_rows if kind == "eigen" else lib.pendulab_nu_rows
    u, g, cnt, sm = _kernel_rows(fn, a, theta1 * theta1, x, n0, L)
    ns = [int(n0) // 2 + i for i in range(L)]
    with mpmath.workdps(40):
        A, T, X = mpmath.mpf(a), mpmath.mpf(theta1), mpmath.mpf(x)
        # J - x is minus the recurrence rows at theta0 = x: its leading minors
        # alternate in sign with theirs, and the pivots are their ratios
        minors = [(-1) ** (j + 1) * m for j, m in enumerate(_rows_det(rows, ns, A, X, T))]
        piv = [minors[0]] + [minors[j] / minors[j - 1] for j in range(1, L)]
        for j in range(L):
            assert abs(u[j] - piv[j]) <= 1e-13 * abs(piv[j]), (j, u[j], piv[j])
        assert cnt == sum(1 for p in piv if p < 0)
        # sm = d/dx log det(J(nu) - x) (eigen) or d/dlam log det(J(lam) - theta0) (nu)
        if kind == "eigen":
            f = lambda t: (-1) ** L * _rows_det(rows, ns, A, t, T)[-1]    # noqa: E731
            ref = mpmath.diff(f, X) / f(X)
        else:
            f = lambda t: (-1) ** L * _rows_det(rows, ns, t, X, T)[-1]    # noqa: E731
            ref = mpmath.diff(f, A) / f(A)
        assert abs(sm - ref) <= 1e-12 * max(1, abs(ref)), (sm, ref)
        # and the eigenvalues below x (nu path: below theta0) are the count
        M = mpmath.zeros(L, L)
        lam = A
        for i, n in enumerate(ns):
            M[i, i] = -rows[1](n, lam, X, T) + X
            if i + 1 < L:
                M[i, i + 1] = M[i + 1, i] = -rows[2](n, lam, X, T)
        ev = mpmath.eigsy(M, eigvals_only=True)
        assert cnt == sum(1 for e in ev if e < X)


def test_load_source_required_raises_one_line(tmp_path, monkeypatch):
    from pendulab.errors import InputError

    monkeypatch.setenv("PENDULAB_CC", str(tmp_path / "no-such-cc"))
    with pytest.raises(InputError, match="C kernel 'probe' unavailable") as info:
        ckernel.load_source("probe", "int pendulab_x(void) { return 2; }\n", required=True)
    assert "\n" not in str(info.value)


@pytest.mark.needs_cc
def test_load_source_builds_and_loads_a_hand_kernel(monkeypatch):
    monkeypatch.delenv("PENDULAB_CC", raising=False)
    ckernel.clear_loaded()
    lib = ckernel.load_source("probe", "int pendulab_x(void) { return 2; }\n", required=True)
    assert lib.pendulab_x() == 2
