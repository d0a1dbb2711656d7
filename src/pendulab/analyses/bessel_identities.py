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

* ``arb`` (python-flint): J, Y and the derivatives J_n', Y_n' as balls whose
  radii bound the error.  The derivatives come from one more value f(z + h)
  by Taylor's formula, f'' and f''' from Bessel's equation of order n, with a
  rigorous bound on the remainder (see :func:`_arb_values`);
* ``mpmath``: besselj/bessely at dps + 10 digits (and at least MP_MIN_DIGITS: see
  :func:`mp_digits`), derivatives by mpmath's own hypergeometric formula
  (``derivative=1``), neither by Bessel's equation nor by the rule being checked.

The engines must agree: every value mpmath gives must lie within the arb ball
widened by 10^-(dps+5) relative, else :class:`EngineDisagreement` is raised.
The result reports the worst relative error over everything checked, the z
and the identity where it occurs, and that error in units of 10^-dps.
"""

import math
from dataclasses import dataclass, field

from flint import arb, ctx

from pendulab.analyses.bessel_zeros import _log2, _Prec, bessel_zeros, bits_for, check_dps
from pendulab.errors import InputError, PendulabError

MAX_NMAX = 100
MAX_POINTS = 10_000
RULES = ("cross", "derivative_J", "derivative_Y", "wronskian")
ENGINES = ("arb", "mpmath")


#: Fewest digits the mpmath engine works at, whatever the dps checked.  mpmath's besselj and
#: bessely at d digits are accurate to about 10^-d relative to the terms they sum, not to the
#: value: it raises its own precision only for a cancellation it can see.  Next to a zero (the
#: grid's points j_n,k rounded to doubles, where |J_n| ~ 1e-17) 11 to 14 digits (dps 1 to 4)
#: left J_0(2.404825557695773) and J_1(3.8317059702075125) without one correct digit, and the
#: engines "disagreed"; from about 13 digits on mpmath sees the cancellation and compensates.
MP_MIN_DIGITS = 25


def mp_digits(dps):
    """The digits of the mpmath engine when the identities are checked at ``dps``: dps + 10,
    and at least :data:`MP_MIN_DIGITS` (the same as dps + 10 from dps = 15 on).

    >>> mp_digits(1), mp_digits(15), mp_digits(30)
    (25, 25, 40)
    """
    return max(dps + 10, MP_MIN_DIGITS)


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
    ``arb_certified`` is True when every arb ball of the four identities
    contains its exact value (cross product + 2/(pi z), both derivative rules'
    lhs - rhs, z W - 2/pi: 0); the derivative balls are certified as well.
    It is False as soon as one ball misses its exact value (a wrong value, or a
    radius too small for the value's error), and None when the arb engine did not
    run (nothing was certified, so nothing is claimed).
    """

    nmax: int
    dps: int
    points: list
    engines: tuple
    by_rule: dict = field(default_factory=dict)
    worst: tuple = None
    ratio: object = None
    arb_certified: bool = None
    agreements: int = 0
    limit_D: dict = field(default_factory=dict)

    def _rows(self):
        import mpmath
        return [[engine, rule.replace("_", " "), mpmath.nstr(v[0], 3), mpmath.nstr(v[1], 6), str(v[2])]
                for (engine, rule), v in sorted(self.by_rule.items())]

    def _caption(self):
        balls = {True: "every arb ball contains its exact value",
                 False: "an arb ball misses its exact value",
                 None: "no arb balls (the arb engine did not run)"}[self.arb_certified]
        return (f"worst relative errors of the identities at {self.dps} digits, n from 0 to "
                f"{self.nmax}, {len(self.points)} points", balls)

    def _repr_latex_(self):
        """The worst error of each (engine, identity) as a table for a notebook
        (:func:`pendulab.latex.math_table`), rounded as the product "bessel" rounds them."""
        from pendulab.latex import math_table, number_tex, text
        rows = [[text(e), text(r), number_tex(err), number_tex(z), n]
                for e, r, err, z, n in self._rows()]
        return math_table([text(line) for line in self._caption()],
                          [text("engine"), text("identity"), text("error"), "z", "n"], rows)

    def _repr_html_(self):
        """The same table in HTML (:func:`pendulab.latex.html_table`), one row per
        (engine, identity)."""
        from pendulab.latex import html_table
        return html_table("; ".join(self._caption()), ["engine", "identity", "error", "z", "n"],
                          self._rows())


