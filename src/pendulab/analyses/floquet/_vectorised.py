"""Vectorised double precision: exponent, verdict, trace and inverse on arrays,
and the certified characteristic values for many |q| at once (the map's
boundaries, :func:`_certify_edges`)."""

from __future__ import annotations

import math
import warnings

import mpmath

from pendulab.errors import AccuracyWarning, InputError, PrecisionError
from pendulab.analyses.floquet._bands import FAMILIES, _edge_index, _family_diagonals, _tail_steps
from pendulab.analyses.floquet._exponent import characteristic_exponent
from pendulab.analyses.floquet._hill import continuants
from pendulab.analyses.floquet._inputs import SIZE_LIMIT, _size_text


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
        xa, ya = np.asarray(x), np.asarray(y)
        if np.iscomplexobj(xa) or np.iscomplexobj(ya):
            raise TypeError("complex")     # refused, not cast to its real part
        xa = xa.astype(float, copy=False)
        ya = ya.astype(float, copy=False)
    except (TypeError, ValueError, OverflowError):
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
            raise InputError(f"|theta0| + 2|theta1| = {_size_text(size, SIZE_LIMIT)} is too large "
                             f"for the vectorised functions (limit {SIZE_LIMIT:g})")
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
    the branch.  Inside band k, lam is the root in (k, k+1) of
    det(J(lam) - theta0), J(lam) the symmetric tridiagonal matrix with diagonal
    (2n + lam)^2 and off-diagonal theta1 (n in Z; 000 eqs. 9-10 as an
    eigenproblem in theta0), by safeguarded Newton (:func:`_band_nu`).  In the
    gaps and below a_0 the trace y = cos(pi lam) comes from Hill's determinant
    (:func:`trace_monodromy`): near a band edge E with exponent e, lam - e
    would follow from 1 - (-1)^e y, which cancels; it is taken instead as
    d = (-1)^e (y(E) - y(theta0)) with y(E) computed by the same routine, so
    that the (smooth) truncation error of the trace cancels too:
    d = 2 sin^2(pi (lam - e)/2) in a band, -2 sinh^2(pi mu/2) in a gap.
    Accuracy (docs/floquet.md): backward stable in the bands and next to the
    edges.  The backward error |lam - nu| d theta0/d lam is below
    1.4e-15 max(1, |theta0|) on MathieuFunctions.jl's lambda grid
    (tests/test_floquet_lambda_grid.py) and at rounding level next to the
    edges; the forward error is that divided by |d theta0/d lam|, which
    vanishes at an edge (lam - e moves like the square root of theta0 - E):
    about 1e-12 absolute away from the edges against 25-digit
    characteristic_exponent (tests/test_floquet_vectorised.py), up to ~1e-7
    within 1e-6 of an edge.  Deep in a gap the trace's accuracy counts: mu
    is good to ~1e-11 relative for |theta1| up to 50, ~1e-10 up to 400.
    Points the double routes cannot resolve are computed one by one
    (~10-25 ms each) with characteristic_exponent (double precision, method
    "hill", guard digits): a band narrower than
    :data:`THIN_BAND` of the scale, a gap point whose edge trace is not +-1
    (:data:`EDGE_TRACE_TOL`: bands thinner than their rounding, or a trace lost
    to cancellation at theta0 << 0), and a trace that overflows (|Im lam| > ~200).
    """
    import numpy as np

    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float, copy=False), x1.ravel().astype(float, copy=False)
    out = np.zeros(f0.shape, dtype=complex)
    if f0.size == 0:
        return out.reshape(shape)
    cnt, below, above = _bands_fast(f0, f1)
    band = (cnt & 1) == 1
    # theta1 = 0: lam = sqrt(theta0) exactly
    zero = f1 == 0
    if zero.any():
        out[zero] = np.sqrt(f0[zero] + 0j)
    # inside a band: lam real, the root in (k, k+1) of det(J(lam) - theta0)
    in_band = band & ~zero & np.isfinite(below) & np.isfinite(above)
    # a band thinner than the rounding of its edges: the scalar routine
    with np.errstate(invalid="ignore"):
        thin = in_band & (above - below <= THIN_BAND * np.maximum(
            1.0, np.maximum(np.abs(f0), np.abs(f1))))
    if thin.any():
        in_band &= ~thin
        out[thin] = _scalar_exponents(f0[thin], f1[thin])
    inb = np.nonzero(in_band)[0]
    lib = _c_band() if inb.size else None
    if lib is not None:
        _c_band_all(lib, 1, inb, f0, np.abs(f1), cnt, below, above, out)
    elif inb.size:
        k = (cnt[inb] - 1) >> 1             # (cnt - 1) // 2, cnt odd
        absq = np.abs(f1[inb])
        # one truncation per band index and octave of |q| (rows grow like sqrt|q|);
        # the points sorted by group once
        order, cuts = _group_order(k * 4096 + _octave(absq))
        at = inb[order]
        out[at] = _solve_groups(_band_nu, f0[at], absq[order], k[order],
                                below[at], above[at], cuts)
    ri = np.nonzero(~in_band & ~zero & ~thin)[0]
    if ri.size:
        out[ri] = _exponent_by_trace(f0[ri], f1[ri], cnt[ri], below[ri], above[ri])
    return out.reshape(shape)


def _octave(absq):
    """floor(log2 |q|), at least -4, for positive |q| (exact: the binary exponent;
    the group key of :func:`exponent` and :func:`_theta0_of_exponent_array`,
    the same as octave() in :data:`_BAND_C`)."""
    import numpy as np

    return np.maximum(np.frexp(absq)[1].astype(np.int64) - 1, -4)


def _c_band_all(lib, kind, idx, p, absq, kc, lo, hi, out, oidx=None):
    """A band route in the C kernel for a list of points, without sorting or
    gathering in NumPy: the groups of :func:`_group_order` (the same keys, so the
    same truncation R per group and the same bits as the NumPy path) from
    pendulab_band_groups, then the Newton loops of pendulab_band_all.

    kind 1 (:func:`exponent`): the points ``idx`` of the flat arrays theta0 ``p``,
    ``absq``, ``kc`` (the count of characteristic values below theta0), ``lo``,
    ``hi``; lam goes to the real parts of ``out`` (complex) at ``idx``.
    kind 0 (:func:`_theta0_of_exponent_array`): all points of nu ``p``, ``absq``,
    ``kc`` (k = floor(nu)), ``lo``, ``hi``; the eigenvalue goes to out[oidx]."""
    import ctypes

    import numpy as np

    PD, PL = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_long)

    def d(a):
        return np.ascontiguousarray(a, dtype=np.float64)

    p, absq, lo, hi = d(p), d(absq), d(lo), d(hi)
    kc = np.ascontiguousarray(kc, dtype=np.int64)
    if kind:
        idx = np.ascontiguousarray(idx, dtype=np.int64)
        n, kmax, qtop = idx.size, (int(kc[idx].max()) - 1) >> 1, float(absq[idx].max())
        ip, flat = idx.ctypes.data_as(PL), out.view(np.float64)
        op = None
    else:
        n, kmax, qtop = p.size, int(kc.max()), float(absq.max())
        ip, flat = None, out
        oidx = np.ascontiguousarray(oidx, dtype=np.int64)
        op = oidx.ctypes.data_as(PL)
    noct = int(_octave(np.array([qtop]))[0]) + 5
    G = (kmax + 1) * noct
    gid = np.empty(n, dtype=np.int64)
    himax, qmax = np.empty(G), np.empty(G)
    count = np.zeros(G, dtype=np.int64)
    lib.pendulab_band_groups(kind, n, ip, absq.ctypes.data_as(PD), kc.ctypes.data_as(PL),
                             hi.ctypes.data_as(PD), noct, G, gid.ctypes.data_as(PL),
                             himax.ctypes.data_as(PD), qmax.ctypes.data_as(PD),
                             count.ctypes.data_as(PL))
    negR = np.zeros(G)
    L = np.zeros(G, dtype=np.int64)
    extra, maxit = _NEWTON[kind]
    for g in np.nonzero(count)[0].tolist():
        R = _shifted_rows(float(himax[g]), float(qmax[g]))
        negR[g], L[g] = float(-R), int(R) + extra
    if lib.pendulab_band_all(kind, n, ip, op, gid.ctypes.data_as(PL), G, p.ctypes.data_as(PD),
                             absq.ctypes.data_as(PD), kc.ctypes.data_as(PL),
                             lo.ctypes.data_as(PD), hi.ctypes.data_as(PD),
                             negR.ctypes.data_as(PD), L.ctypes.data_as(PL), maxit,
                             flat.ctypes.data_as(PD)) < 0:
        raise MemoryError("the band kernel could not allocate its work arrays")


#: (rows beyond R, most Newton iterations) of each band route: kind 0, the
#: inverse's eigenvalue (:func:`_band_eigen`); kind 1, the exponent (:func:`_band_nu`).
#: The NumPy loops and the C kernel read them from here.
_NEWTON = {0: (2, 120), 1: (4, 200)}


def _group_order(key):
    """(order, cuts): the stable sort of the integer array ``key`` and the
    boundaries [0, ..., key.size] of its runs of equal values.  A key spanning
    fewer than 2^15 values is sorted as int16 (radix sort, the same order)."""
    import numpy as np

    if key.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64)
    kmin = int(key.min())
    if int(key.max()) - kmin < 32767:
        order = np.argsort((key - kmin).astype(np.int16), kind="stable")
    else:
        order = np.argsort(key, kind="stable")
    ks = key[order]
    cuts = np.concatenate(([0], np.nonzero(ks[1:] != ks[:-1])[0] + 1, [key.size]))
    return order, cuts


def _solve_groups(solve, P, A, K, LO, HI, cuts):
    """The NumPy path of a band route: ``solve`` (:func:`_band_eigen` or
    :func:`_band_nu`) on points sorted by group of equal (k, octave of |q|)
    (group g is the slice cuts[g]:cuts[g + 1], see :func:`_group_order`), one
    truncation R per group from its largest hi and |q| (the C kernel's
    :func:`_c_band_all` takes the same groups).  Results in the order of the points."""
    import numpy as np

    Q2 = A * A
    res = np.empty(P.size)
    for s0, s1 in zip(cuts[:-1].tolist(), cuts[1:].tolist()):
        sl = slice(s0, s1)
        R = _shifted_rows(float(HI[sl].max()), float(A[sl].max()))
        res[sl] = solve(P[sl], Q2[sl], K[sl], LO[sl], HI[sl], R)
    return res


#: Points of one call whose size (max(theta0, 0) or (k + 1)^2, plus 2|theta1|)
#: lies below this share one table of certified edges; above it, each octave of
#: size gets its own (:func:`_size_groups`), so that one large point does not
#: make the table of every |theta1| of the call as large as its own
SIZE_BUCKET = 1024.0


def _size_groups(size):
    """[index arrays] of the points grouped by octave of ``size`` above
    :data:`SIZE_BUCKET`, or None when they all fall in one group."""
    import numpy as np

    key = np.floor(np.log2(np.maximum(size, SIZE_BUCKET))).astype(np.int64)
    if key.size == 0 or int(key.min()) == int(key.max()):
        return None
    order, cuts = _group_order(key)
    return [order[a:b] for a, b in zip(cuts[:-1].tolist(), cuts[1:].tolist())]


def _by_size(size, fn, *arrays):
    """fn(*arrays) (a tuple of arrays shaped like the points) computed group by
    group of :func:`_size_groups`, or at once when there is one group."""
    import numpy as np

    groups = _size_groups(size)
    if groups is None:
        return fn(*arrays)
    outs = None
    for g in groups:
        res = fn(*(a[g] for a in arrays))
        if outs is None:
            outs = tuple(np.empty(size.shape, dtype=r.dtype) for r in res)
        for o, r in zip(outs, res):
            o[g] = r
    return outs


def _bands_fast(f0, f1):
    """:func:`_bands_double` from the certified values (batched over |q|) when
    there are many distinct |q|; LAPACK one |q| at a time otherwise; the points
    in groups of size (:func:`_by_size`)."""
    import numpy as np

    return _by_size(np.maximum(f0, 0.0) + 2.0 * np.abs(f1), _bands_fast_one, f0, f1)


def _bands_fast_one(f0, f1):
    """:func:`_bands_fast` for points of one size group."""
    import numpy as np

    qs, inv = _unique_inverse(np.abs(f1))
    if qs.size <= 16:
        return _bands_double(f0, f1)
    # far enough for the edge above the largest theta0 (successive edges lie
    # within 2 sqrt(theta0 + 2|q|) + 3 of each other); a point without one
    # takes the trace route of :func:`exponent`
    t = max(float(f0.max()), 0.0)
    reach = float(f0.max()) + 2.0 * math.sqrt(t + 2.0 * float(qs.max())) + 4.0
    try:
        E, _ = _certify_edges(qs, reach)
    except PrecisionError:
        return _bands_double(f0, f1)
    ne = E.shape[1]
    lib = _c_band()
    if lib is not None and ne:
        return _c_band_count(lib, f0, inv, E)
    # the count of edges below theta0, one column (ascending) at a time; the
    # rows are sorted, so no later column counts once one does not
    cnt = np.zeros(f0.size, dtype=np.int64)
    ET = np.ascontiguousarray(E.T)
    for j in range(ne):
        c = ET[j][inv] < f0
        if not c.any():
            break
        cnt += c
    if not ne:
        return cnt, np.full(f0.shape, -np.inf), np.full(f0.shape, np.inf)
    Ef = E.ravel()
    base = inv * ne
    below = np.where(cnt > 0, Ef[base + np.clip(cnt - 1, 0, ne - 1)], -np.inf)
    above = np.where(cnt < ne, Ef[base + np.clip(cnt, 0, ne - 1)], np.inf)
    return cnt, below, above


def _c_band_count(lib, f0, inv, E):
    """(cnt, below, above) of :func:`_bands_fast` in the C kernel: per point, the
    edges of its row of E below theta0 and the two around it (the same values)."""
    import ctypes

    import numpy as np

    PD, PL = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_long)
    t0 = np.ascontiguousarray(f0, dtype=np.float64)
    row = np.ascontiguousarray(inv, dtype=np.int64)
    Ec = np.ascontiguousarray(E, dtype=np.float64)
    cnt = np.empty(t0.size, dtype=np.int64)
    below = np.empty(t0.size)
    above = np.empty(t0.size)
    lib.pendulab_band_count(t0.size, t0.ctypes.data_as(PD), row.ctypes.data_as(PL),
                            Ec.ctypes.data_as(PD), Ec.shape[1], cnt.ctypes.data_as(PL),
                            below.ctypes.data_as(PD), above.ctypes.data_as(PD))
    return cnt, below, above


def _band_nu(th0, q2, k, lo, hi, R, chunk=8192):
    """The exponent lam in (k, k+1) with theta0 = lambda_lam(q): the root of
    det(J(lam) - theta0) (J of :func:`_band_eigen`), for arrays of one shape
    whose theta0 lies in band k = (lo, hi).

    Safeguarded Newton in lam (d/dlam of the pivots: u_i' = 2 m_i + (theta1^2 /
    u_{i-1}) u_{i-1}'/u_{i-1}), the bracket in (k, k+1) kept by the Sturm count
    (k + 1 eigenvalues below theta0: lam is below the root), bisection when a
    step leaves it.  Next to an edge lam - e moves like the square root of
    theta0 - E, so rounding of det at the 1e-16 level gives ~1e-16/(lam - e).
    The loop runs in the C kernel :data:`_BAND_C` when it builds (the same bits),
    else in NumPy (:func:`_band_nu_chunk`)."""
    lib = _c_band()
    if lib is not None:
        extra, maxit = _NEWTON[1]
        return _c_newton(lib, 1, th0, q2, k, lo, hi, _band_nu_guess(th0, k, lo, hi), R,
                         int(R) + extra, maxit)
    return _in_chunks(_band_nu_chunk, th0, q2, k, lo, hi, R, chunk)


def _in_chunks(chunk_fn, x, q2, k, lo, hi, R, chunk):
    """The NumPy fallback of a band Newton, ``chunk_fn`` on slices of at most 16 MB of rows."""
    import numpy as np

    out = np.empty(x.size)
    chunk = max(16, min(chunk, int(2e6 // (R + 4))))   # (rows, chunk) at most 16 MB
    for s in range(0, x.size, chunk):
        sl = slice(s, s + chunk)
        out[sl] = chunk_fn(x[sl], q2[sl], k[sl], lo[sl], hi[sl], R)
    return out


#: arccos x = sqrt(1 - x) (a0 + a1 x + ... + a7 x^7) + e, |e| <= 2e-8 on [0, 1]
#: (Abramowitz & Stegun 4.4.46): the guess of the band route from +, -, *, / and
#: sqrt alone, so that NumPy and the C kernel give it with the same bits on
#: every machine (NumPy's arccos and the C library's acos may differ in the last bit)
_ACOS_COEFFS = (1.5707963050, -0.2145988016, 0.0889789874, -0.0501743046,
                0.0308918810, -0.0170881256, 0.0066700901, -0.0012624911)


def _horner(coeffs, y):
    """coeffs[0] + coeffs[1] y + ... by Horner's rule from the top, in place
    (the operation order of the C kernel's acos_over_pi and cospi01)."""
    r = coeffs[-1] * y
    for c in coeffs[-2:0:-1]:
        r += c
        r *= y
    r += coeffs[0]
    return r


def _acos_over_pi(t):
    """arccos(t)/pi to 1e-8 for an array t in [-1, 1] (:data:`_ACOS_COEFFS`; the
    operations of acos_over_pi in :data:`_BAND_C`)."""
    import numpy as np

    y = np.abs(t)
    r = _horner(_ACOS_COEFFS, y)
    r *= np.sqrt(1.0 - y)
    r = np.where(t >= 0.0, r, math.pi - r)
    r /= math.pi
    return r


def _band_nu_guess(th0, k, lo, hi):
    """The first lam of :func:`_band_nu` (NumPy, for both paths)."""
    import numpy as np

    kf = k.astype(float)
    span = hi - lo
    np.maximum(span, 1e-300, out=span)
    # guess: the trace cos(pi lam) taken as linear in theta0 across the band
    # and, for a band as wide as at q = 0, sqrt(theta0) with [lo, hi] mapped onto [k^2, (k+1)^2]
    # (in place, the operations of lam = (1 - wide) (kf + arccos(1 - 2 w)/pi)
    # + wide sqrt(kf^2 + w (2 kf + 1)), w = clip((th0 - lo)/span), wide = clip(span/(2 kf + 1))^2)
    w = th0 - lo
    w /= span
    np.clip(w, 0.0, 1.0, out=w)
    k21 = 2.0 * kf
    k21 += 1.0
    wide = span
    wide /= k21
    np.clip(wide, 0.0, 1.0, out=wide)
    np.multiply(wide, wide, out=wide)
    t = 2.0 * w
    np.subtract(1.0, t, out=t)
    a = _acos_over_pi(t)
    a += kf
    t = 1.0 - wide
    t *= a
    np.multiply(w, k21, out=w)
    kf2 = kf * kf
    kf2 += w
    a = np.sqrt(kf2)
    a *= wide
    t += a
    lo_c = kf + 1e-9
    hi_c = kf + 1.0
    hi_c -= 1e-9
    return np.clip(t, lo_c, hi_c, out=t)


def _band_nu_chunk(th0, q2, k, lo, hi, R):
    """The NumPy path of :func:`_band_nu` (the C kernel, :data:`_BAND_C`, does the
    same operations point by point)."""
    import numpy as np

    extra, maxit = _NEWTON[1]
    L = int(R) + extra
    kf = k.astype(float)
    n0 = 2.0 * np.floor((-R - kf - 1.0) / 2.0)       # 2n of the first row, for all lam in (k, k+1)
    steps = n0[None, :] + 2.0 * np.arange(L)[:, None]  # exact even integers
    lam = _band_nu_guess(th0, k, lo, hi)
    a, b = kf.copy(), kf + 1.0
    out = lam.copy()
    idx = np.arange(th0.size)
    live = np.ones(th0.size, dtype=bool)
    t0, e2, ka, kfa = th0, q2, k, kf
    for _it in range(maxit):
        if idx.size == 0:
            break
        la = lam[idx]
        r = np.empty_like(la)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            m = steps[0] + la
            u = m * m - t0
            cnt = (u < 0).astype(np.int64)
            g = 2.0 * m / u               # g_i = u_i'/u_i (d/dlam)
            sm = g.copy()
            for i in range(1, L):
                np.divide(e2, u, out=r)   # r = theta1^2/u_{i-1}
                g *= r                    # u_i' = 2 m_i + r g_{i-1}
                np.add(steps[i], la, out=m)
                g += m
                g += m
                np.multiply(m, m, out=u)
                u -= t0
                u -= r
                cnt += u < 0
                g /= u
                sm += g
            below = cnt >= ka + 1
            aa = np.where(below, la, a[idx])
            bb = np.where(below, b[idx], la)
            step = 1.0 / sm
            ln = la - step
        scale = np.maximum(1.0, np.abs(la))
        small = np.abs(step) <= 4.0 * _U * scale
        bad = ~(np.isfinite(ln) & (ln > aa) & (ln < bb)) & ~small
        ln = np.where(bad, 0.5 * (aa + bb), ln)
        # the other roots in lam lie at 2j - lam* (outside (k, k+1)) and beyond
        dist = np.minimum(ln - kfa, kfa + 1.0 - ln)
        early = ~bad & (step * step * L <= 0.25 * _U * scale * dist)
        done = small | early | (bb - aa <= 4.0 * _U * scale)
        a[idx], b[idx] = aa, bb
        lam[idx] = np.where(live[idx], ln, lam[idx])
        fin = idx[done & live[idx]]
        out[fin] = lam[fin]
        live[fin] = False
        keep = live[idx]
        if not keep.any():
            idx = idx[:0]
            break
        if keep.sum() <= 0.5 * idx.size:
            idx, steps = idx[keep], steps[:, keep]
            t0, e2, ka, kfa = t0[keep], e2[keep], ka[keep], kfa[keep]
    out[live] = lam[live]
    return out


def _exponent_by_trace(f0, f1, cnt, below, above):
    """lam from Hill's determinant (the gaps, below a_0, and the rest; see
    :func:`exponent`)."""
    import numpy as np

    _check_arrays(f0, f1)
    N0 = _trace_depth(f0, f1)
    # (2 y) / 2: the rounding of trace_monodromy / 2 (overflow to inf included)
    y = 2.0 * _trace_half(f0, f1, N0) / 2.0
    B = np.where(np.isfinite(below), below, f0)
    A = np.where(np.isfinite(above), above, f0)
    band = cnt % 2 == 1
    k = np.where(band, (cnt - 1) // 2, cnt // 2)
    # edge e and its theta0-value E: in band k the lower edge (e = k) when
    # (-1)^k y >= 0 (lam - k <= 1/2), else the upper one (e = k + 1); in gap k
    # (e = k) the nearer of its two edges
    sk = np.where(k % 2 == 0, 1.0, -1.0)
    lower_half = sk * y >= 0
    e = np.where(band, np.where(lower_half, k, k + 1), k)
    near_below = np.abs(f0 - below) <= np.abs(above - f0)
    at_below = np.where(band, lower_half, near_below)
    # below a_0 with no edge below: any finite value (B, A are f0 there)
    E = np.where(at_below, B, A)
    NE = _trace_depth(E, f1)
    # the recurrence is per point: where E is theta0 itself (a point on an
    # edge) at the same depth, y(E) is y; the others are computed
    same = E == f0 if NE == N0 else np.zeros(f0.shape, dtype=bool)
    yE = y.copy()
    oth = np.nonzero(~same)[0]
    if oth.size:
        yE[oth] = 2.0 * _trace_half(E[oth], f1[oth], NE) / 2.0
    se = np.where(e % 2 == 0, 1.0, -1.0)
    with np.errstate(invalid="ignore", over="ignore"):
        d = se * (yE - y)
        t = 2.0 / np.pi * np.arcsin(np.sqrt(np.clip(d, 0.0, 2.0) / 2.0))
        mu = 2.0 / np.pi * np.arcsinh(np.sqrt(np.maximum(-d, 0.0) / 2.0))
        sign = np.where(e == k, 1.0, -1.0)
        # (an overflowed trace gives mu = inf or nan here; such points are redone below)
        out = np.where(band, e + sign * t + 0j, e + 1j * mu)
    bad = ~(np.isfinite(y) & np.isfinite(yE) & (np.abs(y) < 1e300))
    # d = (-1)^e (y(E) - y) leaves out 1 - (-1)^e y(E), zero at a true edge: the
    # edge's own trace must be +-1 to the trace's accuracy, or that term small
    # beside d.  Where neither holds the double edge does not resolve the edge
    # (a band thinner than its rounding, or a trace that has lost its digits to
    # cancellation at theta0 << 0) and d means nothing
    with np.errstate(invalid="ignore"):
        off = np.abs(yE - se)
        bad |= ~((off <= EDGE_TRACE_TOL) | (off <= 1e-10 * np.abs(d)))
    out[bad] = _scalar_exponents(f0[bad], f1[bad])
    return out


#: The largest |y(E) - (-1)^e| of a resolved edge in the gap route of
#: :func:`exponent` (truncation and rounding of the trace there are ~1e-10 and
#: below), unless it is below 1e-10 |d| (then it changes mu by ~1e-11 at most)
EDGE_TRACE_TOL = 1e-6
#: A stable band narrower than this times max(1, |theta0|, |theta1|) is not
#: resolved by double-precision edges (their error is ~1e-15 of that scale): its
#: points go to the scalar routine
THIN_BAND = 1e-9


def _scalar_exponents(f0, f1):
    """lam of each point by :func:`characteristic_exponent` (double precision,
    method "hill" with its guard digits): the points the vectorised routes
    cannot resolve."""
    import numpy as np

    return np.array([complex(characteristic_exponent(float(a), float(b)).lam)
                     for a, b in zip(f0.tolist(), f1.tolist())], dtype=complex)


def _shifted_rows(top, absq, digits=8):
    """Truncation of J(nu): rows m = 2n + nu with |m| <= R, R from the tail rule
    (eigenvector components below 10^-digits there, so that the eigenvalue,
    which changes with their square, is exact to 10^-(2 digits)) for theta0 <= top."""
    m0 = _edge_index(top, absq)
    return m0 + 2 * _tail_steps(top, absq, m0, digits)


def _theta0_of_exponent_polished(NU, X1):
    """theta0_of_exponent(nu, theta1) to double precision for one non-integer nu
    and theta1 != 0 (exact inputs: Fraction or mpf).

    The vectorised root (:func:`_band_eigen`) refined by Newton on
    det(J(nu) - x) in mpmath, at 30 digits with rows to 10^-16 and at 40 digits
    with four more rows; returns None (the caller then solves the cf function)
    when the two differ by more than 1e-22 relative, Newton does not settle, or
    the result leaves the band or moves from the double root by more than 1e-10."""
    import numpy as np

    nu_f, th_f = float(NU), float(X1)
    k = math.floor(NU)
    if nu_f != nu_f or math.floor(nu_f) != k or nu_f == k:
        return None
    lo, hi = _band_edges(np.array([abs(th_f)]), np.array([k], dtype=np.int64))
    x0 = float(_band_eigen(np.array([nu_f]), np.array([th_f * th_f]), np.array([k]), lo, hi,
                           _shifted_rows(float(hi[0]), abs(th_f)))[0])
    lo, hi = float(lo[0]), float(hi[0])
    scale = max(1.0, abs(x0))
    R = _shifted_rows(hi, abs(th_f), 16)
    found = []
    for dps, extra in ((30, 0), (40, 4)):
        with mpmath.workdps(dps):
            nu = mpmath.mpf(NU.numerator) / NU.denominator if hasattr(NU, "denominator") else +NU
            th = mpmath.mpf(X1.numerator) / X1.denominator if hasattr(X1, "denominator") else +X1
            q2 = th * th
            Rm = R + 2 * extra
            n0 = 2 * math.floor((-Rm - nu_f) / 2.0)
            diag = [(nu + (n0 + 2 * i)) ** 2 for i in range(Rm + 2)]
            x = mpmath.mpf(x0)
            tol = mpmath.mpf(10) ** (5 - dps) * scale
            for _ in range(12):
                u = diag[0] - x
                du = mpmath.mpf(-1)
                s = du / u
                for d in diag[1:]:
                    r = q2 / u
                    du = -1 + r * du / u
                    u = d - x - r
                    s += du / u
                step = 1 / s
                x -= step
                if abs(step) <= tol:
                    break
            else:
                return None
            found.append(x)
    with mpmath.workdps(40):
        if abs(found[0] - found[1]) > mpmath.mpf(10) ** -22 * scale:
            return None
    v = float(found[1])
    if not (lo - 1e-9 * scale <= v <= hi + 1e-9 * scale) or abs(v - x0) > 1e-10 * scale:
        return None
    return v


def _band_eigen(nu, q2, k, lo, hi, R, chunk=8192):
    """The k-th eigenvalue (0-based) of J(nu): rows m = 2n + nu (n integer,
    |m| <= R), diagonal m^2, off-diagonal theta1 (squared: q2), for arrays nu,
    q2, k, lo, hi of one shape; lo < eigenvalue < hi is the band.

    Safeguarded Newton on det(J - x) (pivots u_i of LDL^T: f'/f = sum u_i'/u_i),
    the bracket kept by the Sturm count (k below x: x is above the root),
    bisection when a step leaves the bracket.  The count is exact for off-
    diagonals perturbed by 2.5 ulp (Kahan), so the root is the eigenvalue of
    the float matrix to a few ulps of max(|x|, |q|).  The loop runs in the C
    kernel :data:`_BAND_C` when it builds (the same bits), else in NumPy in
    chunks that stay in the cache (:func:`_band_eigen_chunk`)."""
    lib = _c_band()
    if lib is not None:
        extra, maxit = _NEWTON[0]
        return _c_newton(lib, 0, nu, q2, k, lo, hi, _band_eigen_guess(nu, k, lo, hi), R,
                         int(R) + extra, maxit)
    return _in_chunks(_band_eigen_chunk, nu, q2, k, lo, hi, R, chunk)


#: sin z = z (c0 + c1 z^2 + ... + c7 z^14) + e, c_j = (-1)^j/(2j + 1)!, |e| < 1e-11
#: for |z| <= pi/2 (the Taylor series): the guess of theta0_of_exponent's band
#: route from +, -, * alone, the same bits in NumPy and in the C kernel
_SIN_COEFFS = tuple((-1) ** j / math.factorial(2 * j + 1) for j in range(8))


def _cospi01(x):
    """cos(pi x) to 1e-11 for an array x in [0, 1] (:data:`_SIN_COEFFS`, as
    -sin(pi (x - 1/2)); the operations of cospi01 in :data:`_BAND_C`)."""
    z = x - 0.5
    z *= math.pi
    r = _horner(_SIN_COEFFS, z * z)
    r *= z
    return -r


def _band_eigen_guess(nu, k, lo, hi):
    """The first x of :func:`_band_eigen` (NumPy, for both paths)."""
    import numpy as np

    span = hi - lo
    np.maximum(span, 0.0, out=span)
    kk = k.astype(float)
    # guess: the trace cos(pi nu) taken as linear in theta0 across the band
    # (from +-1 at lo to -+1 at hi; exact for a thin band)
    # and, for a band as wide as at q = 0, the q = 0 value nu^2 mapped onto it
    # (in place, the operations of w = (1 - wide) (0.5 - 0.5 cos(pi (nu - k)))
    # + wide clip((nu^2 - k^2)/(2k + 1)), wide = clip(span/(2k + 1))^2, x = lo + span w)
    k21 = 2.0 * kk
    k21 += 1.0
    wide = span / k21
    np.clip(wide, 0.0, 1.0, out=wide)
    np.multiply(wide, wide, out=wide)
    c = nu - kk
    c = _cospi01(c)
    c *= 0.5
    np.subtract(0.5, c, out=c)
    w = 1.0 - wide
    w *= c
    v = nu * nu
    np.multiply(kk, kk, out=kk)
    v -= kk
    v /= k21
    np.clip(v, 0.0, 1.0, out=v)
    v *= wide
    w += v
    w *= span
    w += lo
    return np.clip(w, lo, hi, out=w)


def _band_eigen_chunk(nu, q2, k, lo, hi, R):
    """The NumPy path of :func:`_band_eigen` (the C kernel, :data:`_BAND_C`, does
    the same operations point by point)."""
    import numpy as np

    extra, maxit = _NEWTON[0]
    L = int(R) + extra
    # diagonal m^2, m = 2n + nu with one rounding (the row n = 0 is nu itself)
    n0 = 2.0 * np.floor((-R - nu) / 2.0)                # 2n of the first row
    D = ((n0[None, :] + 2.0 * np.arange(L)[:, None]) + nu[None, :]) ** 2
    x = _band_eigen_guess(nu, k, lo, hi)
    a, b = lo.copy(), hi.copy()
    out = x.copy()
    idx = np.arange(nu.size)        # the points still iterating (columns of D)
    live = np.ones(nu.size, dtype=bool)
    e2, ka, la, ha = q2, k, lo, hi
    for _it in range(maxit):
        if idx.size == 0:
            break
        xa = x[idx]
        r = np.empty_like(xa)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            u = D[0] - xa
            cnt = (u < 0).astype(np.int64)
            g = -1.0 / u                  # g_i = u_i'/u_i
            sm = g.copy()
            for i in range(1, L):
                np.divide(e2, u, out=r)   # r = theta1^2/u_{i-1}
                g *= r
                g -= 1.0                  # u_i' = -1 + r g_{i-1}
                np.subtract(D[i], xa, out=u)
                u -= r
                cnt += u < 0
                g /= u
                sm += g
            below = cnt <= ka
            aa = np.where(below, xa, a[idx])
            bb = np.where(below, b[idx], xa)
            step = 1.0 / sm
            xn = xa - step
        scale = np.maximum(1.0, np.abs(xa))
        # a step at rounding level is the root (it may cross the bracket's end
        # by rounding); otherwise a step out of the bracket is replaced by bisection
        small = np.abs(step) <= 4.0 * _U * scale
        bad = ~(np.isfinite(xn) & (xn > aa) & (xn < bb)) & ~small
        xn = np.where(bad, 0.5 * (aa + bb), xn)
        # Newton's next error is about step^2 sum 1/|lambda_i - x| over the other
        # eigenvalues, all outside the band: below step^2 L / dist
        dist = np.minimum(xn - la, ha - xn)
        early = ~bad & (step * step * L <= 0.25 * _U * scale * dist)
        done = small | early | (bb - aa <= 4.0 * _U * scale)
        a[idx], b[idx] = aa, bb
        x[idx] = np.where(live[idx], xn, x[idx])
        fin = idx[done & live[idx]]
        out[fin] = x[fin]
        live[fin] = False
        keep = live[idx]
        if not keep.any():
            idx = idx[:0]
            break
        if keep.sum() <= 0.5 * idx.size:       # compact the columns still iterating
            idx, D = idx[keep], D[:, keep]
            e2, ka, la, ha = e2[keep], ka[keep], la[keep], ha[keep]
    out[live] = x[live]
    return out


#: C99 text of the Newton loops of :func:`_band_eigen_chunk` and
#: :func:`_band_nu_chunk` (compiled by :func:`pendulab.numerics.ckernel.load_source`
#: with -ffp-contract=off and no -ffast-math: the same IEEE operations in the same
#: order, so the same bits as the NumPy path; tests/test_vectorised_ckernel.py)
_BAND_C = "".join(f"#define ACOS_A{i} {c!r}\n" for i, c in enumerate(_ACOS_COEFFS)) + \
    "".join(f"#define SIN_C{i} {c!r}\n" for i, c in enumerate(_SIN_COEFFS)) + \
    f"#define PI_D {math.pi!r}\n" + r"""
/* Newton iterations of pendulab.analyses.floquet._vectorised (_band_eigen_chunk,
   _band_nu_chunk), point by point: the same IEEE double operations in the
   same order as the NumPy code, so the results are the same bits.  LANES
   points are swept through the rows together (the loop over lanes
   vectorises); a lane whose point has finished takes the next point. */
#include <math.h>
#include <stdlib.h>

#define LANES 8

static const double U4 = 4.0 * 0x1p-53;   /* 4.0 * _U */
static const double U025 = 0.25 * 0x1p-53; /* 0.25 * _U */

static double npmax1(double x) { return x >= 1.0 || x != x ? x : 1.0; }   /* np.maximum(1.0, x) */
static double npmin(double x, double y) { return (x != x || x <= y) ? x : (y != y ? y : y); }
static double npclip(double x, double a, double b) { return x < a ? a : (x > b ? b : x); }

/* acos(t)/pi for t in [-1, 1] from +, -, *, / and sqrt only (_acos_over_pi) */
static double acos_over_pi(double t)
{
    double y = fabs(t);
    double r = ACOS_A7 * y;
    r += ACOS_A6; r *= y; r += ACOS_A5; r *= y; r += ACOS_A4; r *= y; r += ACOS_A3; r *= y;
    r += ACOS_A2; r *= y; r += ACOS_A1; r *= y; r += ACOS_A0;
    r *= sqrt(1.0 - y);
    if (!(t >= 0.0)) r = PI_D - r;
    return r / PI_D;
}

/* cos(pi x) for x in [0, 1] from +, -, * alone (_cospi01) */
static double cospi01(double x)
{
    double z = x - 0.5;
    z *= PI_D;
    double t = z * z;
    double r = SIN_C7 * t;
    r += SIN_C6; r *= t; r += SIN_C5; r *= t; r += SIN_C4; r *= t; r += SIN_C3; r *= t;
    r += SIN_C2; r *= t; r += SIN_C1; r *= t; r += SIN_C0;
    r *= z;
    return -r;
}

/* the first x of theta0_of_exponent's band route (_band_eigen_guess, the same operations) */
static double eigen_guess(double nu, long k, double lo, double hi)
{
    double span = hi - lo;
    span = (span >= 0.0 || span != span) ? span : 0.0;          /* np.maximum(span, 0.0) */
    double kk = (double)k;
    double k21 = 2.0 * kk;
    k21 += 1.0;
    double wide = span / k21;
    wide = npclip(wide, 0.0, 1.0);
    wide = wide * wide;
    double c = nu - kk;
    c = cospi01(c);
    c *= 0.5;
    c = 0.5 - c;
    double w = 1.0 - wide;
    w *= c;
    double v = nu * nu;
    kk = kk * kk;
    v -= kk;
    v /= k21;
    v = npclip(v, 0.0, 1.0);
    v *= wide;
    w += v;
    w *= span;
    w += lo;
    return npclip(w, lo, hi);
}

/* the first lam of the band route (_band_nu_guess, the same operations) */
static double nu_guess(double th0, long k, double lo, double hi)
{
    double kf = (double)k;
    double span = hi - lo;
    span = (span >= 1e-300 || span != span) ? span : 1e-300;    /* np.maximum(span, 1e-300) */
    double w = th0 - lo;
    w /= span;
    w = npclip(w, 0.0, 1.0);
    double k21 = 2.0 * kf;
    k21 += 1.0;
    double wide = span / k21;
    wide = npclip(wide, 0.0, 1.0);
    wide = wide * wide;
    double t = 2.0 * w;
    t = 1.0 - t;
    double a = acos_over_pi(t);
    a += kf;
    t = 1.0 - wide;
    t *= a;
    w = w * k21;
    double kf2 = kf * kf;
    kf2 += w;
    a = sqrt(kf2);
    a *= wide;
    t += a;
    return npclip(t, kf + 1e-9, (kf + 1.0) - 1e-9);
}

/* rows of J(nu) - x: pivots u_i of its LDL^T, the count of negative ones and
   sum u_i'/u_i (d/dx); one point (the diagnostic entry point of the tests) */
void pendulab_eigen_rows(double nu, double e2, double x, double n0, long L,
                         double *u_out, double *g_out, long *cnt_out, double *sm_out)
{
    double m = (n0 + 2.0 * 0.0) + nu;
    double u = m * m - x;
    long cnt = u < 0;
    double g = -1.0 / u, sm = g;
    u_out[0] = u; g_out[0] = g;
    for (long i = 1; i < L; i++) {
        double r = e2 / u;
        g *= r;
        g -= 1.0;
        m = (n0 + 2.0 * (double)i) + nu;
        u = m * m - x;
        u -= r;
        cnt += u < 0;
        g /= u;
        sm += g;
        u_out[i] = u; g_out[i] = g;
    }
    *cnt_out = cnt; *sm_out = sm;
}

/* rows of J(lam) - theta0 and d/dlam of the pivots (see pendulab_eigen_rows) */
void pendulab_nu_rows(double lam, double e2, double t0, double n0, long L,
                      double *u_out, double *g_out, long *cnt_out, double *sm_out)
{
    double m = (n0 + 2.0 * 0.0) + lam;
    double u = m * m - t0;
    long cnt = u < 0;
    double g = 2.0 * m / u, sm = g;
    u_out[0] = u; g_out[0] = g;
    for (long i = 1; i < L; i++) {
        double r = e2 / u;
        g *= r;
        m = (n0 + 2.0 * (double)i) + lam;
        g += m;
        g += m;
        u = m * m;
        u -= t0;
        u -= r;
        cnt += u < 0;
        g /= u;
        sm += g;
        u_out[i] = u; g_out[i] = g;
    }
    *cnt_out = cnt; *sm_out = sm;
}

/* Newton steps on det(T - x) for the M columns of the symmetric tridiagonals
   d (n x M, row-major), e2 ((n-1) x M, squared off-diagonals), x (M) in place:
   the operations of _newton_eigen, column by column (a column stops where the
   NumPy loop would only subtract zero steps from it). */
void pendulab_newton_eigen(long n, long M, const double *d, const double *e2, double *x,
                           long iters)
{
    const double U2 = 2.0 * 0x1p-53;
    for (long c = 0; c < M; c++) {
        double xc = x[c];
        for (long it = 0; it < iters; it++) {
            double u = d[c] - xc;
            int hit = u == 0.0;
            double du = -1.0;
            double s = -1.0 / u;
            for (long i = 1; i < n; i++) {
                double r = e2[(i - 1) * M + c] / u;
                du = -1.0 + r * du / u;
                u = d[i * M + c] - xc - r;
                hit |= u == 0.0;
                s = s + du / u;
            }
            double step = 1.0 / s;
            if (!(isfinite(step) && !hit)) step = 0.0;
            xc = xc - step;
            if (!(fabs(step) > U2 * npmax1(fabs(xc)))) break;
        }
        x[c] = xc;
    }
}

/* The Newton loop of pendulab_band_newton for the points ord[0..n) (or 0..n
   when ord is null); q2 null: theta1^2 = absq^2; k null: k = (below_cnt - 1)/2;
   x0 null: the guess of _band_eigen_guess (kind 0) or _band_nu_guess (kind 1);
   the result of point s in out[ostride * (oidx ? oidx[s] : s)]. */
static long band_core(int kind, long n, const long *ord, const double *p, const double *q2,
                      const double *absq, const long *k, const long *below_cnt,
                      const double *lo, const double *hi, const double *x0, double negR, long L,
                      long maxit, double *out, const long *oidx, long ostride)
{
    double P[LANES], E2[LANES], N0[LANES], X[LANES], A[LANES], Bb[LANES], LA[LANES], HA[LANES];
    double u[LANES], g[LANES], sm[LANES], m[LANES], r[LANES];
    long K[LANES], cnt[LANES], idx[LANES], it[LANES];
    long next = 0, active = 0, slow = 0;
    const double Lf = (double)L;
    for (int j = 0; j < LANES; j++) {
        idx[j] = -1;
        P[j] = kind ? 0.0 : 1.0; E2[j] = 1.0; N0[j] = 0.0; X[j] = 0.5; K[j] = 0; it[j] = 0;
        A[j] = 0.0; Bb[j] = 1.0; LA[j] = 0.0; HA[j] = 1.0;
    }
    for (;;) {
        /* fill the free lanes */
        for (int j = 0; j < LANES; j++) {
            if (idx[j] >= 0 || next >= n) continue;
            long s = ord ? ord[next] : next;
            next++;
            idx[j] = s; it[j] = 0; active++;
            P[j] = p[s];
            E2[j] = q2 ? q2[s] : absq[s] * absq[s];
            K[j] = k ? k[s] : (below_cnt[s] - 1) >> 1;
            X[j] = x0 ? x0[s] : kind ? nu_guess(P[j], K[j], lo[s], hi[s])
                                      : eigen_guess(P[j], K[j], lo[s], hi[s]);
            if (kind == 0) {
                N0[j] = 2.0 * floor((negR - P[j]) / 2.0);
                A[j] = lo[s]; Bb[j] = hi[s]; LA[j] = lo[s]; HA[j] = hi[s];
            } else {
                double kf = (double)K[j];
                N0[j] = 2.0 * floor(((negR - kf) - 1.0) / 2.0);
                A[j] = kf; Bb[j] = kf + 1.0; LA[j] = kf; HA[j] = kf + 1.0;
            }
        }
        if (active == 0) break;
        if (kind == 0) {
#pragma omp simd
            for (int j = 0; j < LANES; j++) {
                m[j] = (N0[j] + 2.0 * 0.0) + P[j];
                u[j] = m[j] * m[j] - X[j];
                cnt[j] = u[j] < 0;
                g[j] = -1.0 / u[j];
                sm[j] = g[j];
            }
            for (long i = 1; i < L; i++) {
                const double s2 = 2.0 * (double)i;
#pragma omp simd
                for (int j = 0; j < LANES; j++) {
                    r[j] = E2[j] / u[j];
                    g[j] *= r[j];
                    g[j] -= 1.0;
                    m[j] = (N0[j] + s2) + P[j];
                    u[j] = m[j] * m[j] - X[j];
                    u[j] -= r[j];
                    cnt[j] += u[j] < 0;
                    g[j] /= u[j];
                    sm[j] += g[j];
                }
            }
        } else {
#pragma omp simd
            for (int j = 0; j < LANES; j++) {
                m[j] = (N0[j] + 2.0 * 0.0) + X[j];
                u[j] = m[j] * m[j] - P[j];
                cnt[j] = u[j] < 0;
                g[j] = 2.0 * m[j] / u[j];
                sm[j] = g[j];
            }
            for (long i = 1; i < L; i++) {
                const double s2 = 2.0 * (double)i;
#pragma omp simd
                for (int j = 0; j < LANES; j++) {
                    r[j] = E2[j] / u[j];
                    g[j] *= r[j];
                    m[j] = (N0[j] + s2) + X[j];
                    g[j] += m[j];
                    g[j] += m[j];
                    u[j] = m[j] * m[j];
                    u[j] -= P[j];
                    u[j] -= r[j];
                    cnt[j] += u[j] < 0;
                    g[j] /= u[j];
                    sm[j] += g[j];
                }
            }
        }
        for (int j = 0; j < LANES; j++) {
            if (idx[j] < 0) continue;
            double x = X[j];
            int below = kind == 0 ? cnt[j] <= K[j] : cnt[j] >= K[j] + 1;
            double aa = below ? x : A[j];
            double bb = below ? Bb[j] : x;
            double step = 1.0 / sm[j];
            double xn = x - step;
            double scale = npmax1(fabs(x));
            int small = fabs(step) <= U4 * scale;
            int bad = !(isfinite(xn) && xn > aa && xn < bb) && !small;
            if (bad) xn = 0.5 * (aa + bb);
            double dist = npmin(xn - LA[j], HA[j] - xn);
            int early = !bad && (step * step * Lf <= U025 * scale * dist);
            int done = small || early || (bb - aa <= U4 * scale);
            A[j] = aa; Bb[j] = bb; X[j] = xn;
            it[j]++;
            if (done || it[j] >= maxit) {
                if (!done) slow++;
                out[ostride * (oidx ? oidx[idx[j]] : idx[j])] = xn;
                idx[j] = -1;
                active--;
            }
        }
    }
    return slow;
}

/* kind 0: the k-th eigenvalue x of J(nu) in (lo, hi) (_band_eigen_chunk);
   kind 1: the exponent lam in (k, k+1) with theta0 in band k (_band_nu_chunk).
   p: nu (kind 0) or theta0 (kind 1); x0: the guess; lo, hi: the band edges;
   negR = -R; L rows.  Returns the number of points that used all maxit
   iterations. */
long pendulab_band_newton(int kind, long n, const double *p, const double *q2, const long *k,
                          const double *lo, const double *hi, const double *x0, double negR,
                          long L, long maxit, double *out)
{
    return band_core(kind, n, 0, p, q2, 0, k, 0, lo, hi, x0, negR, L, maxit, out, 0, 1);
}

/* The band count of _bands_fast: for each point, the number of entries of its
   row (row[p]) of E (sorted rows, +inf padded; ne columns) below theta0, and
   the entries just below and above it (-inf / +inf at the ends). */
void pendulab_band_count(long n, const double *th0, const long *row, const double *E, long ne,
                         long *cnt, double *below, double *above)
{
    for (long p = 0; p < n; p++) {
        const double *e = E + row[p] * ne;
        const double x = th0[p];
        long c = 0;
        while (c < ne && e[c] < x) c++;
        cnt[p] = c;
        below[p] = c > 0 ? e[c - 1] : -INFINITY;
        above[p] = c < ne ? e[c] : INFINITY;
    }
}

/* floor(log2 x), at least -4, for x > 0 (exact; _octave) */
static long octave(double x)
{
    int e;
    frexp(x, &e);
    long o = (long)e - 1;
    return o < -4 ? -4 : o;
}

/* The groups of _group_order for the points idx[0..n) (0..n when idx is null):
   group (k, octave of absq) numbered k * noct + octave + 4, k = kc (kind 0) or
   (kc - 1)/2 (kind 1: kc counts the characteristic values below theta0); per
   group (0..G) the largest hi and absq and the number of points. */
void pendulab_band_groups(int kind, long n, const long *idx, const double *absq, const long *kc,
                          const double *hi, long noct, long G, long *gid, double *himax,
                          double *qmax, long *count)
{
    for (long g = 0; g < G; g++) { himax[g] = -INFINITY; qmax[g] = -INFINITY; count[g] = 0; }
    for (long i = 0; i < n; i++) {
        long s = idx ? idx[i] : i;
        long g = (kind ? (kc[s] - 1) >> 1 : kc[s]) * noct + octave(absq[s]) + 4;
        gid[i] = g;
        count[g]++;
        if (hi[s] > himax[g]) himax[g] = hi[s];
        if (absq[s] > qmax[g]) qmax[g] = absq[s];
    }
}

/* The band Newton of every point of a list at once, per group of _group_order:
   kind 1 (the exponent's band route, _band_nu_chunk): the points idx[0..n) of
   the full arrays p = theta0, absq = |theta1|, kc (characteristic values below
   theta0; band k = (kc - 1)/2), lo, hi (the band's edges), lam written to
   out[2 idx] (the real parts of a complex array);
   kind 0 (theta0_of_exponent, _band_eigen_chunk): the points 0..n of p = nu,
   absq, kc = k, lo, hi, the eigenvalue written to out[oidx[i]];
   in the groups gid[0..n) (0..G), with negR[g] = -R and L[g] rows for group g,
   from the guess of _band_nu_guess or _band_eigen_guess.  Returns the number of
   points that used all maxit iterations, or -1 when out of memory. */
long pendulab_band_all(int kind, long n, const long *idx, const long *oidx, const long *gid,
                       long G, const double *p, const double *absq, const long *kc,
                       const double *lo, const double *hi, const double *negR, const long *L,
                       long maxit, double *out)
{
    long *start = calloc((size_t)G + 1, sizeof(long));
    long *ord = malloc((size_t)(n > 0 ? n : 1) * sizeof(long));
    long slow = 0;
    if (!start || !ord) { free(start); free(ord); return -1; }
    for (long i = 0; i < n; i++) start[gid[i] + 1]++;
    for (long g = 0; g < G; g++) start[g + 1] += start[g];
    for (long i = 0; i < n; i++)                                  /* stable counting sort */
        ord[start[gid[i]]++] = idx ? idx[i] : i;
    for (long g = G; g > 0; g--) start[g] = start[g - 1];
    start[0] = 0;
    for (long g = 0; g < G; g++) {
        long m = start[g + 1] - start[g];
        if (m <= 0) continue;
        if (kind)
            slow += band_core(1, m, ord + start[g], p, 0, absq, 0, kc, lo, hi, 0, negR[g],
                              L[g], maxit, out, 0, 2);
        else
            slow += band_core(0, m, ord + start[g], p, 0, absq, kc, 0, lo, hi, 0, negR[g],
                              L[g], maxit, out, oidx, 1);
    }
    free(start); free(ord);
    return slow;
}

/* The continuants of pendulab.analyses.floquet._hill.continuants for the rows
   g(n) = f1 / ((2n + s)^2 - f0) of _trace_half, one point at a time, kept at
   the depths N0, 2 N0, 4 N0, 8 N0 (D: n x 4, row-major): the same operations in
   the same order as the NumPy arrays there. */
void pendulab_trace_continuants(long n, const double *f0, const double *f1, const long *s,
                                long N0, double *D)
{
    for (long p = 0; p < n; p++) {
        const double x0 = f0[p], x1 = f1[p];
        const long sp = s[p];
        double klr = 1.0, kl1r = 1.0, klr1 = 1.0, kl1r1 = 0.0;
        long L = 0, R = 0, next = N0;
        int j = 0;
        double gR = x1 / ((double)(sp * sp) - x0), gL = gR;
        for (long N = 1; N <= 8 * N0; N++) {
            long m = 2 * (R + 1) + sp;
            double gn = x1 / ((double)(m * m) - x0);
            double c = gR * gn;
            R++;
            gR = gn;
            double a = klr - c * klr1, b = kl1r - c * kl1r1;
            klr1 = klr; kl1r1 = kl1r; klr = a; kl1r = b;
            m = 2 * (L - 1) + sp;
            gn = x1 / ((double)(m * m) - x0);
            c = gn * gL;
            L--;
            gL = gn;
            a = klr - c * kl1r; b = klr1 - c * kl1r1;
            kl1r = klr; kl1r1 = klr1; klr = a; klr1 = b;
            if (N == next) { D[4 * p + j] = klr; j++; next *= 2; }
        }
    }
}
"""

_C_STATE = {}


def _c_band():
    """The loaded band kernel (ctypes), or None: no compiler (one notice, the NumPy
    path), or the environment variable PENDULAB_BAND_NUMPY set (the NumPy path)."""
    import os

    if os.environ.get("PENDULAB_BAND_NUMPY"):
        return None
    from pendulab.numerics import ckernel

    if "lib" not in _C_STATE or _C_STATE.get("cc") != tuple(ckernel.compiler_command()):
        lib = ckernel.load_source("floquet band Newton", _BAND_C)
        _C_STATE["lib"] = None if lib is None else _bind(lib)
        _C_STATE["cc"] = tuple(ckernel.compiler_command())
    return _C_STATE["lib"]


def _bind(lib):
    """``lib`` (a ctypes.CDLL of :data:`_BAND_C`) with its argument types set."""
    import ctypes

    D, L, PD = ctypes.c_double, ctypes.c_long, ctypes.POINTER(ctypes.c_double)
    PL = ctypes.POINTER(ctypes.c_long)
    lib.pendulab_band_newton.argtypes = [ctypes.c_int, L, PD, PD, PL, PD, PD, PD, D, L, L, PD]
    lib.pendulab_band_newton.restype = L
    lib.pendulab_newton_eigen.argtypes = [L, L, PD, PD, PD, L]
    lib.pendulab_newton_eigen.restype = None
    lib.pendulab_trace_continuants.argtypes = [L, PD, PD, PL, L, PD]
    lib.pendulab_trace_continuants.restype = None
    lib.pendulab_band_count.argtypes = [L, PD, PL, PD, L, PL, PD, PD]
    lib.pendulab_band_count.restype = None
    lib.pendulab_band_groups.argtypes = [ctypes.c_int, L, PL, PD, PL, PD, L, L, PL, PD, PD, PL]
    lib.pendulab_band_groups.restype = None
    lib.pendulab_band_all.argtypes = [ctypes.c_int, L, PL, PL, PL, L, PD, PD, PL, PD, PD, PD, PL,
                                      L, PD]
    lib.pendulab_band_all.restype = L
    for fn in (lib.pendulab_eigen_rows, lib.pendulab_nu_rows):
        fn.argtypes = [D, D, D, D, L, PD, PD, PL, PD]
        fn.restype = None
    return lib


def _c_newton(lib, kind, p, q2, k, lo, hi, x0, R, L, maxit):
    """:func:`_band_eigen_chunk` (kind 0, p = nu) or :func:`_band_nu_chunk` (kind 1,
    p = theta0) for all points at once in the C kernel (guess x0 from NumPy)."""
    import ctypes

    import numpy as np

    def d(a):
        return np.ascontiguousarray(a, dtype=np.float64)

    p, q2, lo, hi, x0 = d(p), d(q2), d(lo), d(hi), d(x0)
    kk = np.ascontiguousarray(k, dtype=np.int64)
    out = np.empty(p.size)
    PD, PL = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_long)
    lib.pendulab_band_newton(kind, p.size, p.ctypes.data_as(PD), q2.ctypes.data_as(PD),
                             kk.ctypes.data_as(PL), lo.ctypes.data_as(PD),
                             hi.ctypes.data_as(PD), x0.ctypes.data_as(PD), float(-R), L, maxit,
                             out.ctypes.data_as(PD))
    return out


def _theta0_of_exponent_array(nu, theta1):
    """Vectorised theta0_of_exponent in double precision (see its docstring).

    Non-integer nu in band k = floor(nu): theta0 is the k-th eigenvalue (0-based)
    of the symmetric tridiagonal J(nu) with diagonal (2n + nu)^2 and off-diagonal
    theta1, n in Z (000 eqs. 9-10 read as an eigenproblem in theta0; its spectrum
    is lambda_{|nu + 2m|}(q), one value in each band), found between the band
    edges by :func:`_band_eigen`.  Integer nu: a_nu(q), q = -theta1.
    """
    import numpy as np

    n_arr, t_arr = _real_arrays(nu, theta1, ("nu", "theta1"))
    n_arr = np.abs(n_arr)
    shape = n_arr.shape
    fn, f1 = n_arr.ravel(), t_arr.ravel()   # read only
    out = np.empty(fn.shape)
    if fn.size == 0:
        return out.reshape(shape)
    t = np.abs(f1)
    t *= 2.0
    t += fn * fn
    size = float(np.max(t))
    if size > SIZE_LIMIT:
        raise InputError(f"|nu^2| + 2|theta1| = {_size_text(size, SIZE_LIMIT)} is too large for the "
                         f"vectorised functions (limit {SIZE_LIMIT:g})")
    zero_q = f1 == 0
    is_int = fn == np.floor(fn)
    is_int &= ~zero_q
    zi = np.flatnonzero(zero_q)
    if zi.size:
        out[zi] = fn[zi] ** 2
    if np.any(is_int):
        # a_n(q), q = -theta1: with the values at |q| sorted, e_0 < e_1 < ... is
        # a_0 < b_1 < a_1 < b_2 < ... (DLMF 28.2.22); a_{2j}(q) = a_{2j}(|q|) and
        # a_{2j+1}(q) = b_{2j+1}(|q|) for q < 0 (DLMF 28.2.26)
        ii = np.nonzero(is_int)[0]
        n_i = fn[ii].astype(np.int64)
        q_i = -f1[ii]
        idx = np.where(n_i == 0, 0, np.where(q_i > 0, 2 * n_i, np.where(n_i % 2 == 0, 2 * n_i, 2 * n_i - 1)))
        out[ii] = _sorted_edges_at(np.abs(q_i), idx)
    todo = np.nonzero(~zero_q & ~is_int)[0]
    if todo.size:
        absq = np.abs(f1[todo])
        k = np.floor(fn[todo]).astype(np.int64)
        lib = _c_band()
        if lib is not None:
            LO, HI = _band_edges(absq, k)
            _c_band_all(lib, 0, None, fn[todo], absq, k, LO, HI, out, todo)
            return out.reshape(shape)
        # one truncation per band index and octave of |q| (rows grow like sqrt|q|);
        # the points sorted by group once (the band edges do not depend on the order)
        order, cuts = _group_order(k * 4096 + _octave(absq))
        at = todo[order]
        A, K = absq[order], k[order]
        LO, HI = _band_edges(A, K)
        out[at] = _solve_groups(_band_eigen, fn[at], A, K, LO, HI, cuts)
    return out.reshape(shape)


def _sorted_edges_at(absq, idx):
    """The idx-th (0-based) of the sorted characteristic values a_n, b_n at each
    |q| (arrays of one shape): certified values (:func:`_certify_edges`), or
    LAPACK per distinct |q| (:func:`_edges_double`) where that is refused; the
    points in groups of size (:func:`_by_size`)."""
    import numpy as np

    return _by_size((idx // 2 + 1.0) ** 2 + 2.0 * np.abs(absq),
                    lambda a, i: (_sorted_edges_one(a, i),), absq, idx)[0]


def _sorted_edges_one(absq, idx):
    """:func:`_sorted_edges_at` for points of one size group."""
    import numpy as np

    qs, inv = np.unique(absq, return_inverse=True)
    imax = int(idx.max())
    top = (imax // 2 + 1.0) ** 2 + 3.0 * float(qs.max()) + 1.0
    ok = False
    if qs.size > 16:  # batched; a few |q| are quicker one by one
        try:
            E, _ = _certify_edges(qs, top)
            ok = E.shape[1] > imax
        except PrecisionError:
            pass
    if ok:
        vals = E[inv, idx]
        if np.all(np.isfinite(vals)):
            return vals
    vals = np.empty(idx.size)
    for i, q in enumerate(qs):
        sel = np.nonzero(inv == i)[0]
        edges = _edges_double(float(q), (int(idx[sel].max()) // 2 + 1.0) ** 2 + 2.0 * q + 1.0)
        vals[sel] = edges[idx[sel]]
    return vals


def _unique_inverse(a):
    """np.unique(a, return_inverse=True) for a flat float array without nan: the
    distinct values by hashing, sorted, and each point's index by bisection."""
    import numpy as np

    if a.size < 4096:
        return np.unique(a, return_inverse=True)
    a = np.ascontiguousarray(a, dtype=np.float64)
    # NumPy hashes integers but sorts floats: the bit patterns of doubles >= +0
    # are distinct integers in the same order (|theta1| here: no -0.0, no nan)
    key = a.view(np.int64) if float(a.min()) >= 0.0 and not np.signbit(a).any() else a
    try:
        qs = np.sort(np.unique(key, sorted=False)).view(np.float64)
    except TypeError:       # NumPy < 2.3
        return np.unique(a, return_inverse=True)
    return qs, np.searchsorted(qs, a)


def _band_edges(absq, k):
    """Edges (e_{2k}, e_{2k+1}) of stable band k at each |q| (arrays of one shape),
    the points in groups of size (:func:`_by_size`)."""
    import numpy as np

    return _by_size((k + 1.0) ** 2 + 2.0 * np.abs(absq), _band_edges_one, absq, k)


def _band_edges_one(absq, k):
    """:func:`_band_edges` for points of one size group."""
    import numpy as np

    qs, inv = _unique_inverse(absq)
    kq = np.zeros(qs.size, dtype=np.int64)
    np.maximum.at(kq, inv, k)
    # every edge up to e_{2 kq + 1} for each distinct |q|: one table, two look-ups
    width = 2 * int(kq.max()) + 2
    table = _sorted_edges_at(np.repeat(qs, width), np.tile(np.arange(width), qs.size))
    at = inv * width
    at += 2 * k
    lo = table[at]
    at += 1
    return lo, table[at]


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
    For theta0 << 0 the trace is a small difference of terms of size
    cosh(pi sqrt(-theta0)), and next to a band it loses digits to that
    cancellation (theta0 = -126, theta1 = 91: -1.996 where the exact trace is
    -2.005); :func:`exponent` detects it and answers those points otherwise.
    """
    x0, x1 = _check_arrays(theta0, theta1)
    shape = x0.shape
    f0, f1 = x0.ravel().astype(float), x1.ravel().astype(float)
    return (2.0 * _trace_half(f0, f1, _trace_depth(f0, f1))).reshape(shape)


def _trace_depth(f0, f1):
    """The first depth N0 of :func:`trace_monodromy` for flat arrays theta0, theta1."""
    import numpy as np

    return int(2 * math.ceil(math.sqrt(float(np.max(np.abs(f0)) + 2 * np.max(np.abs(f1)))))) + 24


def _trace_half(f0, f1, N0):
    """cos(pi lam) of :func:`trace_monodromy` for flat float arrays at depths
    N0, 2 N0, 4 N0, 8 N0 (each point on its own: the same bits for any batch
    with the same N0)."""
    import numpy as np

    # shift s per point (vectorised form of _hill_shift)
    r = np.sqrt(np.maximum(f0, 0.0))
    s = np.where(f0 <= 0.25, np.where(f0 > -1.0, 1, 0), np.where(np.rint(r) % 2 == 0, 1, 0))
    checkpoints = {N0 * 2 ** j: j for j in range(4)}
    one = np.ones_like(f0)

    def g(n):
        return f1 / ((2 * n + s) ** 2 - f0)

    D = [None] * 4
    lib = _c_band()
    with np.errstate(over="ignore", invalid="ignore"):
        if lib is not None and f0.size:
            D = _c_continuants(lib, f0, f1, s, N0)
        else:
            for N, klr in enumerate(continuants(g, N0 * 8, one, np.zeros_like(f0)), start=1):
                if N in checkpoints:
                    D[checkpoints[N]] = klr
        # remove N^-3, N^-4, N^-5 terms
        T = D
        for p in (3, 4, 5):
            fac = 2.0 ** p
            T = [(fac * T[i + 1] - T[i]) / (fac - 1) for i in range(len(T) - 1)]
        delta = T[0]
        cr = np.where(f0 >= 0, np.cos(np.pi * r), np.cosh(np.pi * np.sqrt(np.maximum(-f0, 0.0))))
        cs = np.where(s == 0, 1.0, -1.0)
        y = cs + delta * (cr - cs)
    return y


# ---------------------------------------------------------------------------
# Certified characteristic values for many |q| at once (the map's boundaries)
# ---------------------------------------------------------------------------

#: unit roundoff of IEEE double precision
_U = 2.0 ** -53


def _c_continuants(lib, f0, f1, s, N0):
    """The four depths of :func:`_trace_half`'s continuants in the C kernel (the same bits)."""
    import ctypes

    import numpy as np

    PD, PL = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_long)
    a = np.ascontiguousarray(f0, dtype=np.float64)
    b = np.ascontiguousarray(f1, dtype=np.float64)
    sc = np.ascontiguousarray(s, dtype=np.int64)
    D = np.empty((a.size, 4))
    lib.pendulab_trace_continuants(a.size, a.ctypes.data_as(PD), b.ctypes.data_as(PD),
                                   sc.ctypes.data_as(PL), int(N0), D.ctypes.data_as(PD))
    return [D[:, j] for j in range(4)]


def _diag_base(family, n):
    """Row j's diagonal (2j)^2, (2j+1)^2 or (2j+2)^2 of a DLMF 28.4 family (exact floats)."""
    import numpy as np

    j = np.arange(n, dtype=float)
    off = {"a_even": 0.0, "a_odd": 1.0, "b_odd": 1.0, "b_even": 2.0}[family]
    return (2.0 * j + off) ** 2


def _family_rows(fams, q, n, side=0):
    """Diagonals (n, M) and squared off-diagonals (n-1, M) of the DLMF 28.4
    matrices (see :func:`_family_diagonals`), one column per (family, q) pair:
    ``fams`` (M,) indexes FAMILIES, ``q`` (M,) the q of each column.

    ``side`` = +1 / -1 rounds the one inexact diagonal entry (1 +- q of the odd
    families) up / down, so that the float matrix is >= / <= the exact one in
    the Loewner order; -1 also lowers the last diagonal entry by |q| (the
    coupling to the neglected tail, see :func:`_certify_edges`)."""
    import numpy as np

    q = np.asarray(q, dtype=float)
    fams = np.asarray(fams)
    off = np.array([0.0, 1.0, 1.0, 2.0])[fams]          # a_even, a_odd, b_odd, b_even
    j = np.arange(n, dtype=float)[:, None]
    d = (2.0 * j + off[None, :]) ** 2
    odd = (fams == 1) | (fams == 2)
    d0 = np.where(fams == 1, 1.0 + q, 1.0 - q)
    if side:
        d0 = np.nextafter(d0, side * np.inf)
    d[0] = np.where(odd, d0, d[0])
    if side < 0:
        d[-1] = np.nextafter(d[-1] - np.abs(q), -np.inf)
    e2 = np.repeat((q * q)[None, :], n - 1, axis=0)
    if n > 1:
        e2[0] = np.where(fams == 0, 2.0 * e2[0], e2[0])
    return d, e2


def _sided(d, fams, q, side):
    """:func:`_family_rows`'s ``side`` variants from its side-0 diagonals ``d``."""
    import numpy as np

    out = d.copy()
    odd = (fams == 1) | (fams == 2)
    if odd.any():
        out[0, odd] = np.nextafter(d[0, odd], side * np.inf)
    if side < 0:
        out[-1] = np.nextafter(d[-1] - np.abs(q), -np.inf)
    return out


def _sturm_count_vec(d, e2, x):
    """Number of eigenvalues < x of each symmetric tridiagonal (columns of d, e2),
    counted in floating point by the LDL^T pivots.

    Kahan's lemma: when d and x are doubles, the floating-point count is the
    exact count of a matrix whose squared off-diagonal entries are perturbed by
    at most ~5 u relative (u the unit roundoff) and whose diagonal is exact, so
    by Weyl's theorem its eigenvalues are within :func:`_count_eta` of the
    float matrix's."""
    import numpy as np

    cnt = np.zeros(np.shape(x), dtype=np.int64)
    p = None
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        for i in range(d.shape[0]):
            p = d[i] - x if i == 0 else d[i] - x - e2[i - 1] / p
            p[p == 0.0] = -1e-290
            cnt += p < 0
    return cnt


def _count_eta(q):
    """Eigenvalue shift bounding the rounding of :func:`_sturm_count_vec`:
    2 max|delta b| <= 2 * 3 u * sqrt(2) |q| (Kahan, Weyl; q^2 rounded too),
    with a factor of two to spare, plus the zero-pivot replacement 1e-290."""
    import numpy as np

    return 16.0 * _U * np.abs(q) + 1e-280


def _newton_eigen(d, e2, x, iters=8):
    """Newton steps x <- x - f/f' on f = det(T - x) for each column (through the
    LDL^T pivots u_i: f'/f = sum u_i'/u_i); a zero pivot means x is an
    eigenvalue of the float matrix and stops that column.  In the C kernel
    (:data:`_BAND_C`, the same operations) when it builds."""
    import numpy as np

    x = np.array(x, dtype=float)
    lib = _c_band()
    if lib is not None and x.ndim == 1 and d.ndim == 2 and d.shape[1] == x.size and x.size:
        import ctypes

        PD = ctypes.POINTER(ctypes.c_double)
        dc = np.ascontiguousarray(d, dtype=np.float64)
        ec = np.ascontiguousarray(e2, dtype=np.float64)
        lib.pendulab_newton_eigen(dc.shape[0], x.size, dc.ctypes.data_as(PD),
                                  ec.ctypes.data_as(PD), x.ctypes.data_as(PD), iters)
        return x
    live = np.ones(x.shape, dtype=bool)
    for _ in range(iters):
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            u = d[0] - x
            hit = u == 0.0
            du = -1.0
            s = -1.0 / u
            for i in range(1, d.shape[0]):
                r = e2[i - 1] / u
                du = -1.0 + r * du / u
                u = d[i] - x - r
                hit |= u == 0.0
                s = s + du / u
            step = 1.0 / s
        step = np.where(np.isfinite(step) & ~hit & live, step, 0.0)
        x = x - step
        live &= np.abs(step) > 2 * _U * np.maximum(1.0, np.abs(x))
        if not live.any():
            break
    return x


def _family_size(qmax, top):
    """Truncation (rows) of the DLMF 28.4 matrices for eigenvalues up to ``top``
    at |q| <= qmax: past the block where |C_m| > 2|q| the tail factors of
    :func:`_tail_steps` bring the neglected part below 1e-18."""
    t = max(float(top), 0.0) + 2.0 * float(qmax)
    m0 = _edge_index(t, qmax)
    return m0 // 2 + _tail_steps(t, qmax, m0, 18) + 3


def _newton_certify(cf, qq, cj, x0, n):
    """Newton from x0 and the certificate of :func:`_certify_edges` for the
    columns (family cf, |q| qq, index cj); returns (x, width), width nan where
    the certificate failed even with a LAPACK value and delta = 1e-9."""
    import numpy as np
    from scipy.linalg import eigvalsh_tridiagonal

    d, e2 = _family_rows(cf, qq, n)
    x = _newton_eigen(d, e2, x0)
    dp, dm = _sided(d, cf, qq, +1), _sided(d, cf, qq, -1)
    eta = _count_eta(qq)
    tail_lo = ((2.0 * n + np.array([0.0, 1.0, 1.0, 2.0])[cf]) ** 2 - 2.0 * qq) * (1.0 - 1e-15)
    width = np.full(x.shape, np.nan)
    for delta_rel in (1e-13, 1e-9):
        todo = np.isnan(width)
        if not todo.any():
            break
        delta = delta_rel * np.maximum(1.0, np.abs(x)) + 4.0 * eta
        ok = ((_sturm_count_vec(dp, e2, x + delta) >= cj + 1)
              & (_sturm_count_vec(dm, e2, x - delta) <= cj)
              & (x + delta + eta < tail_lo))
        width = np.where(todo & ok, delta + 2.0 * eta + 4.0 * _U * np.abs(x), width)
        for b in np.nonzero(np.isnan(width))[0]:
            dd, ee = _family_diagonals(FAMILIES[cf[b]], float(qq[b]), n, 1.0)
            x[b] = eigvalsh_tridiagonal(np.asarray(dd, float), np.sqrt(np.asarray(ee, float)),
                                        select="i", select_range=(cj[b], cj[b]))[0]
    return x, width


def _certify_edges(qs, theta0_max, nodes=40):
    """Certified characteristic values below ``theta0_max`` for each |q| in ``qs``.

    qs: 1-D, sorted, distinct, >= 0.  Returns (edges, width), both of shape
    (len(qs), E): edges sorted per row and +inf padded; every exact
    characteristic value a_n(q), b_n(q) (all n) below theta0_max lies within
    +-width of exactly one finite entry of its row, and there is none other
    below theta0_max.

    Predictor: eigenvalues of the DLMF 28.4.5-28.4.8 matrices at up to
    ``nodes`` values of q (numpy.linalg.eigvalsh on the stacked matrices),
    interpolated in q by a cubic spline; corrector: Newton on the
    determinant; certificate, for the k-th eigenvalue x of a family:
    Sturm count >= k + 1 at x + delta for the n-row truncation with its
    inexact diagonal entry rounded up (>= the exact truncation, whose k-th
    eigenvalue is >= the infinite matrix's by Cauchy interlacing), and
    count <= k at x - delta for the truncation with the tail coupling folded
    into its last diagonal entry (T_inf >= diag(T_n - |q| e_n e_n^T, tail - |q|
    e_1 e_1^T), and the tail has no eigenvalue below d_n - 2|q|, Gershgorin),
    each count exact up to :func:`_count_eta` (Kahan's lemma, Weyl).  A failed
    certificate is retried with a LAPACK eigenvalue and a wider delta (1e-9).
    The count at theta0_max certifies that no further value lies below it."""
    import numpy as np
    from scipy.interpolate import CubicSpline
    from scipy.linalg import eigvalsh_tridiagonal

    qs = np.asarray(qs, dtype=float)
    nq = qs.size
    top = float(theta0_max)
    if nq == 0:
        return np.zeros((0, 0)), np.zeros((0, 0))
    qmax = float(qs.max())
    n = _family_size(qmax, top)
    ni = np.arange(nq) if nq <= nodes else np.unique(np.linspace(0, nq - 1, nodes).round().astype(int))
    qn = qs[ni]
    nf = len(FAMILIES)
    margin = 1.0 + 0.5 * abs(top)
    fn = np.repeat(np.arange(nf), qn.size)
    dn, e2n = _family_rows(fn, np.tile(qn, nf), n)
    if n <= 48:
        # predictor: all four families at the nodes in one stacked eigvalsh
        A = np.zeros((fn.size, n, n))
        i = np.arange(n)
        A[:, i, i] = dn.T
        A[:, i[:-1], i[:-1] + 1] = np.sqrt(e2n.T)
        A[:, i[:-1] + 1, i[:-1]] = np.sqrt(e2n.T)
        node_vals = np.linalg.eigvalsh(A).reshape(nf, qn.size, n)
    else:
        # large matrices: LAPACK by index, as many values as lie below top anywhere
        sq = np.sqrt(e2n)
        cnt = [eigvalsh_tridiagonal(dn[:, c], sq[:, c], select="v",
                                    select_range=(-np.inf, top + margin)).size
               for c in range(fn.size)]
        J = min(max(cnt) + 1, n)
        node_vals = np.full((fn.size, n), np.inf)
        for c in range(fn.size):
            node_vals[c, :J] = eigvalsh_tridiagonal(dn[:, c], sq[:, c], select="i",
                                                    select_range=(0, J - 1))
        node_vals = node_vals.reshape(nf, qn.size, n)
    # Gershgorin: a family with no eigenvalue below top at some q is skipped there
    lo_bound = np.stack([-2.0 * np.sqrt(2.0) * qs] + [np.minimum(1.0 - qs, 9.0 - 2 * qs) - qs] * 2
                        + [4.0 - 2.0 * qs])
    curves = [(f, j) for f in range(nf)
              for j in range(min(int(np.max(np.sum(node_vals[f] <= top + margin, axis=1))), n - 2))]
    if not curves:
        g_all = np.zeros((nq, 0))
    elif qn.size == nq:
        g_all = np.stack([node_vals[f, :, j] for f, j in curves], axis=1)
    else:
        y = np.stack([node_vals[f, :, j] for f, j in curves], axis=1)
        g_all = CubicSpline(qn, y, axis=0)(qs) if qn.size >= 4 else \
            np.stack([np.interp(qs, qn, y[:, c]) for c in range(y.shape[1])], axis=1)
    cols_f, cols_q, cols_j, guesses = [], [], [], []
    for c, (f, j) in enumerate(curves):
        g = g_all[:, c]
        sel = np.nonzero((g <= top + margin) & (lo_bound[f] <= top))[0]
        cols_f.append(np.full(sel.size, f))
        cols_q.append(sel)
        cols_j.append(np.full(sel.size, j))
        guesses.append(g[sel])
    cf = np.concatenate(cols_f) if cols_f else np.zeros(0, int)
    cq = np.concatenate(cols_q) if cols_q else np.zeros(0, int)
    cj = np.concatenate(cols_j) if cols_j else np.zeros(0, int)
    qq = qs[cq]
    x0 = np.concatenate(guesses) if guesses else np.zeros(0)
    x = np.empty(x0.shape)
    width = np.full(x0.shape, np.nan)
    block = max(256, int(4e6 // n))        # (n, block) arrays of at most 32 MB
    for s0 in range(0, x0.size, block):
        sl = slice(s0, s0 + block)
        x[sl], width[sl] = _newton_certify(cf[sl], qq[sl], cj[sl], x0[sl], n)
    # no further eigenvalue below top: count at top (+ eta) <= the number kept
    kept = np.zeros((nf, nq), dtype=np.int64)
    np.add.at(kept, (cf, cq), 1)
    jmax = np.zeros((nf, nq), dtype=np.int64)
    np.maximum.at(jmax, (cf, cq), cj + 1)
    af, aq = np.nonzero(lo_bound <= top + 1.0)
    above = np.ones(af.size, dtype=bool)
    for s0 in range(0, af.size, block):
        sl = slice(s0, s0 + block)
        d1, e21 = _family_rows(af[sl], qs[aq[sl]], n, side=-1)
        above[sl] = (_sturm_count_vec(d1, e21, np.full(d1.shape[1], top)
                                      + 2.0 * _count_eta(qs[aq[sl]])) <= kept[af[sl], aq[sl]])
    above &= top + 1.0 < ((2.0 * n + np.array([0.0, 1.0, 1.0, 2.0])[af]) ** 2 - 2.0 * qs[aq]) * 0.999
    if not (above.all() and np.array_equal(kept, jmax) and not np.isnan(width).any()):
        raise PrecisionError("could not certify the characteristic values of the map "
                             f"(|q| up to {qmax:g}, theta0 up to {top:g}) in double precision")
    keep = x - width <= top
    E = int(np.max(np.bincount(cq[keep], minlength=nq), initial=0))
    edges = np.full((nq, E), np.inf)
    wout = np.zeros((nq, E))
    if E:
        order = np.lexsort((x[keep], cq[keep]))
        rows = cq[keep][order]
        start = np.searchsorted(rows, np.arange(nq))
        pos = np.arange(rows.size) - start[rows]
        edges[rows, pos] = x[keep][order]
        wout[rows, pos] = width[keep][order]
    return edges, wout
