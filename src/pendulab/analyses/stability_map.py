"""The inverted pendulum's exact stability limits and its stable/unstable map.

Both read theta0 and theta1 from the canonical stage through a
:class:`pendulab.analyses.stability.ParameterMap` (for the source's drive
a cos(omega t): theta0 = -4 (omega0/omega)^2, 000 eq. 5, and
theta1 = 2 (a/l)/(I/(m l^2)), 000 eq. 6, derived, not typed in here) and the
Mathieu-plane answers from :mod:`pendulab.analyses.floquet`: the first stable
band for the limits, certified characteristic values (and exact decisions
next to them) for the map.
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath

from pendulab.analyses.floquet._charvalues import (
    _band_at_two_precisions, _band_certified, _first_band_mp, _proved_or_none, _value_method,
)
from pendulab.analyses.floquet._inputs import SIZE_LIMIT, _check_dps, _exact, _mp
from pendulab.errors import InputError

__all__ = ["stability_limits", "map_limits", "stability_map", "map_stability"]


def stability_limits(ratio, inertia_ratio=1, dps=None, method=None):
    """Exact limits (lower, upper) of a/l for the inverted pendulum to be stable.

    ratio = omega0/omega >= 0, inertia_ratio = I/(m l^2) > 0 (point mass 1,
    uniform rod pivoted at an end 4/3), for the source's drive a cos(omega t).
    theta0 and theta1 come from the derivation
    (:func:`pendulab.analyses.stability.body_map`: theta0 = -4 ratio^2, 000
    eq. 5, and theta1 = 2 (a/l)/inertia_ratio, 000 eq. 6); the first stable
    band of the Mathieu plane at that theta0 is :func:`first_band` (theta1
    from a_0(q) = theta0 to b_1(|q|) = theta0), divided by theta1/(a/l).
    Only this first band is reported; for large ratio further, exponentially
    thin bands exist at much larger a/l.  ``method`` as for :func:`map_limits`.

    >>> lo, up = stability_limits(0, 1)
    >>> lo, round(up, 6)
    (0.0, 0.454...)
    """
    from pendulab.analyses.stability import body_map

    R, IR = _exact(ratio, "ratio"), _exact(inertia_ratio, "inertia_ratio")
    if R < 0:
        raise InputError(f"ratio = omega0/omega must be >= 0, got {ratio}")
    if IR <= 0:
        raise InputError(f"inertia_ratio = I/(m l^2) must be > 0, got {inertia_ratio}")
    if 4 * R * R > SIZE_LIMIT:
        raise InputError(f"ratio = omega0/omega must be <= {math.sqrt(SIZE_LIMIT / 4):g} "
                         f"(|theta0| = 4 ratio^2 <= {SIZE_LIMIT:g}), got {ratio}")
    return map_limits(body_map(), {"w0_over_w": R, "inertia_ratio": IR}, dps,
                      what=f"stability_limits({ratio})", method=method)


def map_limits(pmap, point, dps=None, what="the limits", method=None):
    """(lower, upper) of a/l in the first stable band for a ParameterMap at ``point``.

    ``pmap`` is a :class:`pendulab.analyses.stability.ParameterMap` of a
    Mathieu drive whose theta1 is proportional to a/l; ``point`` gives the
    other groups ({"w0_over_w": ..., "inertia_ratio": ...}; exact values such
    as Fraction or decimal text are rounded afresh at each working precision).

    method None (default): "arb" when theta0 and the scale (a/l)/theta1 of the
    map are rational at the point (the source's drive with rational ratio and
    I/(m l^2); a float is its exact binary value): both are evaluated exactly
    from the derivation (SymPy, exact rationals) and the band by the
    ball-arithmetic route of :func:`first_band`, every digit proved; in double
    precision (dps None) each end is then the double nearest to every number of
    a ball proved to contain the exact end, i.e. its correctly rounded value.
    Otherwise, or where the balls cannot be made narrow enough, "mpmath":
    theta0 and the scale with the map's mpmath function at the working
    precision, the band by the mpmath route.  Returns a Limits pair whose
    ``certified_digits`` says how many digits are proved (None: mpmath, and
    double precision).
    """
    dps = _check_dps(dps)
    asked, method = method, _value_method(method, dps, "map_limits")
    if asked is None:
        method = "arb"
    exact = {k: (v if isinstance(v, (Fraction, mpmath.mpf)) else _exact(v, k))
             for k, v in point.items()}
    if method == "arb":
        rational = _exact_groups(pmap, exact)
        if rational is not None:
            th0, scale = rational
            if th0 >= 1:
                raise InputError(f"theta0 = {float(th0):.8g} >= 1: the first stable band at "
                                 "theta0 >= 1 is not the one that starts at theta1 = 0")
            band = _proved_or_none(asked, lambda: _band_certified(th0, dps, what,
                                                                  scale=abs(scale)))
            if band is not None:
                return band.of("a/l")

    def band(ww):
        args = {k: _mp(v) for k, v in exact.items()}
        th0 = pmap.evaluate("theta0", args, "mpmath")
        scale = abs(pmap.evaluate("scale", args, "mpmath"))
        lo, up = _first_band_mp(th0, ww)
        return lo * scale, up * scale
    return _band_at_two_precisions(band, dps, what).of("a/l")


def _exact_groups(pmap, exact):
    """(theta0, scale) as Fractions from the derivation at exact ``point`` values, or
    None when they are not rational there (then the mpmath route is used)."""
    import sympy as sp

    def rat(v):
        if isinstance(v, Fraction):
            return sp.Rational(v.numerator, v.denominator)
        sign, man, exp, _ = v._mpf_
        r = sp.Integer(int(man)) * sp.Integer(2) ** int(exp)
        return -r if sign else r
    names = {s.name: s for s in pmap.symbols}
    if set(exact) - set(names) or pmap.scale is None:
        return None
    sub = {names[k]: rat(v) for k, v in exact.items()}
    out = []
    for which in ("theta0", "scale"):
        key = (which, "nsimplify")   # the map's cache of its forms, once per map
        if key not in pmap._fns:
            pmap._fns[key] = sp.nsimplify(getattr(pmap, which))
        expr = pmap._fns[key]
        val = expr.xreplace(sub) if expr.free_symbols - set(sub) == set() else None
        if val is None or not val.is_Rational:
            return None
        out.append(Fraction(int(val.p), int(val.q)))
    return tuple(out)



def stability_map(al_values, ratio_values, inertia_ratio=1.0):
    """Stable/unstable map of the inverted pendulum on a grid.

    Returns a bool array of shape (len(ratio_values), len(al_values)):
    entry [i, j] is True when a/l = al_values[j] stabilises the inverted
    position at omega0/omega = ratio_values[i] (theta0 = -4 ratio^2,
    theta1 = 2 (a/l)/inertia_ratio; 000 eqs. 5-6), equal to the pointwise
    exact verdict of :func:`characteristic_exponent` at those values, for
    every stable band in the grid's range (see :func:`map_stability`).
    """
    import numpy as np

    from pendulab.analyses.stability import body_map

    if not (isinstance(inertia_ratio, (int, float)) and inertia_ratio > 0):
        raise InputError(f"inertia_ratio must be a positive number, got {inertia_ratio!r}")
    al = np.asarray(al_values, dtype=float)
    ra = np.asarray(ratio_values, dtype=float)
    if al.ndim != 1 or ra.ndim != 1:
        raise InputError("al_values and ratio_values must be one-dimensional")
    return map_stability(body_map(), al, ra, inertia_ratio=float(inertia_ratio))


def map_stability(pmap, al_values, ratio_values, **groups):
    """Stable/unstable map [ratio, a/l] of a Mathieu drive's ParameterMap.

    Returns a bool array of shape (len(ratio_values), len(al_values)) equal to
    the pointwise exact verdicts (:func:`characteristic_exponent` at the exact
    values of the grid's doubles).  theta0 and theta1 come from the map's NumPy
    function (the other groups, e.g. inertia_ratio, fixed by ``groups``).

    When theta0 does not involve a/l and theta1 does not involve omega0/omega
    (read from the map's expressions; the source's drive is such a map) theta0
    is evaluated once per row and theta1 once per column; otherwise at every
    point.  Then the characteristic values a_n(|q|), b_n(|q|) below the largest
    theta0 are computed once per distinct |theta1| with a rigorous error bound
    (``floquet._vectorised._certify_edges``), every cell is classified by
    comparing its theta0 with them (stable: an odd number lie below), and the
    few cells within the bound of a value (widened by the rounding of the
    map's evaluation, 32 ulps of theta0 and 80 of theta1) are decided one by
    one by characteristic_exponent on the exact values of the map's
    expressions.  ``map_stability.last_exact`` holds how many cells needed that.
    """
    import numpy as np

    from pendulab import symbols as S

    al = np.asarray(al_values, dtype=float).reshape(-1)
    ra = np.asarray(ratio_values, dtype=float).reshape(-1)
    shape = (ra.size, al.size)
    if 0 in shape:
        map_stability.last_exact = 0
        return np.zeros(shape, dtype=bool)
    if not (np.all(np.isfinite(al)) and np.all(np.isfinite(ra))):
        raise InputError("al_values and ratio_values must be finite (no nan or inf)")
    if getattr(pmap, "kind", "mathieu") != "mathieu":  # the map's own one-line refusal
        pmap.evaluate("theta0", dict(groups, a_over_l=al, w0_over_w=ra))
    separable = not pmap.theta0.has(S.a_over_l) and not pmap.theta1.has(S.w0_over_w)
    with np.errstate(over="ignore", invalid="ignore"):  # overflow: refused just below
        if separable:
            th0 = np.broadcast_to(np.asarray(pmap.evaluate("theta0", dict(groups, w0_over_w=ra)),
                                             dtype=float), ra.shape)[:, None]
            th1 = np.broadcast_to(np.asarray(pmap.evaluate("theta1", dict(groups, a_over_l=al,
                                                                          w0_over_w=0.0)),
                                             dtype=float), al.shape)[None, :]
        else:
            point = dict(groups, a_over_l=al[None, :], w0_over_w=ra[:, None])
            th0 = np.broadcast_to(np.asarray(pmap.evaluate("theta0", point), dtype=float), shape)
            th1 = np.broadcast_to(np.asarray(pmap.evaluate("theta1", point), dtype=float), shape)
    if not (np.all(np.isfinite(th0)) and np.all(np.isfinite(th1))):
        raise InputError("theta0 or theta1 of the map is not finite on the grid")
    size = float(np.max(np.abs(th0))) + 2.0 * float(np.max(np.abs(th1)))
    if size > SIZE_LIMIT:
        raise InputError(f"|theta0| + 2|theta1| = {size:.3g} on the grid is too large "
                         f"(limit {SIZE_LIMIT:g})")
    out, cells = _classify(th0, th1, shape)
    for i, j in cells:
        out[i, j] = _exact_verdict(pmap, groups, float(al[j]), float(ra[i]))
    map_stability.last_exact = len(cells)
    return out


map_stability.last_exact = 0

#: unit roundoff of double precision
_U = 2.0 ** -53


def _classify(th0, th1, shape):
    """The map from certified characteristic values: (verdicts, undecided cells).

    th0 broadcasts to ``shape`` as (rows, 1) or (rows, cols), th1 as (1, cols)
    or (rows, cols).  Returns the bool array and the list of (i, j) whose theta0
    lies within the error bound of a characteristic value."""
    import numpy as np

    from pendulab.analyses.floquet._vectorised import _certify_edges

    rows, cols = shape
    absq = np.abs(th1).ravel()
    qs, inv = np.unique(absq, return_inverse=True)
    top = float(np.max(th0))
    # far enough for every value that the widening below can reach from a cell: a value e
    # is kept when e - width <= top, and a cell at theta0 <= top is near it up to
    # width + 32 u (|e| + 2.5 |q|), with |e| < |top| + 1
    top += 64.0 * _U * abs(top) + 32.0 * _U * (1.0 + 2.5 * float(np.max(absq))) + 1e-300
    chunk = 20000
    parts = [_certify_edges(qs[k:k + chunk], top) for k in range(0, qs.size, chunk)]
    ne = max(p[0].shape[1] for p in parts)
    edges = np.full((qs.size, ne), np.inf)
    width = np.zeros((qs.size, ne))
    for k, (e, w) in zip(range(0, qs.size, chunk), parts):
        edges[k:k + e.shape[0], :e.shape[1]] = e
        width[k:k + e.shape[0], :e.shape[1]] = w
    # widen by the rounding of theta0 (the cell's, ~ the edge near it) and of
    # theta1 (|d edge/dq| <= 2.5: the q-derivative is a Rayleigh quotient of the
    # matrix with entries 1, sqrt 2 that depend on q)
    with np.errstate(invalid="ignore"):
        width = width + 32.0 * _U * (np.where(np.isfinite(edges), np.abs(edges), 0.0)
                                     + 2.5 * qs[:, None]) + 1e-300
    if th1.shape[0] == 1 and th0.shape[1] == 1:  # separable: per-column edges
        t0 = th0[:, 0]
        order = np.argsort(t0, kind="stable")
        s = t0[order]
        E = edges[inv]                                # (cols, ne)
        # in ascending theta0 the count of values below it steps up at P
        P = np.searchsorted(s, E.ravel(), side="right").reshape(E.shape)
        bounds = np.concatenate([np.zeros((cols, 1), dtype=P.dtype), P,
                                 np.full((cols, 1), rows, dtype=P.dtype)], axis=1)
        counts = np.diff(bounds, axis=1).ravel()
        parity = np.tile(np.arange(ne + 1) % 2 == 1, cols)
        by_col = np.repeat(parity, counts).reshape(cols, rows)   # [j, sorted row]
        if np.array_equal(order, np.arange(rows)):
            out = by_col.T
        elif np.array_equal(order, np.arange(rows)[::-1]):
            out = by_col.T[::-1]
        else:
            out = np.empty(shape, dtype=bool)
            out[order] = by_col.T
        Wc = width[inv]
        first = np.searchsorted(s, (E - Wc).ravel(), side="left")
        last = np.searchsorted(s, (E + Wc).ravel(), side="right")
        cells = set()
        for k in np.nonzero(last > first)[0]:
            cells.update((int(order[r]), int(k // ne)) for r in range(first[k], last[k]))
        return out, sorted(cells)
    # general: every cell with its own |q|
    t0 = np.broadcast_to(th0, shape).ravel()
    qi = np.broadcast_to(inv.reshape(th1.shape), shape).ravel()
    flat = np.zeros(t0.size, dtype=bool)
    near = np.zeros(t0.size, dtype=bool)
    for b in range(ne):
        e = edges[qi, b]
        w = width[qi, b]
        flat ^= t0 > e
        near |= np.abs(t0 - e) <= w
    idx = np.nonzero(near)[0]
    return flat.reshape(shape), [(int(k // cols), int(k % cols)) for k in idx]


def _exact_verdict(pmap, groups, al, ra):
    """characteristic_exponent's verdict at the exact values of the map's
    expressions for the doubles al, ra and ``groups`` (rational when the
    expressions are; otherwise evaluated to 60 digits)."""
    import sympy as sp

    from pendulab.analyses.floquet._exponent import characteristic_exponent

    point = dict(groups, a_over_l=al, w0_over_w=ra)
    sub = {}
    for s in pmap.symbols:
        if s.name in point:
            f = Fraction(float(point[s.name]))
            sub[s] = sp.Rational(f.numerator, f.denominator)
    vals = []
    for expr in (pmap.theta0, pmap.theta1):
        v = sp.sympify(expr).subs(sub)
        if v.is_Float:
            v = sp.Rational(v)
        if v.is_Rational:
            vals.append(Fraction(int(v.p), int(v.q)))
        else:
            vals.append(str(sp.N(v, 60)))
    return bool(characteristic_exponent(vals[0], vals[1]).stable)
