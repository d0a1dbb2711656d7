"""Stage 1 (system): the two pendulums as Lagrangians and their symbols.

Nothing here solves anything: a system knows its coordinates, its kinetic
and potential energies and its parameters.  :mod:`pendulab.equations` takes
it from there.

Driven pivot (000_8cba66c4fdf94ac6.txt, sec. 2.1): a rigid body of mass m,
centre of mass at distance l from a pivot that moves vertically as y0(t);
moment of inertia I about the pivot (I = m l^2 + I0, 000 after eq. 2).  The
angle is measured from the upward vertical as in the source (000 Fig. 1), or
from the downward vertical on request.

Variable length (002_19b336b29bb1f03b.txt): a point mass m on a string of
length L(t), angle from the downward vertical (002, "Dedução").
"""

from dataclasses import dataclass, field

import sympy as sp

from pendulab import symbols as S
from pendulab.errors import InputError, ParameterError

#: Bodies and their moment of inertia about the pivot, in terms of m and l
#: (l is the pivot-to-centre-of-mass distance).  A uniform rod of length
#: 2l pivoted at one end: I = m (2l)^2 / 3 = 4 m l^2 / 3 (000: l = L/2,
#: I0 = m L^2 / 12).  A point mass: I = m l^2.
BODIES = {
    "rod": sp.Rational(4, 3) * S.m * S.l**2,
    "point": S.m * S.l**2,
}

ANGLE_ORIGINS = ("up", "down")


def _free_functions(expr):
    return {f for f in expr.atoms(sp.core.function.AppliedUndef)}


#: Functions whose derivative in t is not an ordinary function (a kink or a
#: jump of the pivot would give delta functions in y0'').
_NOT_SMOOTH = (sp.Abs, sp.sign, sp.Heaviside)


def _check_time_expression(expr):
    """Refuse expressions that involve the coordinate or functions of other than t.

    An undefined function of t alone (``y0(t)``) is allowed: the derivation
    then holds for any such function.  Abs, sign and Heaviside of t are
    refused: the equations need two derivatives in t.
    """
    for f in _free_functions(expr):
        if f.func.__name__ in ("theta", "L") or f.args != (S.t,):
            raise InputError(f"may not contain {f}; functions must be of t alone "
                             "and other than theta and L")
    if expr.has(S.tau):
        raise InputError("must be written in t, not tau")
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise InputError(f"is not finite: {sp.sstr(expr)[:40]} (zoo is 1/0: a division by zero)")
    for f in expr.atoms(*_NOT_SMOOTH):
        if f.has(S.t):
            raise InputError(f"must be twice differentiable in t; {f} is not "
                             f"({type(f).__name__} of t has a kink or a jump)")


#: Most terms the square of a drive's (or length's) first derivative may have
#: multiplied out: the Lagrangian holds y0'^2 (64 harmonics give 4096).
MAX_SQUARE_TERMS = 5000


def check_cost(expr):
    """Refuse a function of t whose derivation would pass the cost bounds.

    The bounds (stated in :mod:`pendulab.exprs`): the expression and its first
    two t-derivatives at most ``MAX_SIZE`` nodes each, the square of the first
    derivative at most :data:`MAX_SQUARE_TERMS` terms multiplied out, and a
    trigonometric polynomial at most ``MAX_HARMONICS`` frequencies.
    """
    from pendulab.exprs import MAX_SIZE, expanded_terms, size, trig_spectrum
    value = expr.doit() if expr.has(sp.Derivative) else expr
    for order in (0, 1, 2):
        if order:
            value = sp.diff(value, S.t)
        n = size(value, MAX_SIZE)
        if n > MAX_SIZE:
            raise InputError(f"its derivative of order {order} in t has more than {MAX_SIZE} "
                             f"nodes (limit {MAX_SIZE})")
        if order == 1:
            try:
                expanded_terms(value**2, MAX_SQUARE_TERMS)
            except InputError:
                raise InputError("the square of its derivative in t would have more than "
                                 f"{MAX_SQUARE_TERMS} terms multiplied out (limit "
                                 f"{MAX_SQUARE_TERMS})") from None
    trig_spectrum(expr.doit() if expr.has(sp.Derivative) else expr, S.t)