def _note(rep, engine, rule, err, z, n):
    key = (engine, rule)
    if key not in rep.by_rule or err > rep.by_rule[key][0]:
        rep.by_rule[key] = (err, z, n)


def _to_mpf(x):
    """The midpoint (or any exact arb) as an mpmath number, exactly (mpmath.mpf keeps all bits)."""
    import mpmath
    man, exp = x.mid().man_exp()
    return mpmath.mpf((int(man), int(exp)))


def _accurate(compute, bits, start):
    """compute() at precisions from ``start`` up until its ball is relatively 2^-bits narrow.

    ``start`` already includes the guard bits arb is known to lose (see
    :func:`_guard`), so the first attempt normally succeeds; where arb loses
    more (next to a zero) the precision is raised once by the bits it lost.
    """
    w = start
    for _ in range(10):
        with _Prec(w):
            v = compute()
            if v.is_finite() and not v.contains(0):
                lrel = _log2(v.rad()) - _log2(abs(v).abs_lower())  # log2 of the relative radius, +-1
                if lrel <= -bits - 1:
                    return v
                w += max(lrel + bits + 8, 16)
            else:
                w *= 2
    return v


def _guard(z):
    """Guard bits for one evaluation at z: arb's balls for J_n(z), Y_n(z) come out a few bits
    wider than the working precision, and about log2(z) more for large z (the phase z - n pi/2
    - pi/4 is reduced modulo 2 pi)."""
    return 12 + max(0, math.frexp(z)[1])


def _j_fourth_derivative_bounds(n_top, x):
    """[sup |J_n''''| on (0, x] for n = 0..n_top-1]: J_n'''' = (J_n-4 - 4 J_n-2 + 6 J_n
    - 4 J_n+2 + J_n+4)/16 (DLMF 10.6.7), |J_m(t)| <= min(1, (t/2)^|m| / |m|!) for real t
    (DLMF 10.14.1, 10.14.4; J_-m = (-1)^m J_m).  Upper bounds (call at low precision)."""
    half, t, caps = arb(x) / 2, arb(1), []
    for m in range(n_top + 4):
        caps.append(min(arb(1), t))
        t = t * half / (m + 1)
    return [((caps[abs(n - 4)] + 4 * caps[abs(n - 2)] + 6 * caps[n] + 4 * caps[n + 2] + caps[n + 4]) / 16)
            .abs_upper() for n in range(n_top)]


def _y_fourth_derivative_bounds(n_top, zb, J, Y):
    """[sup |Y_n''''| on [z, oo) for n = 0..n_top-1]: |Y_n''''| <= (|Y_n-4| + 4|Y_n-2| + 6|Y_n|
    + 4|Y_n+2| + |Y_n+4|)/16 (DLMF 10.6.7) <= M_n+4, M_m = sqrt(J_m^2 + Y_m^2), which by
    Nicholson's formula (DLMF 10.9.30) decreases in x > 0 and increases in the order m >= 0
    (Y_-m = (-1)^m Y_m).  ``zb`` is z as a ball, ``J``, ``Y`` the balls of orders 0..n_top at z;
    the three orders above are computed here.  Upper bounds (call at low precision)."""
    M = [(J[m] ** 2 + Y[m] ** 2).sqrt() for m in range(n_top + 1)]
    for m in range(n_top + 1, n_top + 4):
        M.append((zb.bessel_j(m) ** 2 + zb.bessel_y(m) ** 2).sqrt())
    return [M[n + 4].abs_upper() for n in range(n_top)]


