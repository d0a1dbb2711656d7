"""The variable-length pendulum in closed form (002_19b336b29bb1f03b.txt).

From the generalised Bessel match of :func:`pendulab.canonical.length_form`
(alpha = -1/2, beta = 1/2, k = 2 sqrt(g)/v0, p = 1 for L = L0 + v0 t) the
general solution is theta = x^alpha (C1 J_p(k x^beta) + C2 Y_p(k x^beta)),
written with z = k L^beta as theta = A z^(alpha/beta) J_p(z) + B z^(alpha/beta) Y_p(z)
(002: theta = A z^-1 J1(z) + B z^-1 Y1(z), z = (2/v0) sqrt(g L)).

Every step is checked by SymPy rather than asserted:

* the solution is substituted into the equation and the residual is shown
  to be exactly 0 (:func:`closed_form` ``residual``; :func:`is_zero`: the
  Bessel recurrence DLMF 10.6.1 and expansion, else SymPy's simplify);
* the derivative rule d/dz [z^-p C_p(z)] = -z^-p C_{p+1}(z) for C = J, Y
  (DLMF 10.6.6; 002 "Obs. 1") is verified symbolically before it is used;
* the cross product z (J_n Y_{n+1} - J_{n+1} Y_n) is shown to be constant
  (its z-derivative simplifies to 0: Abel's theorem, 002 "Demonstração") and
  its value is the limit z -> 0, giving -2/pi (002 "Afirmação"; DLMF 10.5.3);
* the constants A, B for theta(0) = theta_0, theta'(0) = 0 then follow by
  Cramer's rule and the cross product.

High-precision numerical checks of the same identities, certified by two
engines, live in :mod:`pendulab.analyses.bessel_identities`; certified zeros
and 002's quarter periods in :mod:`pendulab.analyses.bessel_zeros` and
:mod:`pendulab.analyses.bessel_periods`.
"""

from dataclasses import dataclass

import sympy as sp

from pendulab import symbols as S
from pendulab.canonical import Lvar
from pendulab.errors import DerivationOrderError, InputError

_z = S.z


def _lower_orders(expr):
    """``expr`` with every J_n(x), Y_n(x) of order n >= m + 2 (m the lowest order of that
    family and argument in ``expr``) written through the recurrence
    C_n(x) = 2 (n - 1)/x C_{n-1}(x) - C_{n-2}(x) (DLMF 10.6.1), down to orders m, m + 1."""
    funcs = expr.atoms(sp.besselj, sp.bessely)
    lowest = {}
    for f in funcs:
        key = (f.func, f.args[1])
        lowest[key] = f.args[0] if key not in lowest else sp.Min(lowest[key], f.args[0])

    def lower(f):
        n, x = f.args
        gap = n - lowest[(f.func, x)]
        if gap.is_Integer and gap >= 2:
            return lower(f.func(n - 1, x)) * 2 * (n - 1) / x - lower(f.func(n - 2, x))
        return f
    return expr.xreplace({f: lower(f) for f in funcs})


def _fast_zero(expr):
    """True when the numerator of ``expr`` over a common denominator expands to 0 once its
    Bessel functions are brought down to two consecutive orders per argument
    (:func:`_lower_orders`, DLMF 10.6.1; the functions then enter as independent atoms)."""
    try:
        return sp.expand(sp.numer(sp.together(sp.expand(_lower_orders(expr))))) == 0
    except (TypeError, ValueError, NotImplementedError):  # pragma: no cover - simplify decides
        return False


def is_zero(expr):
    """True when ``expr`` is identically 0: :func:`_fast_zero` first, else ``sp.simplify(expr) == 0``.

    The fast proof costs about a tenth of simplify on the residuals of the
    closed form; where it does not succeed SymPy's simplify decides, as before.
    """
    return expr == 0 or _fast_zero(expr) or sp.simplify(expr) == 0


def _simplified_residual(expr):
    """0 when :func:`_fast_zero` proves it, else ``sp.simplify(expr)`` (what is reported)."""
    if expr == 0 or _fast_zero(expr):
        return sp.S.Zero
    return sp.simplify(expr)


def derivative_rule_holds(p, kind):
    """True when d/dz[z^-p C_p(z)] + z^-p C_{p+1}(z) is identically 0 (DLMF 10.6.6; :func:`is_zero`)."""
    f = {"J": sp.besselj, "Y": sp.bessely}[kind]
    expr = sp.diff(_z**-p * f(p, _z), _z) + _z**-p * f(p + 1, _z)
    return is_zero(expr)


