"""The sorted, grouped evaluation of the vectorised exponent and inverse
(one sort by (band, octave of |q|), contiguous groups, the guesses
for all points at once, the band count one column of edges at a time) gives
the same bits as the code it replaced.

The replaced code is kept below, in this test file only, as the reference
(``_old_*``: the loops over the index arrays of each group, and the band count
from the gathered edge matrix); both paths (C kernel and NumPy fallback) are
compared on a few thousand random points, in the bands, in the gaps, below
a_0, at theta1 = 0 and at integer nu, and on the rows of MathieuFunctions.jl's
lambda grid (tests/data/mathieu_lambda_grid.csv).
"""

import os

import numpy as np
import pytest

from pendulab.analyses.floquet import _vectorised as V
from pendulab.errors import PrecisionError

DATA = os.path.join(os.path.dirname(__file__), "data", "mathieu_lambda_grid.csv")


pytestmark = pytest.mark.usefixtures("band_kernel_cache")


# ----------------------------------------------------------------- reference
def _old_groups(key):
    order = np.argsort(key, kind="stable")
    ks = key[order]
    cuts = np.nonzero(np.diff(ks))[0] + 1
    return np.split(order, cuts)


def _old_bands_fast(f0, f1):
    import math

    qs, inv = np.unique(np.abs(f1), return_inverse=True)
    if qs.size <= 16:
        return V._bands_double(f0, f1)
    t = max(float(f0.max()), 0.0)
    reach = float(f0.max()) + 2.0 * math.sqrt(t + 2.0 * float(qs.max())) + 4.0
    try:
        E, _ = V._certify_edges(qs, reach)
    except PrecisionError:
        return V._bands_double(f0, f1)
    Ei = E[inv]
    cnt = np.sum(Ei < f0[:, None], axis=1)
    ne = E.shape[1]
    rows = np.arange(f0.size)
    below = np.where(cnt > 0, Ei[rows, np.clip(cnt - 1, 0, max(ne - 1, 0))], -np.inf) if ne else \
        np.full(f0.shape, -np.inf)
    above = np.where(cnt < ne, Ei[rows, np.clip(cnt, 0, max(ne - 1, 0))], np.inf) if ne else \
        np.full(f0.shape, np.inf)
    return cnt, below, above


def _old_exponent(theta0, theta1):
    x0, x1 = V._check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    out = np.zeros(f0.shape, dtype=complex)
    if f0.size == 0:
        return out.reshape(shape)
    cnt, below, above = _old_bands_fast(f0, f1)
    band = cnt % 2 == 1
    zero = f1 == 0
    out[zero] = np.sqrt(f0[zero] + 0j)
    inb = np.nonzero(band & ~zero & np.isfinite(below) & np.isfinite(above))[0]
    if inb.size:
        k = (cnt[inb] - 1) // 2
        absq = np.abs(f1[inb])
        t0, lo, hi = f0[inb], below[inb], above[inb]
        lam = np.empty(inb.size)
        octave = np.floor(np.log2(absq)).clip(-4, None).astype(np.int64)
        for sel in _old_groups(k * 4096 + octave):
            R = V._shifted_rows(float(hi[sel].max()), float(absq[sel].max()))
            lam[sel] = V._band_nu(t0[sel], absq[sel] ** 2, k[sel], lo[sel], hi[sel], R)
        out[inb] = lam
    rest = np.ones(f0.shape, dtype=bool)
    rest[inb] = False
    rest &= ~zero
    ri = np.nonzero(rest)[0]
    if ri.size:
        out[ri] = V._exponent_by_trace(f0[ri], f1[ri], cnt[ri], below[ri], above[ri])
    return out.reshape(shape)


def _old_theta0_of_exponent_array(nu, theta1):
    n_arr, t_arr = V._real_arrays(nu, theta1, ("nu", "theta1"))
    n_arr = np.abs(n_arr)
    shape = n_arr.shape
    fn, f1 = n_arr.ravel().copy(), t_arr.ravel().copy()
    out = np.empty(fn.shape)
    if fn.size == 0:
        return out.reshape(shape)
    zero_q = f1 == 0
    is_int = (fn == np.floor(fn)) & ~zero_q
    out[zero_q] = fn[zero_q] ** 2
    if np.any(is_int):
        ii = np.nonzero(is_int)[0]
        n_i = fn[ii].astype(np.int64)
        q_i = -f1[ii]
        idx = np.where(n_i == 0, 0, np.where(q_i > 0, 2 * n_i,
                                             np.where(n_i % 2 == 0, 2 * n_i, 2 * n_i - 1)))
        out[ii] = V._sorted_edges_at(np.abs(q_i), idx)
    todo = np.nonzero(~zero_q & ~is_int)[0]
    if todo.size:
        nu_t, absq = fn[todo], np.abs(f1[todo])
        k = np.floor(nu_t).astype(np.int64)
        lo, hi = V._band_edges(absq, k)
        res = np.empty(todo.size)
        octave = np.floor(np.log2(np.maximum(absq, 1e-300))).clip(-4, None).astype(np.int64)
        for sel in _old_groups(k * 4096 + octave):
            R = V._shifted_rows(float(hi[sel].max()), float(absq[sel].max()))
            res[sel] = V._band_eigen(nu_t[sel], absq[sel] ** 2, k[sel], lo[sel], hi[sel], R)
        out[todo] = res
    return out.reshape(shape)