def _arb_values(n_top, z, bits, derivatives=True):
    """J_n, Y_n (n = 0..n_top) at z and J_n', Y_n' (n = 0..n_top-1), all as certified balls.

    Values: arb's bessel_j / bessel_y, each ball relatively 2^-bits narrow.

    Derivatives, from one more value per function: Taylor's formula at z with step
    h = min(z, 1) 2^-hb, hb = bits/3 + 8, and f'' and f''' replaced by Bessel's equation
    f'' = -f'/z - (1 - n^2/z^2) f (DLMF 10.2.1; order n only, not the rule under test):
    f''' = ((n^2 + 2)/z^2 - 1) f' + (1/z - 3 n^2/z^3) f, so

        f(z + h) = A f(z) + B f'(z) + R,
        A = 1 - (h^2/2)(1 - n^2/z^2) + (h^3/6)(1/z - 3 n^2/z^3),
        B = h - h^2/(2z) + (h^3/6)((n^2 + 2)/z^2 - 1),
        |R| <= (h^4/24) sup |f''''| on [z, z + h]   (Lagrange remainder),

    and f'(z) = (f(z + h) - A f(z) +- R)/B, in balls.  The bound on f'''':

    * J_n: the closed form of :func:`_j_fourth_derivative_bounds`;
    * Y_n: |Y_n''''| <= (|Y_n-4| + 4|Y_n-2| + 6|Y_n| + 4|Y_n+2| + |Y_n+4|)/16 (DLMF 10.6.7)
      <= M_n+4(z), with M_m = sqrt(J_m^2 + Y_m^2), which by Nicholson's formula
      (DLMF 10.9.30) decreases in x > 0 and increases in the order m >= 0; M_m(z) from the
      value balls (three more orders at 64 bits; :func:`_y_fourth_derivative_bounds`).

    The difference f(z + h) - A f(z) loses about hb bits, so both values are computed at
    bits + hb (+ guard); R is about 2^-(bits + 16) relative.  Every ball returned holds the
    exact value: the derivative balls are certified, not estimates.
    """
    zb = arb(z)
    g = _guard(z)
    hb = bits // 3 + 8 if derivatives else 0
    J = [_accurate(lambda n=n: zb.bessel_j(n), bits + hb, bits + hb + g) for n in range(n_top + 1)]
    Y = [_accurate(lambda n=n: zb.bessel_y(n), bits + hb, bits + hb + g) for n in range(n_top + 1)]
    if not derivatives:
        return J, Y, [], []
    # bounds on the fourth derivatives on [z, z + 1/64 min(z, 1)], at 64 bits plus the guard
    # bits of the phase: at 64 bits alone arb cannot reduce z = 1e20 modulo 2 pi, its M_m
    # ball is not finite and the derivative loop never ends
    with _Prec(64 + g):
        bY = _y_fourth_derivative_bounds(n_top, zb, J, Y)
        bJ = _j_fourth_derivative_bounds(n_top, arb(z) * (1 + arb(2) ** -6))
    taylor = {}  # (n, hb, precision) -> (A, B, h^4/24), shared by J_n and Y_n (same equation)

    def coefficients(n, hb_n):
        key = (n, hb_n, ctx.prec)
        if key not in taylor:
            h = arb(min(z, 1.0)) * arb(2) ** (-hb_n)  # exact: a power of two times a double
            n2, iz = arb(n * n), 1 / zb
            h2, h3 = h * h / 2, h * h * h / 6
            taylor[key] = (zb + h,  # exact: hb + 53 + log2(z) bits < precision
                           1 - h2 * (1 - n2 * iz * iz) + h3 * (iz - 3 * n2 * iz * iz * iz),
                           h - h2 * iz + h3 * ((n2 + 2) * iz * iz - 1), h ** 4 / 24)
        return taylor[key]

    def deriv(kind, n, f, bound):
        """f'(z) from f(z + h) and f(z); h shrinks when the remainder dominates the ball
        (f' nearly 0), the precision grows when rounding does (cancellation)."""
        hb_n, w = hb, bits + hb + g
        for _ in range(16):
            with _Prec(w):
                xh, A, B, h4 = coefficients(n, hb_n)
                fh = xh.bessel_j(n) if kind == "J" else xh.bessel_y(n)
                if w > bits + hb + g:  # f(z) at the raised precision too
                    f = zb.bessel_j(n) if kind == "J" else zb.bessel_y(n)
                r = (h4 * bound).abs_upper()
                v = (fh - A * f + arb(0, r)) / B
                if not v.is_finite() or v.contains(0):
                    hb_n, w = 2 * hb_n, 2 * w
                    continue
                size = _log2(abs(v).abs_lower())
                if _log2(v.rad()) - size <= -bits - 1:
                    return v
                excess = _log2(r) - _log2(abs(B).abs_lower()) - size + bits + 2  # remainder vs 2^-bits
                if excess > 0:
                    hb_n += excess // 3 + 2
                w = max(w + 16, bits + hb_n + g + (_log2(v.rad()) - size + bits + 8))
        return v
    dJ = [deriv("J", n, J[n], bJ[n]) for n in range(n_top)]
    dY = [deriv("Y", n, Y[n], bY[n]) for n in range(n_top)]
    return J, Y, dJ, dY


