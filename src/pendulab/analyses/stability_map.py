"""The inverted pendulum's exact stability limits and its stable/unstable map.

Both read theta0 and theta1 from the canonical stage through a
:class:`pendulab.analyses.stability.ParameterMap` (for the source's drive
a cos(omega t): theta0 = -4 (omega0/omega)^2, 000 eq. 5, and
theta1 = 2 (a/l)/(I/(m l^2)), 000 eq. 6, derived, not typed in here) and the
Mathieu-plane answers from :mod:`pendulab.analyses.floquet`: the first stable
band for the limits, the vectorised verdict for the map.
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath

from pendulab.analyses.floquet._charvalues import (
    _band_at_two_precisions, _band_certified, _first_band_mp, _value_method,
)
from pendulab.analyses.floquet._inputs import SIZE_LIMIT, _check_dps, _exact, _mp
from pendulab.analyses.floquet._vectorised import is_stable
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

    method None (default): "arb" when dps is given and theta0 and the scale
    (a/l)/theta1 of the map are rational at the point (the source's drive with
    rational ratio and I/(m l^2)): both are evaluated exactly from the
    derivation (SymPy, exact rationals) and the band by the ball-arithmetic
    route of :func:`first_band`, every digit proved; otherwise "mpmath":
    theta0 and the scale with the map's mpmath function at the working
    precision, the band by the mpmath route.  Returns a Limits pair whose
    ``certified_digits`` says how many digits are proved (None: mpmath).
    """
    dps = _check_dps(dps)
    method = _value_method(method, dps, "map_limits")
    exact = {k: (v if isinstance(v, (Fraction, mpmath.mpf)) else _exact(v, k))
             for k, v in point.items()}
    if method == "arb":
        rational = _exact_groups(pmap, exact)
        if rational is not None:
            th0, scale = rational
            if th0 >= 1:
                raise InputError(f"theta0 = {float(th0):.8g} >= 1: the first stable band at "
                                 "theta0 >= 1 is not the one that starts at theta1 = 0")
            return _band_certified(th0, dps, what, scale=abs(scale))

    def band(ww):
        args = {k: _mp(v) for k, v in exact.items()}
        th0 = pmap.evaluate("theta0", args, "mpmath")
        scale = abs(pmap.evaluate("scale", args, "mpmath"))
        lo, up = _first_band_mp(th0, ww)
        return lo * scale, up * scale
    return _band_at_two_precisions(band, dps, what)


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
    for expr in (pmap.theta0, pmap.scale):
        val = sp.nsimplify(expr).subs(sub) if expr.free_symbols - set(sub) == set() else None
        if val is None or not val.is_Rational:
            return None
        out.append(Fraction(int(val.p), int(val.q)))
    return tuple(out)



def stability_map(al_values, ratio_values, inertia_ratio=1.0):
    """Stable/unstable map of the inverted pendulum on a grid.

    Returns a bool array of shape (len(ratio_values), len(al_values)):
    entry [i, j] is True when a/l = al_values[j] stabilises the inverted
    position at omega0/omega = ratio_values[i] (theta0 = -4 ratio^2,
    theta1 = 2 (a/l)/inertia_ratio; 000 eqs. 5-6).
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
    """Stable/unstable map [ratio, a/l] of a Mathieu drive's ParameterMap (vectorised).

    theta0, theta1 from the map's NumPy function at every grid point (the other
    groups, e.g. inertia_ratio, fixed by ``groups``), then :func:`is_stable`.
    """
    import numpy as np

    al = np.asarray(al_values, dtype=float)[None, :]
    ra = np.asarray(ratio_values, dtype=float)[:, None]
    point = dict(groups, a_over_l=al, w0_over_w=ra)
    th0 = np.broadcast_to(pmap.evaluate("theta0", point), (ra.shape[0], al.shape[1]))
    th1 = np.broadcast_to(pmap.evaluate("theta1", point), (ra.shape[0], al.shape[1]))
    return is_stable(th0, th1)
