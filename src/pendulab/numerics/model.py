"""The numerics stage, step 1: first-order systems read from the derivation.

Everything the integrators, code generators and Floquet maps run is built
here from the equations stage (:mod:`pendulab.equations`) and the canonical
stage (:mod:`pendulab.canonical`); no equation of the sources is typed in.

Driven pivot (000_8cba66c4fdf94ac6.txt).  The normalised equation of motion
theta''(t) + F(t, theta, theta') = 0 (000 eq. 3, as derived) is taken to the
source's dimensionless time tau = Omega t / 2 (000, before eq. 5; Omega is the
drive's fundamental frequency found by the canonical stage), so that with
Theta(tau) = theta(t)

    Theta'' = -(4/Omega^2) F(2 tau/Omega, Theta, (Omega/2) Theta').

The moment of inertia is the body's (``system.inertia``), and the physical
symbols are then traded for the dimensionless groups the source states its
results in (000 eqs. 12, 19, 28): a = (a/l) l, omega0 = (omega0/omega) omega,
and I = (I/(m l^2)) m l^2 when I is still a symbol.  For the source's drive
every other symbol cancels and the right-hand side depends on tau, the state
and (a_over_l, w0_over_w) only.  Numbers given by a scene for the remaining
symbols are substituted exactly (as SymPy numbers).

Variable length (002_19b336b29bb1f03b.txt).  The equation L theta'' + 2 L'
theta' + g sin theta = 0 (002 eq. 3, derived from the Lagrangian) with the
scene's L(t) written out, in the time t.

The state is always (theta, dtheta) with dtheta the derivative in the
system's own time variable (tau or t).
"""

from dataclasses import dataclass, field

import sympy as sp

from pendulab import symbols as S
from pendulab.errors import InputError

#: The state symbols of every first-order system: the angle and its rate.
THETA = sp.Symbol("theta", real=True)
DTHETA = sp.Symbol("dtheta", real=True)
STATES = (THETA, DTHETA)


@dataclass(frozen=True)
class FirstOrderSystem:
    """y' = f(time, y, p) with y = (theta, dtheta), read from a derivation.

    * ``time`` - the independent variable (``tau`` for the driven pivot,
      ``t`` for the variable length);
    * ``states`` - (theta, dtheta), dtheta = d theta / d time;
    * ``params`` - the parameter symbols, in the order every generated
      function takes them (sorted by name);
    * ``rhs`` - (dtheta, theta'') of the full nonlinear equation;
    * ``linear_rhs`` - the same for the equation linearised about
      ``about`` (the inverted position for the pivot, 000 eq. 4; the hanging
      rest position for the string, 002 eq. 4), written in the deviation;
    * ``period`` - the period in ``time`` of the coefficients, or None
      (pi in tau for Mathieu's equation, 2 pi for a Hill drive with odd
      harmonics; None for a non-periodic length);
    * ``kind`` - the canonical stage's verdict ("mathieu", "hill",
      "linear" for the pivot; "bessel" or "general" for the string);
    * ``note`` - what was substituted, for banners and docs.
    """

    name: str
    time: sp.Symbol
    states: tuple
    params: tuple
    rhs: tuple
    linear_rhs: tuple
    about: sp.Expr
    period: sp.Expr = None
    kind: str = ""
    note: str = ""
    values: dict = field(default_factory=dict)

    def jacobian(self, linear=False):
        """d f / d y as a 2 x 2 SymPy Matrix (rows: f components, columns: theta, dtheta)."""
        f = sp.Matrix(self.linear_rhs if linear else self.rhs)
        return f.jacobian(sp.Matrix(self.states))

    def linear_matrix(self):
        """A(time, p) with linear_rhs = A y (2 x 2; the monodromy maps integrate Y' = A Y)."""
        return self.jacobian(linear=True)

    def lambdified(self, linear=False):
        """The derivation itself as a NumPy function f(time, y, p) -> (2, ...) array.

        ``y`` has shape (2, ...) and ``p`` shape (len(params), ...); this is the
        reference every generated or hand-written kernel is tested against.
        """
        import numpy as np
        args = (self.time, self.states, self.params)
        # NumPy as a module, not the name "numpy": the same printer and functions, without
        # ``from numpy import *``, which imports f2py, random, ... (0.15 s on first use)
        fn = sp.lambdify(args, list(self.linear_rhs if linear else self.rhs), np)

        def f(time, y, p=()):
            out = fn(time, tuple(y), tuple(p))
            shape = np.broadcast_shapes(*(np.shape(v) for v in out))
            return np.stack([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in out])
        return f