def cross_product(n):
    """Derive J_n Y_{n+1} - J_{n+1} Y_n in closed form (002 "Afirmação", "Obs. 2").

    Abel's theorem: z times the cross product has zero derivative (checked by
    simplification), so it equals its limit at z -> 0: the leading term of its
    expansion at 0+, which SymPy forms from the series of J and Y (what
    ``sp.limit`` does; the limit itself decides if that term is not a
    constant).  Returns the closed form, a function of z.
    """
    cross = sp.besselj(n, _z) * sp.bessely(n + 1, _z) - sp.besselj(n + 1, _z) * sp.bessely(n, _z)
    if not is_zero(sp.diff(_z * cross, _z)):
        raise InputError(f"could not show that z*(J_{n} Y_{n+1} - J_{n+1} Y_{n}) is constant")
    constant = (_z * cross).as_leading_term(_z, cdir=1)
    if constant.has(_z) or not constant.is_finite:
        constant = sp.limit(_z * cross, _z, 0, "+")
    return constant / _z


def chain_derivatives(outer, inner, var):
    """(F, dF/dvar, d^2F/dvar^2) of F = ``outer`` (an expression in z) composed with z = ``inner``
    (an expression in ``var``) by the chain rule, F' z' and F'' z'^2 + F' z'', with F, F', F''
    left as functions of z (so the Bessel functions keep the argument z)."""
    f1 = outer.diff(_z)
    f2 = f1.diff(_z)
    i1 = inner.diff(var)
    i2 = i1.diff(var)
    return outer, f1 * i1, f2 * i1**2 + f1 * i2


def _cramer(eqs, unknowns):
    """{unknown: value} solving the linear equations ``eqs`` (each = 0) by Cramer's rule (002,
    "Pela regra de Cramer"): the coefficient matrix's determinant with the right-hand side in
    the unknown's column, over its determinant (an InputError when that is 0)."""
    matrix, rhs = sp.linear_eq_to_matrix(eqs, unknowns)
    det = matrix.det()
    if det == 0:
        raise InputError("the initial conditions do not fix the constants (determinant 0)")
    out = {}
    for i, key in enumerate(unknowns):
        column = matrix.copy()
        column[:, i] = rhs
        out[key] = column.det() / det
    return out


def _inverse_power(z_of_l, k, beta):
    """L as a function of z for z = k L^beta: (z/k)^(1/beta), or None unless it is checked to
    give back L from z_of_l (SymPy's automatic simplification; L, z positive)."""
    l_of_z = (_z / k) ** (1 / beta)
    return l_of_z if l_of_z.subs(_z, z_of_l) == Lvar else None


def _inverse_linear(length, l_of_z, z_of_t):
    """t as a function of z for L(t) = c0 + c1 t and L = ``l_of_z``: (l_of_z - c0)/c1, or None
    (no such inverse, or it does not give back t from ``z_of_t``)."""
    if l_of_z is None or not length.is_polynomial(S.t):
        return None
    poly = sp.Poly(length, S.t)
    if poly.degree() != 1:
        return None
    t_of_z = (l_of_z - poly.coeff_monomial(1)) / poly.coeff_monomial(S.t)
    return t_of_z if t_of_z.subs(_z, z_of_t) == S.t else None