def _positive_or_symbolic(value):
    """Refuse a number that is not positive; keep symbols (assumed positive)."""
    value = sp.sympify(value)
    if value.has(sp.I):
        raise InputError(f"must be a positive real quantity, got {sp.sstr(value)} "
                         "(I here is the imaginary unit sqrt(-1))")
    if value.is_number:
        if not value.is_real or not value.is_positive:
            raise InputError(f"must be positive, got {value}")
    elif value.is_positive is False or value.is_nonpositive:
        raise InputError(f"must be positive, got {value}")
    return value


def _check_inertia_bound(inertia):
    """Refuse a moment of inertia about the pivot that is provably below m l^2.

    I = m l^2 + I0 with I0 >= 0 the moment about the centre of mass (000
    after eq. 2; parallel-axis theorem).  A value whose sign of I - m l^2
    SymPy cannot decide (a bare number, a new symbol) is accepted.
    """
    excess = sp.simplify(inertia - S.m * S.l**2)
    if excess.is_negative:
        raise InputError(f"I = {sp.sstr(inertia)} is less than m*l**2 (I = m*l**2 + I0 with "
                         "I0 >= 0: the moment about the pivot is at least that of a point mass)")


def _collect(problems, key, check, *args):
    try:
        check(*args)
    except InputError as exc:
        problems.append((key, str(exc)))


