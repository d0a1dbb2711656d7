"""Characteristic values a_m(q), b_m(q) (DLMF 28.2(v)) and the first stable band."""

from __future__ import annotations

import mpmath

from pendulab.errors import ConvergenceError, InputError, PrecisionError
from pendulab.analyses.floquet._bands import _edge_index, _family_diagonals, _tail_steps
from pendulab.analyses.floquet._cf import _illinois
from pendulab.analyses.floquet._inputs import (
    DOUBLE_DPS, GUARD, SIZE_LIMIT, _check_dps, _check_size, _exact, _mp, _size_text,
)


def _family_of(kind, m):
    """(family, index within the family) of a_m or b_m (DLMF 28.4.5-28.4.8)."""
    if kind == "a":
        return ("a_even", m // 2) if m % 2 == 0 else ("a_odd", (m - 1) // 2)
    return ("b_odd", (m - 1) // 2) if m % 2 == 1 else ("b_even", m // 2 - 1)


def _family_size(j, q, digits):
    m0 = _edge_index(0, q)
    return j + 2 + m0 // 2 + _tail_steps(0, q, m0, digits) + _tail_steps(0, q, 2 * j + m0, digits)


def _double_char_value(family, j, qf):
    """Double-precision eigenvalue (and eigenvector peak) of the truncated matrix."""
    import numpy as np
    from scipy.linalg import eigh_tridiagonal

    n = _family_size(j, qf, 18)
    d, e2 = _family_diagonals(family, qf, n, 1.0)
    d = np.array(d, dtype=float)
    e = np.sqrt(np.array(e2, dtype=float))
    if n == 1:
        return float(d[0]), 0
    vals, vecs = eigh_tridiagonal(d, e, select="i", select_range=(j, j))
    return float(vals[0]), int(np.argmax(np.abs(vecs[:, 0])))


def _char_value_mp(family, j, q, w, guess=None):
    """Characteristic value at dps w (inside an active workdps): the root of the
    two-sided continued fraction centred on the dominant Fourier coefficient
    (the recurrences DLMF 28.4.5-28.4.8), bracketed around a double estimate."""
    qf = float(q)
    a0, centre = _double_char_value(family, j, qf)
    n = _family_size(j, qf, w + 5)
    n = max(n, centre + 3)
    d, e2 = _family_diagonals(family, q, n, mpmath.mpf(1))

    def G(a):
        # continued fraction from row 0 up to the centre, and from the
        # truncation depth down to the centre
        low = 0
        for i in range(centre):
            denom = d[i] - a - low
            low = e2[i] / denom
        up = 0
        for i in range(n - 1, centre, -1):
            up = e2[i - 1] / (d[i] - a - up)
        return d[centre] - a - low - up

    scale = max(1.0, abs(a0))
    delta = mpmath.mpf(1e-11 * scale)
    A = mpmath.mpf(a0)
    for _ in range(40):
        lo, hi = A - delta, A + delta
        glo, ghi = G(lo), G(hi)
        if (glo > 0) != (ghi > 0):
            break
        delta *= 8
    else:
        raise ConvergenceError(f"could not bracket the characteristic value ({family}, {j}, q={qf})")
    root, _ = _illinois(G, lo, hi, glo, ghi, mpmath.mpf(10) ** (-w) * scale)
    return root


def _char_value(kind, m, q, dps):
    name = f"mathieu_{kind}"
    if isinstance(m, bool) or not isinstance(m, int):
        raise InputError(f"{name}: order m must be an integer, got {m!r}")
    if kind == "a" and m < 0:
        raise InputError(f"{name}: order m must be >= 0, got {m}")
    if kind == "b" and m < 1:
        raise InputError(f"{name}: order m must be >= 1, got {m}")
    dps = _check_dps(dps)
    Q = _exact(q, "q")
    _check_size(m * m, Q, SIZE_LIMIT, name, names=("m^2", "q"))
    want = DOUBLE_DPS if dps is None else dps
    family, j = _family_of(kind, m)
    if Q == 0:
        val = mpmath.mpf(m * m)
        return float(val) if dps is None else val
    w = want + GUARD
    while True:
        with mpmath.workdps(w):
            v1 = _char_value_mp(family, j, _mp(Q), w)
        with mpmath.workdps(w + 10):
            v2 = _char_value_mp(family, j, _mp(Q), w + 10)
            ok = abs(v1 - v2) <= mpmath.mpf(10) ** (-(want + 2)) * max(1, abs(v2))
        if ok:
            break
        if w > 4 * want + 100:
            raise PrecisionError(f"{name}({m}, {q}) not resolved to {want} digits")
        w = 2 * w
    if dps is None:
        return float(v2)
    with mpmath.workdps(want):
        return +v2


def mathieu_a(m, q, dps=None):
    """Characteristic value a_m(q) of w'' + (a - 2q cos 2z) w = 0 (DLMF 28.2(v)).

    Eigenvalue of the tridiagonal recurrence DLMF 28.4.5 (m even) or 28.4.6
    (m odd), truncated at a depth that grows like sqrt(q) plus what the digits
    need, refined by the continued fraction at the working precision.  Works for
    q < 0 directly (it reproduces a_{2n}(-q) = a_{2n}(q) and
    a_{2n+1}(-q) = b_{2n+1}(q), DLMF 28.2.26-28.2.27) and for |q| up to 1e4
    and beyond.  dps=None returns a float; otherwise an mpf with dps digits.

    >>> round(mathieu_a(0, 1), 10)   # A&S Table 20.1: a_0(1) = -0.4551386041
    -0.4551386041
    """
    return _char_value("a", m, q, dps)


def mathieu_b(m, q, dps=None):
    """Characteristic value b_m(q), m >= 1 (DLMF 28.2(v); recurrences 28.4.7-28.4.8).

    See :func:`mathieu_a`; b_{2n+1}(-q) = a_{2n+1}(q) and b_{2n+2}(-q) = b_{2n+2}(q).
    """
    return _char_value("b", m, q, dps)

def first_band(theta0, dps=None):
    """(lower, upper) |theta1| of the first stable band of 000 eq. 7 at a given theta0 < 1.

    The band is a_0(q) < theta0 < b_1(|q|) with |q| = |theta1| (DLMF 28.2(v);
    a_0 is even in q, b_1(|q|) = a_1(-|q|)): the lower end solves
    a_0(q) = theta0 (0 when theta0 >= 0), the upper one b_1(q) = theta0, each
    by Brent's method on the exact characteristic values.

    >>> lo, up = first_band(-0.01)
    >>> round(lo, 10), round(up, 10)
    (0.1415759161, 0.9164371642)
    >>> round(mathieu_a(0, lo), 12), round(mathieu_b(1, up), 12)   # on the two curves
    (-0.01, -0.01)
    """
    dps = _check_dps(dps)
    X0 = _exact(theta0, "theta0")
    if X0 >= 1:
        raise InputError(f"theta0 = {theta0} >= 1: the first stable band at theta0 >= 1 "
                         "is not the one that starts at theta1 = 0")
    if abs(X0) > SIZE_LIMIT:
        raise InputError(f"|theta0| = {_size_text(X0)} is too large (limit {SIZE_LIMIT:g})")
    return _band_at_two_precisions(lambda ww: _first_band_mp(_mp(X0), ww), dps,
                                   f"first_band({theta0})")


def _band_at_two_precisions(band, dps, what):
    """``band(ww)`` (a pair, computed at working precision ww) resolved to ``dps`` digits.

    Computed at w and w + 10 digits (w = dps + GUARD, doubled until both agree
    to dps + 2 digits); a float pair when ``dps`` is None.
    """
    want = DOUBLE_DPS if dps is None else dps
    w = want + GUARD
    while True:
        res = []
        for ww in (w, w + 10):
            with mpmath.workdps(ww):
                res.append(band(ww))
        with mpmath.workdps(w + 10):
            ok = all(abs(a - b) <= mpmath.mpf(10) ** (-(want + 2)) * max(1, abs(b))
                     for a, b in zip(res[0], res[1]))
        if ok:
            break
        if w > 4 * want + 100:
            raise PrecisionError(f"{what} not resolved to {want} digits")
        w *= 2
    lower, upper = res[1]
    if dps is None:
        return float(lower), float(upper)
    with mpmath.workdps(want):
        return +lower, +upper


def _first_band_mp(th0, w):
    """|q| at the ends of the first band at theta0 = th0 (an mpf, th0 < 1), at dps w."""
    if th0 >= 1:
        raise InputError(f"theta0 = {mpmath.nstr(th0, 8)} >= 1: the first stable band at "
                         "theta0 >= 1 is not the one that starts at theta1 = 0")
    with mpmath.workdps(w):
        out = []
        for family in ("a_even", "b_odd"):
            if family == "a_even" and th0 >= 0:
                out.append(mpmath.mpf(0))
                continue

            def h(q, family=family):
                return _char_value_mp(family, 0, q, w) - th0

            Q = mpmath.mpf(1)
            while h(Q) > 0:
                Q *= 2
            lo = Q / 2 if Q > 1 else mpmath.mpf(0)
            if family == "a_even":
                lo = mpmath.mpf(0)
                hlo = -th0
            else:
                hlo = h(lo) if lo > 0 else 1 - th0
            root, _ = _illinois(h, lo, Q, hlo, h(Q), mpmath.mpf(10) ** (-w) * Q)
            out.append(root)
        return tuple(out)
