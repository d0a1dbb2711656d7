"""Vectorised double precision: exponent, verdict, trace and inverse on arrays."""

from __future__ import annotations

import math
import warnings

from pendulab.errors import AccuracyWarning, InputError
from pendulab.analyses.floquet._bands import FAMILIES, _edge_index, _family_diagonals, _tail_steps
from pendulab.analyses.floquet._charvalues import _family_of
from pendulab.analyses.floquet._exponent import characteristic_exponent
from pendulab.analyses.floquet._inputs import SIZE_LIMIT


def _edges_double(absq, theta0_max):
    """Sorted characteristic values a_n(absq), b_n(absq) up to beyond theta0_max."""
    import numpy as np
    from scipy.linalg import eigvalsh_tridiagonal

    top = max(float(theta0_max), 0.0) + 2.0 * absq
    m0 = _edge_index(top, absq)
    n = m0 // 2 + _tail_steps(top, absq, m0, 18) + 3
    out = []
    for fam in FAMILIES:
        d, e2 = _family_diagonals(fam, absq, n, 1.0)
        vals = eigvalsh_tridiagonal(np.asarray(d, float), np.sqrt(np.asarray(e2, float)))
        out.append(vals[vals <= top + 1.0])
    return np.sort(np.concatenate(out))


def _real_arrays(x, y, names):
    """Two finite float arrays broadcast together; one-line InputError otherwise."""
    import numpy as np

    a, b = names
    try:
        xa = np.asarray(x, dtype=float)
        ya = np.asarray(y, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{a} and {b} must be real numbers or arrays of them") from None
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ya))):
        raise InputError(f"{a} and {b} must be finite (no nan or inf)")
    try:
        return np.broadcast_arrays(xa, ya)
    except ValueError:
        raise InputError(f"{a} and {b} cannot be broadcast together "
                         f"(shapes {xa.shape} and {ya.shape})") from None


def _check_arrays(theta0, theta1):
    import numpy as np

    x0, x1 = _real_arrays(theta0, theta1, ("theta0", "theta1"))
    if x0.size:
        size = float(np.max(np.abs(x0) + 2.0 * np.abs(x1)))
        if size > SIZE_LIMIT:
            raise InputError(f"|theta0| + 2|theta1| = {size:.3g} is too large for the "
                             f"vectorised functions (limit {SIZE_LIMIT:g})")
    return x0, x1


def _bands_double(f0, f1):
    """For flat float arrays theta0, theta1: the number of characteristic values
    below each theta0 and the values just below and above it (-inf/inf at the
    ends), from one eigenproblem per distinct |theta1| (see :func:`is_stable`)."""
    import numpy as np

    absq = np.abs(f1)
    cnt = np.zeros(f0.shape, dtype=int)
    below = np.full(f0.shape, -np.inf)
    above = np.full(f0.shape, np.inf)
    if f0.size == 0:
        return cnt, below, above
    qs, inverse = np.unique(absq, return_inverse=True)
    for i, q in enumerate(qs):
        idx = np.nonzero(inverse == i)[0]
        th = f0[idx]
        # reach beyond the next edge above every theta0 (edges near n^2 lie
        # within ~2|q| + 2n of it)
        reach = (math.sqrt(max(float(th.max()), 0.0) + 2.0 * float(q)) + 3.0) ** 2
        edges = _edges_double(float(q), reach)
        c = np.searchsorted(edges, th, side="left")
        cnt[idx] = c
        below[idx] = np.where(c > 0, edges[np.clip(c - 1, 0, edges.size - 1)], -np.inf)
        above[idx] = np.where(c < edges.size, edges[np.clip(c, 0, edges.size - 1)], np.inf)
    return cnt, below, above