def _state_form(expr, coordinate, time):
    """Replace theta(time), theta'(time) by the state symbols in ``expr``."""
    return expr.subs({coordinate.diff(time): DTHETA}).subs({coordinate: THETA})


def _numbers(values, exprs=(), where="values"):
    """{Symbol: exact SymPy number} from {name or Symbol: number or expression}.

    A name is matched to the symbol of that name in ``exprs`` (the scene's
    own symbols are real, pendulab's physical ones positive), then to
    pendulab's symbols, then taken as a real symbol.
    """
    own = {s.name: s for e in exprs for s in sp.sympify(e).free_symbols}
    out = {}
    for key, value in (values or {}).items():
        name = key.name if isinstance(key, sp.Symbol) else str(key)
        sym = own.get(name) or S.NAMESPACE.get(name) or sp.Symbol(name, real=True)
        num = sp.nsimplify(value) if isinstance(value, float) else sp.sympify(value)
        if not (num.is_number and num.is_real and num.is_finite):
            raise InputError(f"{where}.{sym}: must be a finite real number, got {value!r}")
        out[sym] = num
    return out


def _physical(nums, inertia):
    """With g among the numbers, omega0 follows from its definition (000 eq. 3)."""
    from pendulab.equations import OMEGA0_SQUARED
    if S.g in nums and S.omega0 not in nums:
        return {S.omega0: sp.sqrt(OMEGA0_SQUARED.subs(S.I, inertia))}
    return {}


def _dimensionless_groups(inertia_symbolic):
    groups = {S.a: S.a_over_l * S.l, S.omega0: S.w0_over_w * S.omega}
    if inertia_symbolic:
        groups[S.I] = S.inertia_ratio * S.m * S.l**2
    return groups


#: pivot_system's results in this process, by what they depend on (see there)
_PIVOT = {}


def pivot_system(equations, form, values=None, groups=True):
    """The driven pivot as a first-order system in tau (see the module docstring).

    ``equations`` is the equations stage of a :class:`~pendulab.systems.DrivenPivot`,
    ``form`` its canonical stage (:func:`pendulab.canonical.periodic_form`).
    ``values`` maps symbol names to numbers substituted after the groups
    (e.g. ``{"l": 0.05}``); ``groups=False`` keeps the physical symbols.
    Made once per process for each derivation, body inertia, values and
    groups (the final simplify, :func:`_tidy`, was most of a build's symbolic work here): the
    same record is returned again.

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import DrivenPivot
    >>> from pendulab.canonical import periodic_form
    >>> eqs = derive(DrivenPivot(body="rod"))
    >>> fos = pivot_system(eqs, periodic_form(eqs))
    >>> pivot_system(derive(DrivenPivot(body="rod")), periodic_form(eqs)) is fos
    True
    >>> fos.params
    (a_over_l, w0_over_w)
    >>> fos.linear_rhs[1]
    theta*(-3*a_over_l*cos(2*tau) + 4*w0_over_w**2)
    """
    from pendulab.equations import MAX_CACHED, derivation_key
    # the equations depend on the derivation key only, the form on the equations; the body
    # enters through its inertia: the rod's kernels, sweeps and Floquet product share one
    key = (derivation_key(equations.system), sp.srepr(sp.sympify(equations.system.inertia)),
           repr(form.frequency), repr(sorted((values or {}).items(), key=repr)), groups)
    if key in _PIVOT and _PIVOT[key][0] == equations.eom and _PIVOT[key][1] == form:
        return _PIVOT[key][2]
    out = _pivot_system(equations, form, values, groups)
    if len(_PIVOT) >= MAX_CACHED:
        _PIVOT.pop(next(iter(_PIVOT)))
    _PIVOT[key] = (equations.eom, form, out)
    return out