def _mp_values(n_top, z, dps, derivatives=True):
    import mpmath
    with mpmath.workdps(mp_digits(dps)):
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
    if "arb" in engines:
        rep.arb_certified = True  # until a ball misses its exact value
    with mpmath.workdps(mp_digits(dps)):
        two_pi_mp = 2 / mpmath.pi
    with _Prec(bits):
        two_pi_arb = 2 / arb.pi()
    tol = mpmath.mpf(10) ** (-(dps + 5))
    for z in pts:
        vals = {}
        if "arb" in engines:
            vals["arb"] = _arb_values(nmax + 1, z, bits, deriv)
            with _Prec(bits), mpmath.workdps(mp_digits(dps)):
                for n in range(nmax + 1):
                    errs, cross, zw = _errors(*vals["arb"], n, arb(z), two_pi_arb, abs)
                    for rule, e in errs.items():
                        if not e.contains(0):  # the exact identity is outside the ball
                            rep.arb_certified = False
                        _note(rep, "arb", rule, e.upper(), z, n)  # kept as arb, to mpf below
                    if z == pts[0] and deriv:
                        rep.limit_D["arb"] = _to_mpf(zw.mid())
        if "mpmath" in engines:
            vals["mpmath"] = _mp_values(nmax + 1, z, dps, deriv)
            with mpmath.workdps(mp_digits(dps)):
                x = mpmath.mpf(z)
                for n in range(nmax + 1):
                    errs, _, zw = _errors(*vals["mpmath"], n, x, two_pi_mp, abs)
                    for rule, e in errs.items():
                        _note(rep, "mpmath", rule, e, z, n)
                    if z == pts[0] and deriv:
                        rep.limit_D["mpmath"] = zw
        if len(vals) == 2:
            with mpmath.workdps(mp_digits(dps)):
                _compare(vals["arb"], vals["mpmath"], z, tol, rep)
    with mpmath.workdps(mp_digits(dps)):
        for key, (err, z, n) in rep.by_rule.items():
            if key[0] == "arb":
                rep.by_rule[key] = (_to_mpf(err), z, n)
        rep.worst = None
        for (engine, rule), (err, z, n) in rep.by_rule.items():
            if rep.worst is None or err > rep.worst[0]:
                rep.worst = (err, z, rule, n, engine)
        rep.ratio = rep.worst[0] / mpmath.mpf(10) ** (-dps)
    return rep


def _compare(av, mv, z, tol, rep):
    """Every mpmath value inside the arb ball widened by tol relative (else EngineDisagreement)."""
    import mpmath
    names = ("J", "Y", "J'", "Y'")
    for name, a_list, m_list in zip(names, av, mv):
        for n, (a, m) in enumerate(zip(a_list, m_list)):
            mid, rad = _to_mpf(a.mid()), _to_mpf(a.rad())
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