@dataclass
class BesselSolution:
    """General solution and initial-value solution of the variable-length pendulum.

    Call :meth:`solve` first; reading a result before raises
    :class:`DerivationOrderError` ("solve() first").
    """

    form: object  # pendulab.canonical.BesselForm
    length: sp.Expr
    _done: bool = False

    def _need(self):
        if not self._done:
            raise DerivationOrderError("the Bessel solution is read before solve() ran")

    def solve(self):
        f = self.form
        if f is None or f.alpha is None:
            raise InputError("the equation has no generalised Bessel form; no closed form")
        alpha, beta, k, p = f.alpha, f.beta, f.k, f.p
        if not (p.is_integer and p >= 0):
            raise InputError(f"Bessel order {p} is not a non-negative integer")
        self.z_of_L = k * Lvar**beta
        power = sp.simplify(alpha / beta)
        self.power = power
        self.general_z = (S.A * _z**power * sp.besselj(p, _z)
                          + S.B * _z**power * sp.bessely(p, _z))
        # Substitution check in the L-form (002 eq. 7 corrected) ...
        eq = f.euler_form
        thL = S.theta(Lvar)

        def in_l(theta, d1, d2):
            return eq.subs({thL.diff(Lvar, 2): d2, thL.diff(Lvar): d1}).subs(thL, theta)

        l_of_z = _inverse_power(self.z_of_L, k, beta)
        self.residual_L = self._residual(in_l, Lvar, self.z_of_L, l_of_z)

        # ... and in t, in the linear equation (002 eq. 4) with L(t) written out.
        def in_t(theta, d1, d2):
            return self.length * d2 + 2 * self.length.diff(S.t) * d1 + S.g * theta

        z_t = self.z_of_L.subs(Lvar, self.length)
        self.residual_t = self._residual(in_t, S.t, z_t, _inverse_linear(self.length, l_of_z, z_t))
        # Initial conditions theta(0) = theta_0, theta'(0) = 0 (002).  dz/dt != 0, so
        # theta'(0) = 0 <=> dtheta/dz = 0 at z0; the derivative rule turns
        # d/dz[z^-p C_p] into -z^-p C_{p+1} once it has been checked.
        self.z0 = sp.simplify(self.z_of_L.subs(Lvar, self.length.subs(S.t, 0)))
        rules_ok = power == -p and all(derivative_rule_holds(int(p), c) for c in "JY")
        if rules_ok:
            dtheta = -(S.A * _z**power * sp.besselj(p + 1, _z)
                       + S.B * _z**power * sp.bessely(p + 1, _z))
            if not is_zero(dtheta - self.general_z.diff(_z)):
                raise InputError("derivative rule check failed")
        else:
            dtheta = self.general_z.diff(_z)
        self.dtheta_dz = dtheta
        z0s = S.z0
        eqs = [self.general_z.subs(_z, z0s) - S.theta_0, dtheta.subs(_z, z0s)]
        sol = _cramer(eqs, [S.A, S.B])
        self.cramer = {key: sp.factor(val) for key, val in sol.items()}
        cross = cross_product(int(p))  # J_p Y_{p+1} - J_{p+1} Y_p as a function of z
        jy = sp.besselj(p, z0s) * sp.bessely(p + 1, z0s) - sp.besselj(p + 1, z0s) * sp.bessely(p, z0s)
        simplified = {}
        for key, val in self.cramer.items():
            num, den = sp.fraction(sp.together(val))
            ratio = sp.cancel(den / jy)
            if ratio.has(sp.besselj) or ratio.has(sp.bessely):
                simplified[key] = val
            else:
                simplified[key] = sp.factor(num / (ratio * cross.subs(_z, z0s)))
        self.z0_symbol = z0s
        self.constants = simplified
        self.particular_z = sp.factor(self.general_z.subs(simplified))
        self.cross = cross
        self._done = True
        return self

    def _residual(self, build, var, z_of_var, var_of_z):
        """0 when theta = general_z(z(var)) is shown to solve ``build(theta, theta', theta'')`` = 0
        identically, else the simplified residual (what is reported).

        Fast route: the derivatives by the chain rule, d theta/d var = F'(z) z', d^2 theta/d var^2
        = F''(z) z'^2 + F'(z) z'' (F = general_z, z = ``z_of_var``), and var written back as
        ``var_of_z`` (checked to undo z: var_of_z(z(var)) = var, so the residual vanishes for
        every var exactly when it vanishes for every z); the residual is then a rational function
        of z and the Bessel functions of z, and :func:`_fast_zero` shows it is 0.  Where the
        inverse is not known or the fast proof does not succeed, the residual is formed by
        differentiating general_z(z(var)) itself and :func:`_simplified_residual` decides.
        """
        if var_of_z is not None:
            in_z = build(*chain_derivatives(self.general_z, z_of_var, var)).subs(var, var_of_z)
            if not in_z.has(var) and _fast_zero(in_z):
                return sp.S.Zero
        theta = self.general_z.subs(_z, z_of_var)
        return _simplified_residual(build(theta, theta.diff(var), theta.diff(var, 2)))

    def _repr_latex_(self):
        """The general solution in z and the initial-value solution (002) as one ``align*``,
        as the product "equations" prints them; None (the plain repr) before :meth:`solve`."""
        if not self._done:
            return None
        from pendulab.latex import align, sum_rows, text
        rows = [r"&" + text("general solution in Bessel functions (002):")]
        rows += sum_rows(r"\theta", self.general_z) + [r"z &= " + sp.latex(self.z_of_L)]
        rows += [r"&" + text("with ") + r"\theta(0) = \theta_0,\ \dot\theta(0) = 0" + text(":"),
                 r"\theta &= " + sp.latex(self.particular_z), r"z_0 &= " + sp.latex(self.z0)]
        return align(rows)

    @property
    def solution(self):
        self._need()
        return self.general_z

    @property
    def residuals(self):
        self._need()
        return self.residual_L, self.residual_t


