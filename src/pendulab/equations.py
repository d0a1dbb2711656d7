"""Stage 2 (equations): Euler-Lagrange equations, normalised and linearised.

:func:`derive` takes a system from :mod:`pendulab.systems` and returns an
:class:`Equations` record.  Every expression is the left-hand side of
``expr = 0``.
"""

from dataclasses import dataclass, replace

import sympy as sp

from pendulab import symbols as S
from pendulab.systems import DrivenPivot, VariableLength, without_sine_squared
from pendulab.errors import InputError


#: omega0^2 = m g l / I, the natural frequency the source introduces in 000 eq. 3.
OMEGA0_SQUARED = S.m * S.g * S.l / S.I


def euler_lagrange(lagrangian, coordinate, time=S.t):
    """d/dt (dL/dq') - dL/dq for one coordinate q(t) (the Euler-Lagrange expression)."""
    qdot = coordinate.diff(time)
    return sp.expand(sp.diff(lagrangian, qdot).diff(time) - sp.diff(lagrangian, coordinate))


def linearise(expr, coordinate, about, time=S.t):
    """First-order part of ``expr`` in the deviation of ``coordinate`` from ``about``.

    ``coordinate`` -> ``about + eps*u`` and the eps-derivative at eps = 0 is
    taken; the deviation u is written back as the coordinate's own name, so
    the result reads as an equation for the small deviation.
    """
    eps = sp.Dummy("eps")
    u = sp.Function("u")(time)
    shifted = expr.subs(coordinate, about + eps * u).doit()
    first = sp.diff(shifted, eps).subs(eps, 0).doit()
    return sp.expand(first.subs(u, coordinate).doit())


def normalise(expr, coordinate, time=S.t):
    """Divide ``expr`` by the coefficient of the coordinate's second derivative.

    The coefficient is simplified (unless it is a single symbol, as the
    inertia I of the driven pivot is); the quotient is only multiplied out (no
    ``simplify`` of the whole equation, whose cost grows with the drive).
    """
    acc = coordinate.diff(time, 2)
    coeff = sp.expand(expr).coeff(acc)
    if not coeff.is_Atom:
        coeff = sp.simplify(coeff)
    if coeff == 0:
        raise InputError("the equation has no second derivative of the coordinate")
    return sp.expand(sp.expand(expr) / coeff)


@dataclass(frozen=True)
class Equations:
    """The equations of motion of a system (each entry: left side of ``= 0``).

    * ``lagrangian`` - T - V;
    * ``euler_lagrange`` - d/dt dL/dq' - dL/dq as SymPy forms it;
    * ``source_form`` - the source's grouping: (I/(m l)) theta'' - (y0'' + g)
      sin theta (000, before eq. 3) or L theta'' + 2 L' theta' + g sin theta
      (002 eq. 3, with L = L(t));
    * ``eom`` - for the driven pivot normalised (theta'' has coefficient 1)
      with omega0^2 = m g l/I introduced (000 eq. 3); for the variable length
      the source form with the scene's L(t) written out;
    * ``linear`` - linearised about the inverted position (000 eq. 4) or about
      the hanging rest position (002 eq. 4);
    * ``newton`` - variable length only: the source's Newton projection
      (002 eqs. 1-2), for comparison.
    """

    system: object
    lagrangian: sp.Expr
    euler_lagrange: sp.Expr
    source_form: sp.Expr
    eom: sp.Expr
    linear: sp.Expr
    linear_about: sp.Expr
    newton: sp.Expr = None

    def _repr_latex_(self):
        """The Lagrangian, the equation of motion and its linearisation as one ``align*``
        (a notebook shows it typeset), long sums broken by the products' printer
        (:func:`pendulab.latex.sum_rows`)."""
        from pendulab.latex import align, sum_rows, text
        rows = [r"&" + text("Lagrangian T - V:")] + sum_rows(r"\mathcal{L}", self.lagrangian)
        if self.newton is None:  # the driven pivot (000 eqs. 2-4)
            rows += [r"&" + text("equation of motion (000 eq. 3):")] + sum_rows("", self.eom, 0)
            rows.append(r"\omega_0^2 &= " + sp.latex(OMEGA0_SQUARED))
        else:  # the variable length (002 eqs. 3-4)
            rows += [r"&" + text("equation of motion (002 eq. 3):")] + sum_rows("", self.eom, 0)
        rows += [r"&" + text("linearised about ") + r"\theta = " + sp.latex(self.linear_about)
                 + ":"] + sum_rows("", self.linear, 0)
        return align(rows)