@dataclass(frozen=True)
class DrivenPivot:
    """A rigid body on a vertically driven pivot (000 sec. 2.1).

    Parameters
    ----------
    body : {"rod", "point", "explicit"}
        ``rod``: I = 4 m l^2/3; ``point``: I = m l^2; ``explicit``: I is
        ``inertia`` (default the symbol I).
    drive : sympy expression in t
        Pivot height y0(t); default a cos(omega t) (000 eq. 1).
    angle : {"up", "down"}
        Measure theta from the upward vertical (the source's choice) or from
        the downward one.
    inertia : sympy expression, optional
        Moment of inertia about the pivot for ``body="explicit"``.  A number
        or expression in m, l, I0 ...; must be positive.

    The equations are derived with the moment of inertia kept as the symbol I
    (as the source writes them); :attr:`inertia` is the body's value of I,
    substituted where a product asks for it.
    """

    body: str = "rod"
    drive: sp.Expr = field(default_factory=lambda: S.a * sp.cos(S.omega * S.t))
    angle: str = "up"
    inertia_value: sp.Expr = None

    name = "kapitza"

    def __post_init__(self):
        problems = []  # (parameter, message): the scene names the key of each
        if self.body not in (*BODIES, "explicit"):
            problems.append(("body", f"must be one of rod, point, explicit; got {self.body!r}"))
        if self.angle not in ANGLE_ORIGINS:
            problems.append(("angle", f"must be 'up' or 'down'; got {self.angle!r}"))
        if self.body != "explicit" and self.inertia_value is not None:
            problems.append(("inertia", f"given but body is {self.body!r} (use body='explicit')"))
        drive = sp.sympify(self.drive)
        _collect(problems, "drive", _check_time_expression, drive)
        if not any(key == "drive" for key, _ in problems):
            _collect(problems, "drive", check_cost, drive)
        if self.inertia_value is not None:
            inertia = sp.sympify(self.inertia_value)
            _collect(problems, "inertia", _positive_or_symbolic, inertia)
            if inertia.has(S.t):
                problems.append(("inertia", "may not depend on t"))
            _collect(problems, "inertia", _check_time_expression, inertia)
            if not any(key == "inertia" for key, _ in problems):
                _collect(problems, "inertia", _check_inertia_bound, inertia)
        if problems:
            raise ParameterError(problems)
        object.__setattr__(self, "drive", drive)

    # -- parameters ---------------------------------------------------------
    @property
    def coordinate(self):
        """The generalised coordinate theta(t)."""
        return S.theta(S.t)

    @property
    def inertia(self):
        """The body's moment of inertia about the pivot (an expression)."""
        if self.body == "explicit":
            return S.I if self.inertia_value is None else sp.sympify(self.inertia_value)
        return BODIES[self.body]

    @property
    def inertia_ratio(self):
        """I / (m l^2): 4/3 for a rod, 1 for a point mass."""
        return sp.simplify(self.inertia / (S.m * S.l**2))

    # -- mechanics ------------------------------------------------------------
    @property
    def centre_of_mass(self):
        """(x, y) of the centre of mass (000, lines after eq. 2)."""
        th = self.coordinate
        sign = 1 if self.angle == "up" else -1
        return S.l * sp.sin(th), self.drive + sign * S.l * sp.cos(th)

    @property
    def kinetic_energy(self):
        """T = m (x'^2 + y'^2)/2 + I0 theta'^2/2 with I0 = I - m l^2 (000 eq. 2)."""
        x, y = self.centre_of_mass
        th = self.coordinate
        i_cm = S.I - S.m * S.l**2
        return (S.m * (x.diff(S.t)**2 + y.diff(S.t)**2) / 2
                + i_cm * th.diff(S.t)**2 / 2)

    @property
    def potential_energy(self):
        """V = m g y (000, before the Lagrangian)."""
        return S.m * S.g * self.centre_of_mass[1]

    #: The undefined function that stands for the drive in :meth:`lagrangian_template`.
    DRIVE = sp.Function("_y0", real=True)(S.t)

    def lagrangian_template(self):
        """L = T - V with the drive kept as the undefined function :attr:`DRIVE`.

        sin^2 theta is written 1 - cos^2 theta and the result multiplied out,
        which cancels the m l^2 theta'^2 terms (000, the Lagrangian after
        eq. 2).  The work does not depend on the drive: put it in with
        :meth:`with_drive`.
        """
        template = DrivenPivot.__new__(DrivenPivot)
        for name in ("body", "angle", "inertia_value"):
            object.__setattr__(template, name, getattr(self, name))
        object.__setattr__(template, "drive", self.DRIVE)
        th = self.coordinate
        lag = sp.expand(template.kinetic_energy - template.potential_energy)
        return sp.expand(lag.subs(sp.sin(th)**2, 1 - sp.cos(th)**2))

    def with_drive(self, expr):
        """``expr`` (from :meth:`lagrangian_template`) with the scene's drive put in, multiplied out."""
        return sp.expand(expr.subs(self.DRIVE, self.drive).doit())

    @property
    def lagrangian(self):
        """L = T - V, simplified (000, the Lagrangian after eq. 2).

        The drive's own trigonometric terms are left as the user wrote them
        (only multiplied out); see :meth:`lagrangian_template`.
        """
        return self.with_drive(self.lagrangian_template())

    @property
    def inverted_position(self):
        """The value of theta at the inverted (upright) position."""
        return sp.Integer(0) if self.angle == "up" else sp.pi

    def describe(self):
        return {
            "system": self.name,
            "body": self.body,
            "angle_from": self.angle,
            "drive": self.drive,
            "I": self.inertia,
            "I_over_ml2": self.inertia_ratio,
        }


#: How far (in the scene's unit of time) a length that is not a polynomial is
#: scanned for a zero: 20000 samples of 0 < t <= 100.
LENGTH_SCAN_END = 100


def without_sine_squared(expr, angle):
    """``expr`` multiplied out with sin^2(angle) = 1 - cos^2(angle) put in (the one identity
    the variable length's Lagrangian and Newton projection need; SymPy's trigsimp and simplify
    find the same expressions, many times slower)."""
    return sp.expand(sp.expand(expr).subs(sp.sin(angle) ** 2, 1 - sp.cos(angle) ** 2))


