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
    simplification), so it equals its limit at z -> 0, which SymPy computes
    from the series of J and Y.  Returns the closed form, a function of z.
    """
    cross = sp.besselj(n, _z) * sp.bessely(n + 1, _z) - sp.besselj(n + 1, _z) * sp.bessely(n, _z)
    if not is_zero(sp.diff(_z * cross, _z)):
        raise InputError(f"could not show that z*(J_{n} Y_{n+1} - J_{n+1} Y_{n}) is constant")
    constant = sp.limit(_z * cross, _z, 0, "+")
    return constant / _z


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
        theta_L = self.general_z.subs(_z, self.z_of_L)
        # Substitution check in the L-form (002 eq. 7 corrected) ...
        eq = f.euler_form
        thL = S.theta(Lvar)
        residual_L = eq.subs({thL.diff(Lvar, 2): theta_L.diff(Lvar, 2),
                              thL.diff(Lvar): theta_L.diff(Lvar)}).subs(thL, theta_L)
        self.residual_L = _simplified_residual(residual_L)
        # ... and in t, in the linear equation (002 eq. 4) with L(t) written out.
        theta_t = theta_L.subs(Lvar, self.length)
        lin = (self.length * theta_t.diff(S.t, 2) + 2 * self.length.diff(S.t) * theta_t.diff(S.t)
               + S.g * theta_t)
        self.residual_t = _simplified_residual(lin)
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
        sol = sp.solve(eqs, [S.A, S.B], dict=True)[0]
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

def quarter_periods(count=8, dps=30):
    """Quarter periods of the B = 0 solution of the growing string, in time order (002).

    A list of ``count`` records (dicts: "from", "to", "direction" ("toward"
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
    out = []
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