def g_of_omega0():
    """g solved from omega0^2 = m g l / I (000 eq. 3).

    The relation is linear in g with a slope free of g, so g = omega0^2 / slope
    (what ``sp.solve`` gives, 100 times faster: solve simplifies, and its first
    simplify imports sympy.physics.units).
    """
    slope = sp.diff(OMEGA0_SQUARED, S.g)
    if slope.has(S.g) or sp.expand(OMEGA0_SQUARED - slope * S.g) != 0:
        raise InputError("omega0^2 is not linear in g")  # pragma: no cover - a fixed relation
    return S.omega0**2 / slope


def _derive_driven_pivot(system):
    th = system.coordinate
    # Derived with the drive as an undefined function, then the drive put in: the cost
    # of the derivatives does not grow with the drive's harmonics (y0'^2 has N^2 terms).
    template = system.lagrangian_template()
    lag = system.with_drive(template)
    el = system.with_drive(euler_lagrange(template, th))
    source_form = sp.expand(el / (S.m * S.l))
    # 000 eq. 3: normalise and trade g for omega0^2 = m g l / I.
    eom = normalise(el, th)
    eom = sp.expand(eom.subs(S.g, g_of_omega0()))
    eom = sp.collect(eom, sp.sin(th))
    about = system.inverted_position
    linear = linearise(eom, th, about)
    linear = sp.collect(linear, th)
    return Equations(system, lag, el, source_form, eom, linear, about)


def newton_projection(mass=S.m):
    """The source's Newton route for the variable length (002 eqs. 1-2).

    Differentiates the position twice (002 eq. 1) and projects m a - P on the
    unit vector (cos theta, -sin theta) normal to the string (002 eq. 2),
    divided by m: x'' cos theta - y'' sin theta + g sin theta, expanded, with
    sin^2 theta = 1 - cos^2 theta put in (the only identity the projection
    needs; SymPy's simplify finds the same expression 30 times slower).
    """
    th = S.theta(S.t)
    ell = S.L(S.t)
    x, y = ell * sp.sin(th), ell * sp.cos(th)
    # d/dt of the velocities, which the kinetic energy formed (SymPy's cache): half the cost of diff(t, 2)
    ax, ay = x.diff(S.t).diff(S.t), y.diff(S.t).diff(S.t)
    return without_sine_squared(ax * sp.cos(th) - ay * sp.sin(th) + S.g * sp.sin(th), th)


def _derive_variable_length(system):
    th = system.coordinate
    lag = system.lagrangian
    el = euler_lagrange(lag, th)
    ell = S.L(S.t)
    source_form = sp.expand(sp.cancel(el / (system.mass * ell)))
    eom = sp.expand(source_form.subs(ell, system.length).doit())
    linear = sp.expand(linearise(source_form, th, 0))
    return Equations(system, lag, el, source_form, eom, linear, sp.Integer(0),
                     newton=sp.expand(newton_projection()))


def derive(system):
    """Euler-Lagrange equations of ``system`` (a DrivenPivot or VariableLength).

    Each derivation is done once per process and then shared (the record is
    immutable): for the driven pivot the equations depend on the drive and the
    angle only, since the moment of inertia stays the symbol I (the body's
    value enters where a product substitutes it), so the rod, the point mass
    and the generic body of the analyses (phelps_hunter, averaging) share one
    derivation; the record returned names the ``system`` asked for.
    """
    eqs = _derive_once(derivation_key(system), system)
    return eqs if eqs.system == system else replace(eqs, system=system)


def derivation_key(system):
    """What the equations of ``system`` depend on: (class, drive, angle) or (class, length, mass)."""
    if isinstance(system, DrivenPivot):
        return (DrivenPivot, system.drive, system.angle)
    if isinstance(system, VariableLength):
        return (VariableLength, system.length, system.mass)
    raise InputError(f"unknown system {system!r}")


_DERIVED = {}
#: Derivations kept per process (the oldest is dropped beyond this many).
MAX_CACHED = 32


def _derive_once(key, system):
    """The derivation for ``key``, computed by the first ``system`` that has it."""
    if key not in _DERIVED:
        run = _derive_driven_pivot if key[0] is DrivenPivot else _derive_variable_length
        eqs = run(system)
        if len(_DERIVED) >= MAX_CACHED:
            _DERIVED.pop(next(iter(_DERIVED)))
        _DERIVED[key] = eqs
    return _DERIVED[key]