def _first_zero(length):
    t = S.t
    written = length
    length = sp.expand(length)
    if not length.has(t):
        return None
    if length.is_polynomial(t):
        poly = sp.Poly(length, t)
        if poly.degree() <= 2:
            found = []
            for root in sp.solve(length, t):
                if root.is_positive:
                    found.append((root, True))
                elif root.is_real is not False and root.is_positive is None and root.free_symbols:
                    found.append((root, False))
            certain = [r for r, ok in found if ok and r.is_number]
            if certain:
                return min(certain, key=float), True
            return found[0] if found else None
        if not poly.free_symbols - {t} and poly.degree() <= 8:
            roots = [r for r in poly.real_roots() if r.is_positive]
            return (min(roots, key=float), True) if roots else None
        # higher degrees (t**999: exact real roots would take minutes) are scanned below
    # positive constant factors out (L0*(2 - exp(t)): L0 is, before expanding)
    const, rest = sp.factor_terms(written).as_independent(t, as_Add=False)
    if const.is_positive is not True:
        return None
    if rest.free_symbols != {t}:
        # one symbol r that enters only as r*t (L0*cos(omega*t)): scanned in u = r t, and the
        # time is u/r when r is positive
        others = rest.free_symbols - {t}
        if len(others) != 1:
            return None
        rate = others.pop()
        u = sp.Dummy("u", positive=True)
        scaled = rest.subs(t, u / rate)
        if scaled.has(rate):
            return None
        found = _first_zero(scaled.subs(u, t))
        if found is None or not isinstance(found[0], sp.Float):
            return None
        return found[0] / rate, False
    import numpy as np
    f = sp.lambdify(t, rest, "numpy")
    ts = np.linspace(0, LENGTH_SCAN_END, 20001)[1:]
    with np.errstate(all="ignore"):
        ys = np.broadcast_to(np.asarray(f(ts), dtype=float), ts.shape).copy()
    # a float that underflowed to 0 (exp(-10*t) past t = 74.5) is not a zero: each run of
    # 0.0 takes the sign of the expression at its first sample, evaluated at 30 digits
    zeros = np.nonzero(ys == 0)[0]
    starts = [int(k) for i, k in enumerate(zeros) if i == 0 or zeros[i - 1] != k - 1]
    for k in starts[:16]:
        sign = float(sp.sign(rest.evalf(30, subs={t: sp.Float(repr(float(ts[k])), 30)})))
        end = k
        while end < ys.size and ys[end] == 0:
            ys[end] = sign * 1e-300 if sign else 0.0
            end += 1
    if not np.all(np.isfinite(ys)):  # overflow or a pole: look only before it
        k = int(np.argmin(np.isfinite(ys)))
        ts, ys = ts[:k], ys[:k]
        if ts.size < 3:
            return None
    scale = abs(float(rest.subs(t, 0))) or 1.0  # |L(0)| / const, positive (checked before)
    mags = np.abs(ys)
    crossing = np.sign(ys[1:]) != np.sign(ys[:-1])
    # a zero it touches without crossing (1 + cos t): a strict interior minimum of |L| near 0
    touching = np.zeros_like(crossing)
    touching[1:] = ((mags[1:-1] < mags[:-2]) & (mags[1:-1] < mags[2:])
                    & (mags[1:-1] < 1e-4 * scale))
    for k in np.nonzero(crossing | touching)[0]:
        k = int(k)
        if not crossing[k]:
            return sp.Float(ts[k], 6), True
        lo, hi = float(ts[k]), float(ts[k + 1])
        for _ in range(60):
            mid = (lo + hi) / 2
            if np.sign(f(mid)) == np.sign(f(lo)):
                lo = mid
            else:
                hi = mid
        if abs(float(f(hi))) <= 1e-6 * scale:  # a zero, not a pole (3 + tan t changes sign at pi/2)
            return sp.Float(hi, 6), True
        # a pole: L is not finite there, and what comes after it (the zero of 1 + tan t at
        # 3 pi/4) is no length the string reaches
        return None
    return None


def length_zero_note(system):
    """One sentence stating where L(t) reaches zero (None when it does not, as far as known)."""
    found = system.length_zero
    if found is None:
        return None
    when, certain = found
    at = f"about t = {float(when):.6g}" if isinstance(when, sp.Float) else f"t = {sp.sstr(when)}"
    text = f"L(t) = {sp.sstr(system.length)} reaches zero at {at}"
    if not certain:
        text += " (when that is positive)"
    return text + ": the string has no length there, and the equations hold only before it"