def _tidy(expr):
    """simplify(expr) for a right-hand side of the driven pivot, by cancel and factor_terms where they do.

    Where the expression's numbers are rationals and its only functions sines
    and cosines of distinct angles, each of degree at most 1 in the cancelled
    fraction (the drive a cos(omega t) of the scenes: a rational function of the
    symbols times sin(theta) or theta, linear in cos(2 tau)), the cancelled
    fraction with the common factors of its terms taken out is what simplify
    gives, and it is formed here without simplify's trigonometric search (0.1 s
    per process).  tests/test_numerics_model.py compares the two by srepr for
    the scenes' drives and others; whatever else (Floats, pi, sin^2 + cos^2, other
    functions) goes through simplify.
    """
    trig = expr.atoms(sp.Function)
    if (expr.has(sp.Float, sp.NumberSymbol, sp.I)
            or any(not isinstance(f, (sp.sin, sp.cos)) for f in trig)
            or len({f.args[0] for f in trig}) != len(trig)):
        return sp.simplify(expr)
    fraction = sp.cancel(expr)
    if any(sp.degree(part, f) > 1 for part in sp.fraction(fraction) for f in trig):
        return sp.simplify(expr)
    return sp.factor_terms(fraction)


def _pivot_system(equations, form, values, groups):
    system = equations.system
    th = system.coordinate
    acc = th.diff(S.t, 2)
    eom = sp.expand(equations.eom)
    if sp.simplify(eom.coeff(acc) - 1) != 0:
        raise InputError("the equation of motion is not normalised (theta'' coefficient 1)")
    freq = form.frequency if form.frequency is not None else S.omega
    inertia = sp.sympify(system.inertia)
    out = []
    for expr in (eom, equations.linear):
        rest = sp.expand(expr) - acc
        # d/dt = (Omega/2) d/dtau: theta' = (Omega/2) dtheta, theta'' = (Omega/2)^2 Theta''.
        rest = _state_form(rest, th, S.t).subs(DTHETA, freq * DTHETA / 2)
        rest = rest.subs(S.t, 2 * S.tau / freq)
        second = -4 * rest / freq**2
        out.append(second.subs(S.I, inertia))
    note = f"tau = ({freq}) t/2; I = {inertia}"
    if groups:
        sub = _dimensionless_groups(inertia.has(S.I))
        out = [e.subs(sub) for e in out]
        note += "; a = a_over_l*l, omega0 = w0_over_w*omega" + (
            ", I = inertia_ratio*m*l**2" if inertia.has(S.I) else "")
    nums = _numbers(values, out)
    if nums:
        out = [e.subs(_physical(nums, inertia)).subs(nums) for e in out]
    out = [_tidy(e) for e in out]
    params = tuple(sorted(set().union(*(e.free_symbols for e in out)) - {S.tau, *STATES},
                          key=lambda s: s.name))
    about = system.inverted_position
    return FirstOrderSystem("kapitza", S.tau, STATES, params, (DTHETA, out[0]), (DTHETA, out[1]),
                            about, period=form.period, kind=form.kind, note=note, values=nums)


def length_system(equations, values=None):
    """The variable-length pendulum as a first-order system in t (002 eqs. 3-4).

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import VariableLength
    >>> fos = length_system(derive(VariableLength()))
    >>> fos.params
    (L0, g, v0)
    >>> fos.rhs[1]
    -(2*dtheta*v0 + g*sin(theta))/(L0 + t*v0)
    """
    system = equations.system
    th = system.coordinate
    acc = th.diff(S.t, 2)
    length = system.length
    out = []
    for expr in (equations.eom, equations.linear):
        expr = sp.expand(expr.subs(S.L(S.t), length).doit())
        lead = sp.simplify(expr.coeff(acc))
        if lead == 0:
            raise InputError("the variable-length equation has no second derivative")
        rest = sp.expand(expr - lead * acc)
        out.append(sp.simplify(-_state_form(rest, th, S.t) / lead))
    nums = _numbers(values, out)
    if nums:
        out = [sp.simplify(e.subs(nums)) for e in out]
    params = tuple(sorted(set().union(*(e.free_symbols for e in out)) - {S.t, *STATES},
                          key=lambda s: s.name))
    from pendulab.canonical import fundamental_frequency
    freq = fundamental_frequency(length)
    period = None if freq is None else sp.simplify(2 * sp.pi / freq)
    kind = "bessel" if system.is_linear_length else "general"
    return FirstOrderSystem("variable-length", S.t, STATES, params, (DTHETA, out[0]),
                            (DTHETA, out[1]), sp.Integer(0), period=period, kind=kind,
                            note=f"L(t) = {length}", values=nums)


@dataclass(frozen=True)
class Geometry:
    """Where the parts of a pendulum are, as expressions in the system's time and THETA.

    ``pivot`` and ``mass`` are (x, y) pairs with y pointing up: the pivot and
    the centre of mass (the driven pivot, over l, in tau, with the groups of
    :func:`pivot_system`) or the suspension point and the mass (the string,
    in metres, in t).  ``params`` are the symbols left in them, sorted by name.
    """

    time: sp.Symbol
    pivot: tuple
    mass: tuple
    params: tuple