def closed_form(form, length):
    """Solve the variable-length pendulum for ``form`` (a BesselForm) and ``length`` L(t)."""
    return BesselSolution(form, sp.sympify(length)).solve()


def check_cross_product_numerically(n, z_values, dps=50):
    """max |J_n Y_{n+1} - J_{n+1} Y_n + 2/(pi z)| over ``z_values`` at ``dps`` digits (mpmath)."""
    import mpmath
    worst = mpmath.mpf(0)
    with mpmath.workdps(dps + 10):
        for zv in z_values:
            zz = mpmath.mpf(zv)
            val = (mpmath.besselj(n, zz) * mpmath.bessely(n + 1, zz)
                   - mpmath.besselj(n + 1, zz) * mpmath.bessely(n, zz) + 2 / (mpmath.pi * zz))
            worst = max(worst, abs(val))
    return worst


# ---------------------------------------------------------------------------
# Quarter periods (002, last part)
# ---------------------------------------------------------------------------

class SwingList(list):
    """The list :func:`quarter_periods` returns (its records unchanged), which a notebook shows
    as a table: one row per quarter period, in time order."""

    def _rows(self):
        import mpmath
        return [[str(k + 1), r["from"], r["to"], r["direction"], mpmath.nstr(r["duration"], 15)]
                for k, r in enumerate(self)]

    _CAPTION = "quarter periods of the growing string in time order (unit v0/(4g))"
    _TEX_CAPTION = r"\text{quarter periods of the growing string in time order (unit }v_0/(4g)\text{)}"

    def _repr_latex_(self):
        """The table as display math (:func:`pendulab.latex.math_table`)."""
        from pendulab.latex import math_table, text
        rows = [[k, text(a), text(b), text(d), v] for k, a, b, d, v in self._rows()]
        return math_table(self._TEX_CAPTION, ["", text("from"), text("to"), text("swing"),
                                                 text("duration")], rows)

    def _repr_html_(self):
        """The table in HTML (:func:`pendulab.latex.html_table`), one row per quarter period."""
        from pendulab.latex import html_table
        return html_table(self._CAPTION, ["", "from", "to", "swing", "duration"], self._rows())


def quarter_periods(count=8, dps=30):
    """Quarter periods of the B = 0 solution of the growing string, in time order (002).

    A list (a :class:`SwingList`) of ``count`` records (dicts: "from", "to", "direction" ("toward"
    equilibrium or "outward"), "z_from", "z_to", "duration" = difference of
    squares in the unit v0/(4 g)), numbers as mpmath mpf at ``dps`` digits.
    The zeros are pendulab's certified ones
    (:func:`pendulab.analyses.bessel_zeros.bessel_zeros`); for the shortening
    string and the margins see :mod:`pendulab.analyses.bessel_periods`.
    """
    import mpmath

    from pendulab.analyses.bessel_zeros import bessel_zeros, check_count, check_dps
    check_count(count, "count", 10_000)
    check_dps(dps)
    n = count // 2 + 3
    j1, j2 = bessel_zeros(1, n, dps).strings, bessel_zeros(2, n, dps).strings
    out = SwingList()
    with mpmath.workdps(dps + 10):
        events = []
        for k in range(1, n):  # interlacing (proved in bessel_periods): j_2,k < j_1,k+1 < j_2,k+1
            events.append(("J2", k, mpmath.mpf(j2[k - 1])))
            events.append(("J1", k + 1, mpmath.mpf(j1[k])))
        for (f1, k1, z1), (f2, k2, z2) in zip(events, events[1:]):
            if len(out) == count:
                break
            out.append({"from": f"{f1} zero {k1}", "to": f"{f2} zero {k2}", "z_from": z1, "z_to": z2,
                        "direction": "toward" if f1 == "J2" else "outward", "duration": z2 ** 2 - z1 ** 2})
    return out


def toward_swings_are_longer(periods):
    """The source's claim: each swing toward equilibrium outlasts its outward neighbours.

    Returns a list of (index, holds) for every "toward" quarter period that has
    a neighbour; the claim is that every entry holds.
    """
    verdict = []
    for i, rec in enumerate(periods):
        if rec["direction"] != "toward":
            continue
        neighbours = [periods[j]["duration"] for j in (i - 1, i + 1) if 0 <= j < len(periods)]
        verdict.append((i, all(rec["duration"] > d for d in neighbours)))
    return verdict
