"""Stage 3 (canonical form): Mathieu/Hill for the driven pivot, Bessel for the variable length.

Driven pivot: with tau = omega t / 2 (000, before eq. 5) the linearised
equation becomes theta'' + P(tau) theta = 0.  The periodic coefficient is
analysed exactly: it is written as a finite sum of exponentials
exp(i k tau), straight from its sines and cosines (products of the spectra
of the factors, :func:`pendulab.exprs.trig_spectrum`; no rewrite to
exponentials and no simplify of the whole, so the work grows like the square
of the number of harmonics, at most :data:`pendulab.limits.MAX_HARMONICS`), and

* only k in {0, +-2}: Mathieu's equation theta'' + (theta0 + 2 theta1 cos 2tau)
  theta = 0 (000 eq. 7), with theta0 and theta1 read off (000 eqs. 5-6); a
  sine or phase-shifted drive is Mathieu's after a shift of tau, reported;
* other integer k (a drive with several harmonics of omega): a Hill
  equation, reported with its Fourier coefficients;
* anything else (non-periodic or incommensurate drive): neither, reported as
  a linear equation with a time-dependent coefficient.

Variable length: for L(t) = c0 + c1 t the length becomes the independent
variable (002 eqs. 5-7) and the equation is matched to the generalised Bessel
form x^2 y'' + (1 - 2 alpha) x y' + (alpha^2 - beta^2 p^2 + beta^2 k^2 x^(2 beta)) y = 0
(002, "equação de Bessel modificada"), whose solutions are x^alpha Z_p(k x^beta).
"""

from dataclasses import dataclass, field
from math import gcd, lcm

import sympy as sp

from pendulab import symbols as S
from pendulab.errors import InputError
from pendulab.exprs import size, trig_spectrum

#: The length used as independent variable (002 eqs. 5-7).
Lvar = S.Lvar


# ---------------------------------------------------------------------------
# Driven pivot
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class PeriodicForm:
    """theta''(tau) + coefficient(tau) theta = 0 and what kind of equation it is.

    ``kind`` is "mathieu", "hill" or "linear".  For Mathieu, ``theta0`` and
    ``theta1`` are the parameters of 000 eq. 7 and ``shift`` the tau-shift that
    turns the drive into a pure cosine (0 for the source's drive).  ``fourier``
    maps k >= 0 to the real pair (A_k, B_k) of the coefficient
    sum_k A_k cos(k tau) + B_k sin(k tau) (Hill and Mathieu).  ``frequency``
    is the fundamental angular frequency Omega of the drive, tau = Omega t/2
    (None when the coefficient is not periodic; tau then uses omega).
    """

    equation: sp.Expr
    coefficient: sp.Expr
    kind: str
    theta0: sp.Expr = None
    theta1: sp.Expr = None
    shift: sp.Expr = sp.Integer(0)
    fourier: dict = field(default_factory=dict)
    period: sp.Expr = None
    note: str = ""
    frequency: sp.Expr = S.omega

    def _repr_latex_(self):
        """The equation in tau = Omega t/2 and, for Mathieu's, theta0 and theta1 (000 eqs. 5-7),
        as one ``align*`` (the products' printer :func:`pendulab.latex.sum_rows`)."""
        from pendulab.latex import align, sum_rows, text
        names = {"mathieu": "Mathieu's equation (000 eq. 7)", "hill": "a Hill equation",
                 "linear": "a linear equation, not periodic"}
        omega = S.omega if self.frequency is None else self.frequency
        rows = [r"&" + text(names.get(self.kind, self.kind) + ", ") + r"\tau = "
                + sp.latex(omega * S.t / 2) + ":"]
        rows += sum_rows("", self.equation, 0)
        if self.kind == "mathieu":
            rows += [r"\theta_0 &= " + sp.latex(self.theta0),
                     r"\theta_1 &= " + sp.latex(self.theta1)]
        return align(rows)