def pivot_geometry(equations, form):
    """The driven pivot's :class:`Geometry`, read from the system's centre of mass and drive.

    The coordinates are the ones the Lagrangian is built from (000, after
    eq. 2), taken to tau = Omega t/2 and divided by l:

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import DrivenPivot
    >>> from pendulab.canonical import periodic_form
    >>> eqs = derive(DrivenPivot(body="rod"))
    >>> geo = pivot_geometry(eqs, periodic_form(eqs))
    >>> geo.pivot, geo.mass
    ((0, a_over_l*cos(2*tau)), (sin(theta), a_over_l*cos(2*tau) + cos(theta)))
    """
    system = equations.system
    freq = form.frequency if form.frequency is not None else S.omega
    sub = _dimensionless_groups(False)

    def scaled(expr):
        expr = sp.sympify(expr).xreplace({system.coordinate: THETA}).subs(S.t, 2 * S.tau / freq)
        return sp.simplify(sp.expand(expr.subs(sub) / S.l))

    pivot = (sp.Integer(0), scaled(system.drive))
    mass = tuple(scaled(c) for c in system.centre_of_mass)
    params = tuple(sorted(set().union(*(e.free_symbols for e in pivot + mass))
                          - {S.tau, THETA}, key=lambda s: s.name))
    return Geometry(S.tau, pivot, mass, params)


def length_geometry(equations):
    """The string's :class:`Geometry` (002, "posição", y turned to point up), with L(t) put in.

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import VariableLength
    >>> length_geometry(derive(VariableLength())).mass
    ((L0 + t*v0)*sin(theta), -(L0 + t*v0)*cos(theta))
    """
    system = equations.system
    x, y = system.position
    mass = tuple(sp.expand(c.subs(S.L(S.t), system.length).xreplace({system.coordinate: THETA}))
                 for c in (x, -y))
    mass = tuple(sp.factor_terms(c) for c in mass)
    params = tuple(sorted(set().union(*(e.free_symbols for e in mass)) - {S.t, THETA},
                          key=lambda s: s.name))
    return Geometry(S.t, (sp.Integer(0), sp.Integer(0)), mass, params)


def first_order(ctx, values=None, groups=True):
    """The first-order system of a scene's pipeline context (reads its stages)."""
    if ctx.scene.system == "kapitza":
        return pivot_system(ctx.get("equations"), ctx.get("canonical"), values=values, groups=groups)
    return length_system(ctx.get("equations"), values=values)


def mathieu_parameters(equations, form, values=None, groups=True):
    """(theta0, theta1) of the canonical stage in the dimensionless groups (000 eqs. 5-6).

    Read from ``form`` (the Mathieu form the canonical stage found) with the
    body's inertia and the substitutions of :func:`pivot_system`; refuses a
    drive whose canonical form is not Mathieu's (a Hill drive has no single
    theta1).

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import DrivenPivot
    >>> from pendulab.canonical import periodic_form
    >>> eqs = derive(DrivenPivot(body="rod"))
    >>> mathieu_parameters(eqs, periodic_form(eqs))
    (-4*w0_over_w**2, 3*a_over_l/2)

    The source's Fig. 2 pendulum (000 sec. 4: a rod 10 cm long, so l = 5 cm;
    pivot amplitude 6 mm at 86 Hz) in SI units:

    >>> th0, th1 = mathieu_parameters(eqs, periodic_form(eqs), groups=False,
    ...     values={"l": "1/20", "a": "3/500", "omega": "2*pi*86", "g": "9.81"})
    >>> round(float(th0), 6), round(float(th1), 6)
    (-0.002016, 0.18)
    """
    if form.kind != "mathieu":
        raise InputError(f"the drive gives a {form.kind} equation, not Mathieu's: it has no "
                         "single (theta0, theta1)" + (f" ({form.note})" if form.note else ""))
    inertia = sp.sympify(equations.system.inertia)
    pair = [sp.sympify(v).subs(S.I, inertia) for v in (form.theta0, form.theta1)]
    if groups:
        sub = _dimensionless_groups(inertia.has(S.I))
        pair = [v.subs(sub) for v in pair]
    nums = _numbers(values, pair)
    return tuple(sp.simplify(v.subs(_physical(nums, inertia)).subs(nums)) for v in pair)
