"""The Bessel identities of 002, checked numerically at any precision by two engines.

For n = 0..N and every z of a grid (log-spaced from 1e-30 to 1e6, plus the
doubles nearest to the first zeros of J_0, J_1, J_2, where the terms cancel):

* cross product (002 "Afirmação" for n = 1, "Obs. 2"; DLMF 10.5.3 rearranged):
  J_n(z) Y_n+1(z) - J_n+1(z) Y_n(z) = -2/(pi z); error relative to 2/(pi z);
* derivative rules (002 "Obs. 1"; DLMF 10.6.6):
  d/dz[z^-n C_n(z)] = -z^-n C_n+1(z) for C = J and C = Y; error relative to
  z^-n (|C_n'| + (n/z) |C_n| + |C_n+1|), the size of the terms that cancel;
* Wronskian constant (002 "Demonstração"): z W(z) = z (J_n Y_n' - J_n' Y_n)
  = D = 2/pi at every z, in particular as z -> 0 (the grid starts at 1e-30).

The two engines are independent:

* ``arb`` (python-flint): J and Y as balls whose radii bound the error; the
  derivatives J_n', Y_n' by a central difference with step
  h = min(z, 1) 2^-b (b the working bits), at the precision that keeps the
  quotient's ball 2^-b narrow; its truncation error, about h^2 |f'''|/6,
  is far below 10^-dps (an estimate, not a ball bound: arb's
  enclosures of Y on complex discs are too wide to bound it usefully);
* ``mpmath``: besselj/bessely at dps + 10 digits, derivatives by mpmath's own
  hypergeometric formula (``derivative=1``), not by the rule being checked.

The engines must agree: every value mpmath gives must lie within the arb ball
widened by 10^-(dps+5) relative, else :class:`EngineDisagreement` is raised.
The result reports the worst relative error over everything checked, the z
and the identity where it occurs, and that error in units of 10^-dps.
"""

import math
from dataclasses import dataclass, field

from flint import arb

from pendulab.analyses.bessel_zeros import _Prec, bessel_zeros, bits_for, check_dps
from pendulab.errors import InputError, PendulabError

MAX_NMAX = 100
MAX_POINTS = 10_000
RULES = ("cross", "derivative_J", "derivative_Y", "wronskian")
ENGINES = ("arb", "mpmath")


class EngineDisagreement(PendulabError):
    """mpmath and arb give values that cannot both be right (a bug in one of them)."""


def default_grid(count=200, lo_exp=-30, hi_exp=6, near_zeros=True):
    """``count`` log-spaced points in [10^lo_exp, 10^hi_exp] as doubles, plus (optionally)
    the doubles nearest to j_n,k for n = 0, 1, 2 and k = 1, 2, 3 (certified zeros).

    Doubles are exact binary numbers, so both engines evaluate at the same z.
    """
    if isinstance(count, bool) or not isinstance(count, int) or not 2 <= count <= MAX_POINTS:
        raise InputError(f"points must be an integer from 2 to {MAX_POINTS}, got {count!r}")
    pts = [10.0 ** (lo_exp + (hi_exp - lo_exp) * i / (count - 1)) for i in range(count)]
    if near_zeros:
        for n in (0, 1, 2):
            for s in bessel_zeros(n, 3, 20).strings:
                pts.append(float(s))
    return sorted(set(pts))


def check_z(z):
    """z must be a positive finite number (the identities are undefined at z <= 0)."""
    if isinstance(z, bool) or not isinstance(z, (int, float)) or not math.isfinite(z) or z <= 0:
        raise InputError(f"z must be a positive number (the identities hold for z > 0), got {z!r}")
    return float(z)


@dataclass
class IdentityReport:
    """Worst relative errors, by identity and engine.

    ``worst`` is (error as mpmath mpf, z, identity, n, engine); ``by_rule``
    maps (engine, identity) -> (error, z, n); ``ratio`` = worst error / 10^-dps.
    ``arb_certified`` is True when every arb ball of the cross product and of
    z W contains the exact value (-2/(pi z), resp. 2/pi).
    """

    nmax: int
    dps: int
    points: list
    engines: tuple
    by_rule: dict = field(default_factory=dict)
    worst: tuple = None
    ratio: object = None
    arb_certified: bool = True
    agreements: int = 0
    limit_D: dict = field(default_factory=dict)


def _note(rep, engine, rule, err, z, n):
    key = (engine, rule)
    if key not in rep.by_rule or err > rep.by_rule[key][0]:
        rep.by_rule[key] = (err, z, n)
    if rep.worst is None or err > rep.worst[0]:
        rep.worst = (err, z, rule, n, engine)