def exponent(theta0, theta1):
    """Vectorised characteristic exponent lam of 000 eq. 7 in double precision.

    theta0, theta1 broadcast against each other; returns a complex array of the
    broadcast shape with the same unfolded lam as :func:`characteristic_exponent`
    (real in (k, k+1) in the k-th stable band, k + i mu in the k-th gap, i mu
    below a_0; ``.real`` is the exponent in the bands).

    The band index comes from the count of characteristic values below theta0
    (eigenvalues of the DLMF 28.4 matrices, as in :func:`is_stable`) and fixes
    the branch; the trace y = cos(pi lam) comes from Hill's determinant
    (:func:`trace_monodromy`).  Near a band edge E with exponent e, lam - e
    would follow from 1 - (-1)^e y, which cancels; it is taken instead as
    d = (-1)^e (y(E) - y(theta0)) with y(E) computed by the same routine, so
    that the (smooth) truncation error of the trace cancels too:
    d = 2 sin^2(pi (lam - e)/2) in a band, -2 sinh^2(pi mu/2) in a gap.
    Accuracy (measured against 25-digit characteristic_exponent on random
    points, tests/test_floquet_vectorised.py): about 1e-9 absolute in lam for
    |theta0|, |theta1| <= 20, also next to the edges (where lam itself depends
    on theta0 like a square root: an input error of 1e-16 moves it by ~1e-8).
    Points whose trace overflows a double (|Im lam| > ~200) are computed one by
    one with characteristic_exponent (double precision, method "hill").
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    out = np.zeros(f0.shape, dtype=complex)
    if f0.size == 0:
        return out.reshape(shape)
    cnt, below, above = _bands_double(f0, f1)
    y = trace_monodromy(f0, f1) / 2.0
    band = cnt % 2 == 1
    k = np.where(band, (cnt - 1) // 2, cnt // 2)
    # edge e and its theta0-value E: in band k the lower edge (e = k) when
    # (-1)^k y >= 0 (lam - k <= 1/2), else the upper one (e = k + 1); in gap k
    # (e = k) the nearer of its two edges
    sk = np.where(k % 2 == 0, 1.0, -1.0)
    lower_half = sk * y >= 0
    e = np.where(band, np.where(lower_half, k, k + 1), k)
    near_below = np.abs(f0 - below) <= np.abs(above - f0)
    E = np.where(band, np.where(lower_half, below, above), np.where(near_below, below, above))
    E = np.where(np.isfinite(E), E, f0)  # below a_0 with no edge below: any finite value
    yE = trace_monodromy(E, f1) / 2.0
    se = np.where(e % 2 == 0, 1.0, -1.0)
    with np.errstate(invalid="ignore", over="ignore"):
        d = se * (yE - y)
        t = 2.0 / np.pi * np.arcsin(np.sqrt(np.clip(d, 0.0, 2.0) / 2.0))
        mu = 2.0 / np.pi * np.arcsinh(np.sqrt(np.maximum(-d, 0.0) / 2.0))
    sign = np.where(e == k, 1.0, -1.0)
    out = np.where(band, e + sign * t + 0j, e + 1j * mu)
    bad = ~(np.isfinite(y) & np.isfinite(yE) & (np.abs(y) < 1e300))
    for i in np.nonzero(bad)[0]:
        out[i] = complex(characteristic_exponent(float(f0[i]), float(f1[i])).lam)
    return out.reshape(shape)


def _char_values_double(theta1_values, kind_order):
    """a_n(q) or b_n(q), q = -theta1, for each distinct theta1 (double precision).

    kind_order: list of ("a"|"b", n); returns dict (theta1, kind, n) -> value."""
    import numpy as np
    from scipy.linalg import eigvalsh_tridiagonal

    out = {}
    top = max(n for _, n in kind_order) if kind_order else 0
    for th1 in np.unique(theta1_values):
        q = -float(th1)
        size = float(top * top) + 2.0 * abs(q)
        m0 = _edge_index(size, q)
        n = m0 // 2 + top // 2 + _tail_steps(size, q, m0, 18) + 3
        vals = {}
        for fam in FAMILIES:
            d, e2 = _family_diagonals(fam, q, n, 1.0)
            vals[fam] = np.sort(eigvalsh_tridiagonal(np.asarray(d, float),
                                                     np.sqrt(np.asarray(e2, float))))
        for kind, m in kind_order:
            fam, j = _family_of(kind, m)
            out[(float(th1), kind, m)] = float(vals[fam][j])
    return out


def _theta0_of_exponent_array(nu, theta1):
    """Vectorised theta0_of_exponent in double precision (see its docstring).

    Non-integer nu: bisection in the band [lo, hi] (edges from :func:`_bands_double`
    at the band's midpoint count) on d(theta0) = d*, with d the edge-referenced
    trace difference of :func:`exponent` and d* = 2 sin^2(pi (nu - e)/2) for the
    integer e nearest nu; d is monotone in the band.  Integer nu: a_nu(q), q = -theta1.
    """
    import numpy as np

    n_arr, t_arr = _real_arrays(nu, theta1, ("nu", "theta1"))
    n_arr = np.abs(n_arr)
    shape = n_arr.shape
    fn, f1 = n_arr.ravel().copy(), t_arr.ravel().copy()
    out = np.empty(fn.shape)
    if fn.size == 0:
        return out.reshape(shape)
    size = float(np.max(fn * fn + 2.0 * np.abs(f1)))
    if size > SIZE_LIMIT:
        raise InputError(f"|nu^2| + 2|theta1| = {size:.3g} is too large for the "
                         f"vectorised functions (limit {SIZE_LIMIT:g})")
    zero_q = f1 == 0
    is_int = (fn == np.floor(fn)) & ~zero_q
    out[zero_q] = fn[zero_q] ** 2
    if np.any(is_int):
        ii = np.nonzero(is_int)[0]
        orders = sorted({("a", int(v)) for v in fn[ii]})
        vals = _char_values_double(f1[ii], orders)
        out[ii] = [vals[(float(t), "a", int(v))] for t, v in zip(f1[ii], fn[ii])]
    todo = np.nonzero(~zero_q & ~is_int)[0]
    if todo.size:
        nu_t, q_t = fn[todo], f1[todo]
        k = np.floor(nu_t).astype(int)
        e = np.rint(nu_t).astype(int)
        # band edges: the (2k+1)-th and (2k+2)-th characteristic values at |q|
        lo = np.empty(todo.size)
        hi = np.empty(todo.size)
        for q in np.unique(np.abs(q_t)):
            idx = np.nonzero(np.abs(q_t) == q)[0]
            top = float((k[idx].max() + 1) ** 2) + 2.0 * q + 1.0
            edges = _edges_double(float(q), top)
            lo[idx] = edges[2 * k[idx]]
            hi[idx] = edges[2 * k[idx] + 1]
        E = np.where(e == k, lo, hi)
        se = np.where(e % 2 == 0, 1.0, -1.0)
        yE = trace_monodromy(E, q_t) / 2.0
        target = 2.0 * np.sin(np.pi * (nu_t - e) / 2.0) ** 2
        # d(theta0) - target is > 0 on the side of E's far end: orient so that
        # phi = (d - target) * orient is increasing in theta0
        orient = np.where(e == k, 1.0, -1.0)
        a, b = lo.copy(), hi.copy()
        for _ in range(200):
            mid = 0.5 * (a + b)
            d = se * (yE - trace_monodromy(mid, q_t) / 2.0)
            phi = (d - target) * orient
            a = np.where(phi < 0, mid, a)
            b = np.where(phi < 0, b, mid)
            if np.all(b - a <= 4e-16 * np.maximum(1.0, np.abs(mid))):
                break
        out[todo] = 0.5 * (a + b)
    return out.reshape(shape)


def is_stable(theta0, theta1, rtol=1e-12):
    """Vectorised stable/unstable verdict for 000 eq. 7 in double precision.

    theta0, theta1 broadcast against each other (numpy arrays or scalars); the
    result is a bool array of the broadcast shape.  A point is stable when an
    odd number of characteristic values a_n(|theta1|), b_n(|theta1|) lie below
    theta0, i.e. inside a stable band.  The characteristic values are
    eigenvalues of the DLMF 28.4 tridiagonal matrices, computed once for each
    distinct |theta1| (so a grid costs one small eigenproblem per row), then
    compared with all theta0 at once.  Points closer than rtol (relative) to a
    characteristic value cannot be classified reliably in double precision: an
    AccuracyWarning says how many; use characteristic_exponent with dps there.
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel(), np.abs(x1.ravel())
    out = np.zeros(f0.shape, dtype=bool)
    close = 0
    if f0.size == 0:
        return out.reshape(shape)
    qs, inverse = np.unique(f1, return_inverse=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.searchsorted(inverse[order], np.arange(len(qs) + 1))
    for i, q in enumerate(qs):
        idx = order[bounds[i]:bounds[i + 1]]
        th = f0[idx]
        edges = _edges_double(float(q), th.max())
        cnt = np.searchsorted(edges, th, side="left")
        out[idx] = (cnt % 2) == 1
        if edges.size and q != 0:  # at q = 0 the edges k^2 are exact
            lo = edges[np.clip(cnt - 1, 0, edges.size - 1)]
            hi = edges[np.clip(cnt, 0, edges.size - 1)]
            dist = np.minimum(np.abs(th - lo), np.abs(th - hi))
            close += int(np.count_nonzero(dist <= rtol * np.maximum(1.0, np.abs(th)) * (1 + q)))
    if close:
        warnings.warn(f"is_stable: {close} point(s) lie within double-precision "
                      f"resolution of a characteristic curve; their verdict is not "
                      f"reliable (use characteristic_exponent with dps)",
                      AccuracyWarning, stacklevel=2)
    return out.reshape(shape)


def trace_monodromy(theta0, theta1):
    """Vectorised trace of the monodromy matrix, 2 cos(pi lam), in double precision.

    Hill's determinant (see the module docstring) evaluated for all points at
    once by the symmetric continuant recurrence; the algebraic truncation error
    (N^-3, N^-4, ...) is removed by Richardson extrapolation over the depths
    N0, 2 N0, 4 N0, 8 N0.  Accurate to about 1e-11 relative to
    max(1, |trace|) for moderate parameters; overflows to inf for very large q.
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    # shift s per point (vectorised form of _hill_shift)
    r = np.sqrt(np.maximum(f0, 0.0))
    s = np.where(f0 <= 0.25, np.where(f0 > -1.0, 1, 0), np.where(np.rint(r) % 2 == 0, 1, 0))
    N0 = int(2 * math.ceil(math.sqrt(float(np.max(np.abs(f0)) + 2 * np.max(np.abs(f1)))))) + 24
    checkpoints = {N0 * 2 ** j: j for j in range(4)}
    one = np.ones_like(f0)

    def g(n):
        return f1 / ((2 * n + s) ** 2 - f0)

    klr, kl1r, klr1, kl1r1 = one.copy(), one.copy(), one.copy(), np.zeros_like(f0)
    L = R = 0
    gR = gL = g(0)
    D = [None] * 4
    with np.errstate(over="ignore", invalid="ignore"):
        for N in range(1, N0 * 8 + 1):
            gn = g(R + 1)
            c = gR * gn
            R += 1
            gR = gn
            klr, kl1r, klr1, kl1r1 = klr - c * klr1, kl1r - c * kl1r1, klr, kl1r
            gn = g(L - 1)
            c = gn * gL
            L -= 1
            gL = gn
            klr, klr1, kl1r, kl1r1 = klr - c * kl1r, klr1 - c * kl1r1, klr, klr1
            if N in checkpoints:
                D[checkpoints[N]] = klr.copy()
        # remove N^-3, N^-4, N^-5 terms
        T = D
        for p in (3, 4, 5):
            fac = 2.0 ** p
            T = [(fac * T[i + 1] - T[i]) / (fac - 1) for i in range(len(T) - 1)]
        delta = T[0]
        cr = np.where(f0 >= 0, np.cos(np.pi * r), np.cosh(np.pi * np.sqrt(np.maximum(-f0, 0.0))))
        cs = np.where(s == 0, 1.0, -1.0)
        y = cs + delta * (cr - cs)
    return (2.0 * y).reshape(shape)