def _exponential_spectrum(expr, var):
    """Write ``expr`` as sum c_k exp(i k var); return {k: c_k} or None.

    None when ``expr`` is not a trigonometric polynomial in ``var`` or some
    rate k is not a real number.  The spectrum comes straight from the sines
    and cosines (:func:`pendulab.exprs.trig_spectrum`), with no rewrite to
    exponentials; each c_k is simplified on its own (a few symbols each).
    """
    spectrum = trig_spectrum(expr, var)
    if spectrum is None:
        return None
    out = {}
    for rate, coeff in spectrum.items():
        if not rate.is_number or not rate.is_real:
            return None
        k = sp.nsimplify(rate)
        out[k] = out.get(k, 0) + coeff
    simplified = {k: _simplify_small(sp.expand(c)) for k, c in out.items()}
    return {k: c for k, c in simplified.items() if c != 0}


def _simplify_small(expr):
    """``sp.simplify`` for a coefficient; a product of powers is left as it is (already simplest)."""
    if expr.is_Add or expr.has(sp.exp, sp.sin, sp.cos):
        return sp.simplify(expr)
    return expr


def _real_fourier(spectrum):
    """{k: c_k} of exp(i k tau) -> {k >= 0: (A_k, B_k)} of cos(k tau), sin(k tau)."""
    out = {}
    for k in sorted({abs(int(k)) for k in spectrum}):
        cp = spectrum.get(sp.Integer(k), sp.Integer(0))
        cm = spectrum.get(sp.Integer(-k), sp.Integer(0))
        if k == 0:
            out[0] = (_simplify_small(sp.expand(cp)), sp.Integer(0))
        else:
            out[k] = (_simplify_small(sp.expand(cp + cm)),
                      _simplify_small(sp.expand(sp.I * (cp - cm))))
    return out


def _positive_part(rate):
    """``rate`` with its numeric sign removed (``-omega`` -> ``omega``)."""
    c, rest = rate.as_coeff_Mul()
    return abs(c) * rest


def fundamental_frequency(expr):
    """The fundamental angular frequency of a periodic function of t, or None.

    ``expr`` is written as a sum of exponentials exp(i w_j t) (from its sines
    and cosines, :func:`pendulab.exprs.trig_spectrum`); when every w_j
    is a rational multiple of one of them, the fundamental is their greatest
    common divisor (``a*cos(omega*t)`` -> omega, ``0.01*cos(20*t)`` -> 20,
    ``a*cos(omega*t)**2`` -> 2*omega, ``a*cos(omega*t) + b*cos(2*omega*t)`` ->
    omega).  None when ``expr`` has no oscillating part, or is not a finite sum
    of commensurate harmonics plus a constant.

    >>> from pendulab import symbols as S
    >>> fundamental_frequency(S.a*sp.cos(S.omega*S.t/2) + S.a*sp.sin(3*S.omega*S.t/4))
    omega/4
    """
    spectrum = trig_spectrum(sp.sympify(expr), S.t)
    if spectrum is None:
        return None
    rates = []
    for rate, coeff in spectrum.items():
        if rate == 0:
            continue
        if not rate.is_real:
            return None
        if sp.expand(coeff) != 0:
            rates.append(_positive_part(rate))
    if not rates:
        return None
    base = min(rates, key=sp.default_sort_key)
    numerators, denominators = [], []
    for rate in rates:
        ratio = sp.nsimplify(sp.simplify(rate / base))
        if not ratio.is_Rational:
            return None
        numerators.append(int(ratio.p))
        denominators.append(int(ratio.q))
    return base * sp.Rational(gcd(*numerators), lcm(*denominators))