def _to_mpf(x):
    """The midpoint (or any exact arb) as an mpmath number, exactly (mpmath.mpf keeps all bits)."""
    import mpmath
    man, exp = x.mid().man_exp()
    return mpmath.mpf((int(man), int(exp)))


def _accurate(compute, bits, start):
    """compute() at precisions from ``start`` up until its ball is relatively 2^-bits narrow."""
    w = start
    for _ in range(10):
        with _Prec(w):
            v = compute()
            if v.is_finite() and not v.contains(0) and v.rad() <= abs(v).abs_lower() * arb(2) ** (-bits):
                return v
            if v.is_finite() and not v.contains(0):
                lost = float((v.rad() / abs(v).abs_lower()).log() / arb(2).log()) + bits
                w += max(int(lost) + 8, 16)
            else:
                w *= 2
    return v


def _arb_values(n_top, z, bits, derivatives=True):
    """J_n, Y_n (n = 0..n_top) at z and J_n', Y_n' (n = 0..n_top-1) by central differences.

    Each ball is made relatively 2^-bits narrow by raising the precision where
    arb loses bits (the differences f(z+h) - f(z-h) lose about log2(f/(h f')) bits).
    """
    zb = arb(z)
    J = [_accurate(lambda n=n: zb.bessel_j(n), bits, bits) for n in range(n_top + 1)]
    Y = [_accurate(lambda n=n: zb.bessel_y(n), bits, bits) for n in range(n_top + 1)]
    if not derivatives:
        return J, Y, [], []
    hb = bits
    h = arb(min(z, 1.0)) * arb(2) ** (-hb)  # exact: a power of two times a double

    def diff(kind, n):
        def go():
            xp, xm = zb + h, zb - h
            if kind == "J":
                return (xp.bessel_j(n) - xm.bessel_j(n)) / (2 * h)
            return (xp.bessel_y(n) - xm.bessel_y(n)) / (2 * h)
        return _accurate(go, bits, bits + hb + 16)
    dJ = [diff("J", n) for n in range(n_top)]
    dY = [diff("Y", n) for n in range(n_top)]
    return J, Y, dJ, dY


def _mp_values(n_top, z, dps, derivatives=True):
    import mpmath
    with mpmath.workdps(dps + 10):
        x = mpmath.mpf(z)
        J = [mpmath.besselj(n, x) for n in range(n_top + 1)]
        Y = [mpmath.bessely(n, x) for n in range(n_top + 1)]
        if not derivatives:
            return J, Y, [], []
        dJ = [mpmath.besselj(n, x, derivative=1) for n in range(n_top)]
        dY = [mpmath.bessely(n, x, derivative=1) for n in range(n_top)]
    return J, Y, dJ, dY


def _errors(J, Y, dJ, dY, n, z, two_over_pi, absf):
    """Relative errors of the four identities at order n (generic in the number type);
    only the cross product when no derivatives are given."""
    ref = two_over_pi / z
    cross = J[n] * Y[n + 1] - J[n + 1] * Y[n]
    e_cross = absf(cross + ref) / ref
    errs = {"cross": e_cross}
    if not dJ:
        return errs, cross, None
    zn = z ** (-n)
    for name, C, dC in (("derivative_J", J, dJ), ("derivative_Y", Y, dY)):
        lhs = zn * (dC[n] - n / z * C[n])  # d/dz[z^-n C_n] by the product rule
        rhs = -zn * C[n + 1]
        scale = zn * (absf(dC[n]) + n / z * absf(C[n]) + absf(C[n + 1]))
        errs[name] = absf(lhs - rhs) / scale
    zw = z * (J[n] * dY[n] - dJ[n] * Y[n])
    errs["wronskian"] = absf(zw - two_over_pi) / two_over_pi
    return errs, cross, zw