@dataclass(frozen=True)
class VariableLength:
    """A point mass on a string of length L(t) (002).

    Parameters
    ----------
    length : sympy expression in t
        L(t); default L0 + v0 t (002, "Resolução").  Numbers in it must keep
        it positive at t = 0.
    mass : sympy expression
        The mass (the source takes m = 1; it cancels from the equation).

    The angle is measured from the downward vertical with the y axis pointing
    down (002, "Dedução").
    """

    length: sp.Expr = field(default_factory=lambda: S.L0 + S.v0 * S.t)
    mass: sp.Expr = S.m

    name = "variable-length"

    def __post_init__(self):
        problems = []  # (parameter, message)
        length = sp.sympify(self.length)
        _collect(problems, "length", _check_time_expression, length)
        at0 = length.subs(S.t, 0)
        if not problems:
            if length.has(sp.I):
                problems.append(("length", "must be real (I here is the imaginary unit sqrt(-1))"))
            elif (at0.is_number and not at0.is_positive) or at0.is_nonpositive:
                problems.append(("length", f"must be positive at t = 0, got {at0}"))
            else:
                _collect(problems, "length", check_cost, length)
        mass = sp.sympify(self.mass)
        _collect(problems, "mass", _positive_or_symbolic, mass)
        if mass.has(S.t) or _free_functions(mass):
            problems.append(("mass", "must be a constant (not a function of t): the "
                                     "Lagrangian used here holds for a constant mass only"))
        if problems:
            raise ParameterError(problems)
        object.__setattr__(self, "length", length)
        object.__setattr__(self, "mass", sp.sympify(self.mass))

    @property
    def coordinate(self):
        return S.theta(S.t)

    @property
    def position(self):
        """(x, y) of the mass, y pointing down (002, "posição")."""
        th = self.coordinate
        ell = S.L(S.t)
        return ell * sp.sin(th), ell * sp.cos(th)

    @property
    def kinetic_energy(self):
        x, y = self.position
        return self.mass * (x.diff(S.t)**2 + y.diff(S.t)**2) / 2

    @property
    def potential_energy(self):
        """V = -m g y (y points down)."""
        return -self.mass * S.g * self.position[1]

    @property
    def lagrangian(self):
        """L = T - V with the length kept as the function L(t), multiplied out with
        sin^2 theta = 1 - cos^2 theta put in (all that trigsimp found here, at a sixth of its cost)."""
        return without_sine_squared(self.kinetic_energy - self.potential_energy, self.coordinate)

    @property
    def length_zero(self):
        """The first time t > 0 at which L(t) = 0, as ``(t, certain)``; None if none is found.

        A polynomial length is solved exactly (degree <= 2, symbolic
        coefficients allowed) or by its real roots (numeric coefficients,
        degree <= 8);
        ``certain`` is False when the root is positive only for some values
        of the symbols.  Any other length whose only variable is t (after
        positive constant factors are taken out: L0*cos(t), L0*(2 - exp(t))) is scanned on
        0 < t <= :data:`LENGTH_SCAN_END` and the sign change refined by
        bisection (a float then); one with a single other symbol r that enters
        only as r*t (L0*cos(omega*t)) is scanned in r*t, and its time u/r is
        not certain (r may be negative).  A float that underflowed to 0.0 is
        not a zero, and a pole ends the scan (1 + tan t: no zero is claimed
        past pi/2).  Past the zero the string has no length: the equations
        hold only before it.
        """
        return _first_zero(self.length)

    @property
    def is_linear_length(self):
        """True when L(t) = c0 + c1 t with c1 != 0 (the source's case)."""
        p = sp.Poly(self.length, S.t) if self.length.is_polynomial(S.t) else None
        return p is not None and p.degree() == 1

    def describe(self):
        return {"system": self.name, "length": self.length, "mass": self.mass}