def periodic_form(equations):
    """Canonical form of the driven pivot's linearised equation in tau = Omega t/2.

    Omega is the fundamental frequency of the pivot's acceleration
    (:func:`fundamental_frequency`):
    omega for the source's drive a cos(omega t) (000, before eq. 5).  When the
    drive is not periodic, omega is kept and the form is reported as linear.
    """
    th_t = S.theta(S.t)
    lin = sp.expand(equations.linear)
    acc = th_t.diff(S.t, 2)
    if sp.simplify(lin.coeff(acc) - 1) != 0:
        raise InputError("linear equation is not normalised")
    # lin is expanded: its coefficients are read off without simplify (whose cost grows
    # quickly with the number of harmonics of the drive).
    coefficient_t = lin.coeff(th_t)
    rest = sp.expand(lin - acc - coefficient_t * th_t)
    if rest != 0:
        raise InputError(f"linearised equation has terms other than theta'' and theta: {rest}")
    # The fundamental of the coefficient (of the pivot's acceleration y0''):
    # y0 = a t^2 + c cos(omega t) is a periodic drive on top of a constant one.
    found = fundamental_frequency(coefficient_t)
    freq = S.omega if found is None else found
    # theta(t) = Theta(tau), d^2/dt^2 = (Omega/2)^2 d^2/dtau^2 (000, before eq. 5).
    coefficient = sp.expand((4 / freq**2) * coefficient_t.subs(S.t, 2 * S.tau / freq))
    th = S.theta(S.tau)
    equation = th.diff(S.tau, 2) + coefficient * th
    spectrum = _exponential_spectrum(coefficient, S.tau)
    if spectrum is None or any(not k.is_integer for k in spectrum):
        return PeriodicForm(equation, coefficient, "linear", frequency=found,
                            note=f"the coefficient is not periodic with period 2*pi/({freq}): "
                                 "neither Mathieu's nor Hill's equation")
    period = sp.pi if all(k % 2 == 0 for k in spectrum) else 2 * sp.pi
    nonzero = sorted(k for k in spectrum if k != 0)
    fourier = _real_fourier(spectrum)
    # The same function as its Fourier sum (cos(2 tau), not 2 cos(tau)**2 - 1), when shorter.
    as_sum = sp.expand(sum((c * sp.cos(k * S.tau) + s * sp.sin(k * S.tau)
                            for k, (c, s) in fourier.items()), sp.Integer(0)))
    if size(as_sum) <= size(coefficient):
        coefficient = as_sum
        equation = th.diff(S.tau, 2) + coefficient * th
    if nonzero and nonzero != [-2, 2]:
        return PeriodicForm(equation, coefficient, "hill", fourier=fourier, period=period,
                            frequency=freq,
                            note=f"the drive is not a single harmonic of {freq}: this is a Hill "
                                 "equation with the Fourier coefficients given, not Mathieu's")
    theta0 = spectrum.get(sp.Integer(0), sp.Integer(0))
    if not nonzero:
        return PeriodicForm(equation, coefficient, "mathieu", theta0=theta0,
                            theta1=sp.Integer(0), fourier=fourier, period=sp.pi,
                            frequency=freq, note="no periodic drive term: theta1 = 0")
    # c_2 e^{2i tau} + c_-2 e^{-2i tau} = 2 |c_2| cos(2 tau + arg c_2) for real coefficients;
    # expand_complex turns (-1)**(1/3) and the like into re + i im.
    cp = sp.expand_complex(spectrum[sp.Integer(2)])
    re_part, im_part = sp.simplify(sp.re(cp)), sp.simplify(sp.im(cp))
    if im_part == 0:
        theta1 = sp.simplify(cp)
        shift = sp.Integer(0)
    else:
        theta1 = sp.simplify(sp.sqrt(sp.factor(sp.expand(re_part**2 + im_part**2))))
        shift = sp.simplify(-sp.atan2(im_part, re_part) / 2)
    note = "" if shift == 0 else (
        f"Mathieu's equation in the shifted time tau - ({shift}); the drive is a "
        "phase-shifted cosine")
    return PeriodicForm(equation, coefficient, "mathieu", theta0=theta0, theta1=theta1,
                        shift=shift, fourier=fourier, period=sp.pi, note=note, frequency=freq)