def check_identities(nmax, dps, points=None, engines=ENGINES, rules=RULES):
    """Check the identities of the module docstring for n = 0..nmax at ``dps`` digits.

    ``points``: the z values (positive numbers; default :func:`default_grid`).
    ``engines``: a subset of ("arb", "mpmath").  ``rules``: all of RULES, or
    ("cross",) alone, which needs no derivatives (about 3x faster).
    Returns :class:`IdentityReport`.
    """
    import mpmath
    if isinstance(nmax, bool) or not isinstance(nmax, int) or not 0 <= nmax <= MAX_NMAX:
        raise InputError(f"nmax must be an integer from 0 to {MAX_NMAX}, got {nmax!r}")
    check_dps(dps)
    engines = tuple(engines)
    if not engines or any(e not in ENGINES for e in engines):
        raise InputError(f"engines must be a non-empty subset of {ENGINES}, got {engines!r}")
    rules = tuple(rules)
    if rules not in (RULES, ("cross",)):
        raise InputError(f"rules must be all of {RULES} or ('cross',), got {rules!r}")
    deriv = rules == RULES
    pts = default_grid() if points is None else [check_z(z) for z in points]
    if not pts:
        raise InputError("points must not be empty")
    bits = bits_for(dps)
    rep = IdentityReport(nmax, dps, pts, engines)
    with mpmath.workdps(dps + 10):
        two_pi_mp = 2 / mpmath.pi
    with _Prec(bits):
        two_pi_arb = 2 / arb.pi()
    tol = mpmath.mpf(10) ** (-(dps + 5))
    for z in pts:
        vals = {}
        if "arb" in engines:
            vals["arb"] = _arb_values(nmax + 1, z, bits, deriv)
            with _Prec(bits), mpmath.workdps(dps + 10):
                for n in range(nmax + 1):
                    errs, cross, zw = _errors(*vals["arb"], n, arb(z), two_pi_arb, abs)
                    if not (cross + two_pi_arb / arb(z)).contains(0):
                        rep.arb_certified = False
                    for rule, e in errs.items():
                        _note(rep, "arb", rule, _to_mpf(e.mid()) + _to_mpf(e.rad()), z, n)
                    if z == pts[0] and deriv:
                        rep.limit_D["arb"] = _to_mpf(zw.mid())
        if "mpmath" in engines:
            vals["mpmath"] = _mp_values(nmax + 1, z, dps, deriv)
            with mpmath.workdps(dps + 10):
                x = mpmath.mpf(z)
                for n in range(nmax + 1):
                    errs, _, zw = _errors(*vals["mpmath"], n, x, two_pi_mp, abs)
                    for rule, e in errs.items():
                        _note(rep, "mpmath", rule, e, z, n)
                    if z == pts[0] and deriv:
                        rep.limit_D["mpmath"] = zw
        if len(vals) == 2:
            with mpmath.workdps(dps + 10):
                _compare(vals["arb"], vals["mpmath"], z, tol, rep)
    with mpmath.workdps(dps + 10):
        rep.ratio = rep.worst[0] / mpmath.mpf(10) ** (-dps)
    return rep


def _compare(av, mv, z, tol, rep):
    """Every mpmath value inside the arb ball widened by tol relative (else EngineDisagreement)."""
    import mpmath
    names = ("J", "Y", "J'", "Y'")
    for name, a_list, m_list in zip(names, av, mv):
        for n, (a, m) in enumerate(zip(a_list, m_list)):
            mid, rad = _to_mpf(a.mid()), _to_mpf(a.rad())
            if name.endswith("'"):  # finite-difference derivative: allow its truncation too
                rad += abs(mid) * tol * 10 ** 4
            if abs(m - mid) > rad + tol * max(abs(m), abs(mid)):
                raise EngineDisagreement(f"mpmath and arb disagree on {name}_{n}({mpmath.nstr(z, 17)}): "
                                         f"{mpmath.nstr(m, 20)} vs {mpmath.nstr(mid, 20)} +- "
                                         f"{mpmath.nstr(rad, 3)}")
            rep.agreements += 1


def scipy_cross_product_errors(nmax, points):
    """Relative error of J_n Y_n+1 - J_n+1 Y_n + 2/(pi z) in double precision (SciPy jv/yv).

    Returns a list of (z, n, relative error) against the arb value at 30 digits.
    Used in docs/bessel.md to show where double precision loses digits.
    """
    import numpy as np
    from scipy.special import jv, yv
    out = []
    for z in points:
        z = check_z(z)
        for n in range(nmax + 1):
            with np.errstate(all="ignore"):  # Y_n overflows at small z: inf * 0 = nan
                d = jv(n, z) * yv(n + 1, z) - jv(n + 1, z) * yv(n, z)
            ref = -2 / (np.pi * z)
            out.append((z, n, float(abs(d - ref) / abs(ref)) if np.isfinite(d) else math.inf))
    return out


def scipy_value_errors(n, points, dps=30):
    """Relative errors of SciPy's jv(n, z) and yv(n, z) against arb balls at ``dps`` digits.

    Returns a list of (z, error of jv, error of yv).
    """
    from scipy.special import jv, yv
    out = []
    with _Prec(bits_for(dps)):
        for z in points:
            z = check_z(z)
            x = arb(z)
            rj, ry = x.bessel_j(n), x.bessel_y(n)
            ej = abs(arb(float(jv(n, z))) - rj) / abs(rj)
            ey = abs(arb(float(yv(n, z))) - ry) / abs(ry)
            out.append((z, float(ej.mid()), float(ey.mid())))
    return out