# --------------------------------------------------------------------- tests
def _points(rng, n):
    """nu in [0, 4.5) (some integers, some theta1 = 0) and theta1 in [-12, 12]
    with a few repeated |theta1| (as on a grid)."""
    nu = rng.uniform(0.0, 4.5, n)
    nu[: n // 20] = rng.integers(0, 5, n // 20)
    th1 = rng.uniform(-12.0, 12.0, n)
    th1[n // 20: n // 10] = 0.0
    th1[-n // 4:] = rng.choice(np.round(np.linspace(-6, 6, 41), 2), n // 4)
    return nu, th1


def _theta0_points(rng, n):
    """theta0 across bands and gaps and below a_0: uniform in [-30, 30], and the
    band edges themselves moved by a few ulps (points just inside gaps)."""
    th1 = rng.uniform(-10.0, 10.0, n)
    th0 = rng.uniform(-30.0, 30.0, n)
    m = n // 5
    edges = V._theta0_of_exponent_array(rng.integers(0, 4, m).astype(float), th1[:m])
    th0[:m] = edges + rng.integers(-4, 5, m) * np.spacing(np.abs(edges))
    th1[m: m + n // 20] = 0.0
    return th0, th1


@pytest.mark.parametrize("numpy_path", [False, True])
def test_random_points_give_the_previous_bits(numpy_path, monkeypatch):
    if numpy_path:
        monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    rng = np.random.default_rng(2026)
    nu, th1 = _points(rng, 3000 if not numpy_path else 1500)
    new = V._theta0_of_exponent_array(nu, th1)
    assert np.array_equal(new, _old_theta0_of_exponent_array(nu, th1))
    # in the bands (the inverse's values) ...
    assert np.array_equal(V.exponent(new, th1), _old_exponent(new, th1))
    # ... and across the gaps and below a_0
    th0, t1 = _theta0_points(rng, 3000 if not numpy_path else 1500)
    new_lam = V.exponent(th0, t1)
    assert np.array_equal(new_lam, _old_exponent(th0, t1), equal_nan=True)
    # the sample does reach the gaps and below a_0
    gap = np.abs(new_lam.imag) > 0
    assert np.count_nonzero(gap & (new_lam.real == 0)) > 50
    assert np.count_nonzero(gap & (new_lam.real > 0)) > 50


def test_lambda_grid_rows_give_the_previous_bits():
    nu, q, _ = np.loadtxt(DATA, delimiter=",", comments="#", unpack=True)
    new = V._theta0_of_exponent_array(nu, -q)
    assert np.array_equal(new, _old_theta0_of_exponent_array(nu, -q))
    assert np.array_equal(V.exponent(new, -q), _old_exponent(new, -q))


def test_group_order_is_the_stable_sort():
    rng = np.random.default_rng(7)
    grouped = rng.integers(0, 9, 2000) * 4096 + rng.integers(-4, 6, 2000)
    for key in (rng.integers(-3, 40000, 500), grouped):
        order, cuts = V._group_order(key)
        assert np.array_equal(order, np.argsort(key, kind="stable"))
        groups = [order[a:b].tolist() for a, b in zip(cuts[:-1], cuts[1:])]
        assert groups == [g.tolist() for g in _old_groups(key)]


@pytest.mark.needs_cc
def test_newton_eigen_kernel_gives_the_numpy_bits(monkeypatch):
    """The C loop of _newton_eigen (the certified edges' corrector) against its
    NumPy loop on the DLMF 28.4 matrices at random q, from rough guesses, from
    guesses that are already the eigenvalues (steps at rounding level), and
    from a diagonal entry of a 1x1 and a zero-coupling matrix (zero pivots)."""
    rng = np.random.default_rng(11)
    M, n = 600, 14
    fams = rng.integers(0, 4, M)
    q = rng.uniform(0.0, 30.0, M)
    q[:20] = 0.0
    d, e2 = V._family_rows(fams, q, n)
    x0 = d[rng.integers(0, 4, M), np.arange(M)] + rng.normal(0.0, 2.0, M)
    x0[20:40] = d[0, 20:40]                      # q = 0 columns start on a pivot zero
    assert V._c_band() is not None
    got_c = V._newton_eigen(d, e2, x0)
    again = V._newton_eigen(d, e2, got_c)        # from the roots themselves
    monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
    assert V._c_band() is None
    assert np.array_equal(got_c, V._newton_eigen(d, e2, x0))
    assert np.array_equal(again, V._newton_eigen(d, e2, got_c))
    for nn in (1, 2):
        d1, e21 = V._family_rows(fams[:50], q[:50], nn)
        monkeypatch.delenv("PENDULAB_BAND_NUMPY")
        c1 = V._newton_eigen(d1, e21, x0[:50], iters=3)
        monkeypatch.setenv("PENDULAB_BAND_NUMPY", "1")
        assert np.array_equal(c1, V._newton_eigen(d1, e21, x0[:50], iters=3), equal_nan=True)
    # the corrector converges: most columns end on an eigenvalue of their
    # float matrix (LAPACK's values as the independent reference)
    from scipy.linalg import eigvalsh_tridiagonal

    near = [np.min(np.abs(eigvalsh_tridiagonal(d[:, c], np.sqrt(e2[:, c])) - got_c[c]))
            <= 1e-9 * max(1.0, abs(got_c[c])) for c in range(M)]
    assert np.mean(near) > 0.9