# ---------------------------------------------------------------------------
# Variable length
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class BesselForm:
    """The variable-length equation with L as independent variable (002 eqs. 5-7).

    ``length_equation`` is L v0^2 theta_LL + 2 v0^2 theta_L + g theta (002,
    the line before eq. 7); ``euler_form`` is that times L/v0^2, so that the
    theta_LL coefficient is L^2 (002 eq. 7, see the docs for the factor L the
    printed eq. 7 drops).  ``alpha, beta, k, p`` are the generalised Bessel
    parameters; ``None`` when the equation does not have that form.
    """

    rate: sp.Expr
    length_equation: sp.Expr
    euler_form: sp.Expr
    alpha: sp.Expr = None
    beta: sp.Expr = None
    k: sp.Expr = None
    p: sp.Expr = None

    def _repr_latex_(self):
        """The equation in L (002 eq. 7, multiplied out) and the generalised Bessel parameters
        as one ``align*`` (the products' printer :func:`pendulab.latex.sum_rows`)."""
        from pendulab.latex import align, sum_rows, text
        rows = [r"&" + text("with L as the variable, dL/dt = ") + sp.latex(self.rate) + ":"]
        rows += sum_rows("", self.euler_form, 0)
        if self.alpha is None:
            rows.append(r"&" + text("not of the generalised Bessel form"))
        else:
            rows.append(r"&\alpha = " + sp.latex(self.alpha) + r", \quad \beta = "
                        + sp.latex(self.beta) + r", \quad k = " + sp.latex(self.k)
                        + r", \quad p = " + sp.latex(self.p))
        return align(rows)


def length_form(equations):
    """Change the independent variable from t to L for L(t) = c0 + c1 t (002 eqs. 5-7)."""
    system = equations.system
    if not system.is_linear_length:
        return None
    rate = sp.Poly(system.length, S.t).coeff_monomial(S.t)
    th_L = S.theta(Lvar)
    ell = S.L(S.t)
    lin = equations.linear
    # Chain rule (002 eqs. 5-6): d/dt = v0 d/dL, so theta' = v0 theta_L, theta'' = v0^2 theta_LL.
    replaced = lin.subs({
        S.theta(S.t).diff(S.t, 2): rate**2 * th_L.diff(Lvar, 2),
        S.theta(S.t).diff(S.t): rate * th_L.diff(Lvar),
    }).subs({ell.diff(S.t): rate}).subs({ell: Lvar, S.theta(S.t): th_L})
    length_equation = sp.expand(replaced)
    lead = length_equation.coeff(th_L.diff(Lvar, 2))
    euler = sp.expand(length_equation * Lvar**2 / lead)
    return _match_bessel(rate, length_equation, euler)


def _match_bessel(rate, length_equation, euler):
    th_L = S.theta(Lvar)
    c1 = sp.simplify(euler.coeff(th_L.diff(Lvar)) / Lvar)
    c0 = sp.expand(euler.subs({th_L.diff(Lvar, 2): 0, th_L.diff(Lvar): 0}) / th_L)
    if c1.has(Lvar):
        return BesselForm(rate, length_equation, euler)
    poly = sp.Poly(c0, Lvar) if c0.is_polynomial(Lvar) else None
    if poly is None:
        return BesselForm(rate, length_equation, euler)
    terms = {mon[0]: cf for mon, cf in zip(poly.monoms(), poly.coeffs())}
    q0 = terms.pop(0, sp.Integer(0))
    if len(terms) != 1:
        return BesselForm(rate, length_equation, euler)
    (s, q1), = terms.items()
    alpha = (1 - c1) / 2
    beta = sp.Rational(s, 2)
    k = sp.sqrt(q1) / beta
    p = sp.sqrt(sp.simplify(alpha**2 - q0)) / beta
    return BesselForm(rate, length_equation, euler, alpha, beta, sp.simplify(k), sp.simplify(p))
