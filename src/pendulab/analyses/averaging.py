"""Butikov's averaging (000 sec. 2.3, eqs. 13-19), derived for a physical pendulum.

The angle is split into a slow part and a small fast part, theta = psi + delta
(000 eq. 13), and the torques are averaged over one drive period 2 pi/omega
with psi held fixed.  Everything is formed by SymPy:

* the torques are read from the Euler-Lagrange equation of the driven pivot
  (the equations stage): I theta'' = m l y0'' sin theta + m g l sin theta, so
  the inertial torque is m l y0'' sin theta = -m a l omega^2 cos(omega t) sin theta
  and the gravitational one m g l sin theta (both positive when they increase
  theta);
* the fast part is the zero-mean periodic solution of I delta'' = (inertial
  torque at theta = psi): delta = (m a l/I) sin psi cos(omega t);
* sin theta ~ sin psi + delta cos psi (000 eq. 15) comes from the series of
  sin(psi + delta) to first order in delta;
* the averages are integrals over one period.

``inertia="source"`` follows the source's steps instead: its eq. 14 (the
inertial torque with the opposite sign convention, -m y0'' l sin theta) and its
eq. 13 (delta = -(a/l) sin psi cos(omega t)), whose amplitude a/l is the
point-mass amplitude m a l/(m l^2).  The two sign flips cancel in the average,
the amplitude does not: for a physical pendulum the source's eq. 19 carries
sqrt(I/(m l^2)) where the derivation gives I/(m l^2).  Kapitza's effective
potential (Landau & Lifshitz, Mechanics, sec. 30: U_eff = U + <f^2>/(2 I omega^2)
for a coordinate with kinetic energy I theta'^2/2) gives the same corrected
torques without any assumption about delta; the exact Floquet lower limit
(:func:`pendulab.analyses.phelps_hunter.lower_limit_small_ratio`) decides.

>>> lower_bound_source()
sqrt(2)*sqrt(inertia_ratio)*w0_over_w
>>> lower_bound_physical()
sqrt(2)*inertia_ratio*w0_over_w
"""

import functools

import sympy as sp

from pendulab import symbols as S
from pendulab.analyses.phelps_hunter import (
    a_over_l, inertia_ratio, quadratic_root, to_dimensionless, w0_over_w,
)
from pendulab.errors import InputError
from pendulab.systems import BODIES

#: The slow angle psi of 000 eq. 13.
psi = S.psi
#: The fast deviation delta of 000 eq. 13.
delta = S.delta
#: A frozen value of the angle theta (the coordinate theta(t) with t held).
_theta = sp.Symbol("theta_", real=True)

#: The moments of inertia of the bodies by name: the systems' own table (one road).
_BODIES = BODIES


def _inertia(inertia):
    """Resolve the ``inertia`` argument: "source", "I", "point", "rod" or an expression."""
    if isinstance(inertia, str):
        if inertia == "source":
            return "source"
        if inertia in _BODIES:
            return _BODIES[inertia]
        from pendulab.exprs import parse
        value = parse(inertia)
    else:
        value = sp.sympify(inertia)
    if value.has(S.t) or value.has(psi) or value.has(S.omega):
        raise InputError(f"inertia must be a constant moment of inertia, got {value}")
    if value.is_positive is False or value.is_zero:
        raise InputError(f"inertia must be positive, got {value}")
    return value


def _is_zero(expr):
    """True when ``expr`` is 0: expanded first (a sum of trigonometric monomials here
    cancels term by term), simplified only if that leaves something."""
    return sp.expand(expr) == 0 or sp.simplify(expr) == 0


@functools.lru_cache(maxsize=None)
def _lagrangian_torques():
    """(inertial, gravitational) torques on theta from the Euler-Lagrange equation.

    The equation of the driven pivot (moment of inertia I, drive a cos omega t,
    000 eq. 1) is I theta'' - (torques) = 0; the torques are split into the
    part with g and the rest.  theta(t) is replaced by a plain symbol.
    """
    from pendulab.equations import derive
    from pendulab.systems import DrivenPivot

    system = DrivenPivot(body="explicit")
    el = derive(system).euler_lagrange
    th = system.coordinate
    acc = th.diff(S.t, 2)
    coefficient = sp.expand(el).coeff(acc)
    if not _is_zero(coefficient - S.I):  # pragma: no cover
        raise RuntimeError(f"Euler-Lagrange expression has {coefficient} theta'', expected I theta''")
    torque = sp.expand(-(el - coefficient * acc)).subs(th, _theta).doit()
    gravitational = sp.expand(torque).coeff(S.g) * S.g
    # each part is one product of symbols, a sine and a cosine, which simplify gives back as
    # it is: expanded, not simplified (tests/test_averaging.py checks that simplify leaves both)
    return sp.expand(torque - gravitational), gravitational


def _source_inertial_torque():
    """000 eq. 14 as the source sets it up: tau_i = (-m y0'') l sin theta, y0 = a cos omega t."""
    y0 = S.a * sp.cos(S.omega * S.t)  # 000 eq. 1
    return -S.m * sp.diff(y0, S.t, 2) * S.l * sp.sin(_theta)


def fast_displacement(inertia="I"):
    """The fast part delta of theta = psi + delta (000 eq. 13).

    ``"source"``: the source's postulate -(a/l) sin psi cos omega t.  Otherwise
    the zero-mean periodic solution of I delta'' = (inertial torque at psi),
    found with an ansatz A cos omega t + B sin omega t.
    """
    value = _inertia(inertia)
    if value == "source":
        return -(S.a / S.l) * sp.sin(psi) * sp.cos(S.omega * S.t)  # 000 eq. 13 as printed
    inertial, _ = _lagrangian_torques()
    fast_torque = inertial.subs(_theta, psi)
    A, B = sp.symbols("A_ B_")
    trial = A * sp.cos(S.omega * S.t) + B * sp.sin(S.omega * S.t)
    residual = sp.expand(value * sp.diff(trial, S.t, 2) - fast_torque)
    equations = [residual.coeff(sp.cos(S.omega * S.t)), residual.coeff(sp.sin(S.omega * S.t))]
    solution = sp.solve(equations, [A, B], dict=True)[0]
    result = trial.subs(solution)
    if not _is_zero(value * sp.diff(result, S.t, 2) - fast_torque):  # pragma: no cover
        raise RuntimeError("fast displacement does not solve I delta'' = fast torque")
    return result


@functools.lru_cache(maxsize=None)
def sin_split():
    """sin(psi + delta) to first order in delta (000 eq. 15), from its series."""
    eps = sp.Symbol("eps")
    f = sp.sin(psi + eps * delta)
    # its Taylor polynomial f(0) + f'(0) eps, the derivative formed by SymPy
    return (f.subs(eps, 0) + sp.diff(f, eps).subs(eps, 0) * eps).subs(eps, 1)


def period_average(expr):
    """<f> = (1/T) int_0^T f dt with T = 2 pi/omega (000, footnote 1 of sec. 2.3)."""
    return sp.simplify(_mean(expr))


def _mean(expr):
    """The period mean of :func:`period_average`, not simplified.

    A polynomial in cos(omega t), sin(omega t) (every torque here) is a Laurent
    polynomial in z = e^{i omega t}; its mean over a period is the z^0 coefficient
    (the mean of e^{i k omega t} is 0 for k != 0).  Anything else is integrated."""
    z = sp.Symbol("z_", positive=True)
    wt = S.omega * S.t
    e = sp.expand(sp.expand(expr).subs({sp.cos(wt): (z + 1 / z) / 2,
                                        sp.sin(wt): (z - 1 / z) / (2 * sp.I)}))
    if not e.has(S.t):
        return sp.Add(*[term for term in sp.Add.make_args(e) if not term.has(z)])
    period = 2 * sp.pi / S.omega
    return sp.integrate(sp.expand(expr), (S.t, 0, period)) / period


@functools.lru_cache(maxsize=None)
def _instantaneous(inertia):
    """(delta, tau_i, tau_g): the fast part and the torques with sin(psi + delta) split, before averaging."""
    value = _inertia(inertia)
    inertial, gravitational = _lagrangian_torques()
    if value == "source":
        inertial = _source_inertial_torque()
    d = fast_displacement(inertia)
    split = sin_split().subs(delta, d)
    tau_i = inertial.subs(sp.sin(_theta), split)
    tau_g = gravitational.subs(sp.sin(_theta), split)
    if tau_i.has(_theta) or tau_g.has(_theta):  # pragma: no cover
        raise RuntimeError("torques depend on theta other than through sin(theta)")
    return d, tau_i, tau_g


@functools.lru_cache(maxsize=None)
def _averaged(inertia):
    d, tau_i, tau_g = _instantaneous(inertia)
    return {
        "delta": d,
        "inertial_instantaneous": sp.expand(tau_i),
        "gravitational_instantaneous": sp.expand(tau_g),
        "inertial": sp.factor(sp.trigsimp(_mean(tau_i))),
        "gravitational": sp.factor(sp.trigsimp(_mean(tau_g))),
    }


def averaged_torques(inertia="I"):
    """Torques averaged over a drive period with psi fixed (000 eqs. 14-17).

    ``inertia``: "I" (the symbol, a general physical pendulum; default),
    "point", "rod", an expression for the moment of inertia about the pivot, or
    "source" to follow the source's eqs. 13-14 as printed.  Returns a dict with
    "delta" (the fast part), "inertial" (<tau_i>), "gravitational" (<tau_g>)
    and the instantaneous torques before averaging.

    >>> averaged_torques("point")["inertial"]
    -a**2*m*omega**2*sin(2*psi)/4
    """
    key = inertia if isinstance(inertia, str) else sp.sympify(inertia)
    return dict(_averaged(key))


def averaged_potentials(inertia="I"):
    """Potentials of the averaged torques, U = -int <tau> dpsi (000, end of sec. 2.3).

    >>> averaged_potentials("source")["inertial"]
    -a**2*m*omega**2*cos(2*psi)/8
    """
    torques = averaged_torques(inertia)
    u_i = -sp.integrate(torques["inertial"], psi)
    u_g = -sp.integrate(torques["gravitational"], psi)
    return {"inertial": sp.factor(u_i), "gravitational": sp.factor(u_g)}


@functools.lru_cache(maxsize=None)
def effective_potential():
    """Kapitza's effective potential for the physical pendulum (Landau & Lifshitz sec. 30).

    U_eff = U + <f^2>/(2 I omega^2), with U the psi-dependent part of the
    pendulum's potential energy (the systems stage) and f the fast torque at
    theta = psi.  Needs no postulate for delta.

    >>> effective_potential()
    g*l*m*cos(psi) + a**2*l**2*m**2*omega**2*sin(psi)**2/(4*I)
    """
    from pendulab.systems import DrivenPivot

    system = DrivenPivot(body="explicit")
    V = system.potential_energy.subs(system.coordinate, psi)
    U = sp.expand(V) - sp.expand(V).as_independent(psi, as_Add=True)[0]
    inertial, _ = _lagrangian_torques()
    fast = inertial.subs(_theta, psi)
    return sp.expand(U + period_average(fast**2) / (2 * S.I * S.omega**2))


def _ratio_at_small_psi(inertia):
    """|<tau_i>|/|<tau_g>| as psi -> 0 (the left side of 000 eq. 18 over the right)."""
    torques = averaged_torques(inertia)
    return sp.simplify(sp.limit(-torques["inertial"] / torques["gravitational"], psi, 0))


@functools.lru_cache(maxsize=None)
def _g_from_omega0():
    """g from the source's definition omega0^2 = m g l/I (000, after eq. 3)."""
    (g,) = sp.solve(sp.Eq(S.omega0**2, S.m * S.g * S.l / S.I), S.g)
    return g


def _small_psi_ratio(inertia):
    """:func:`_ratio_at_small_psi` without trigsimp, limit or simplify (the lower bounds' route).

    The means of the torques are polynomials in sin(psi), cos(psi); their ratio,
    cancelled as a rational function of those, is continuous at psi = 0 when its
    denominator does not vanish there, and then its value at psi = 0 is the limit.
    Otherwise (not the case for these torques) the limit is taken.  The bounds are
    the same expressions (tests/test_averaging.py compares them with this route's
    and the averaged torques' limit).
    """
    _, tau_i, tau_g = _instantaneous(inertia)
    ratio = sp.cancel(-_mean(tau_i) / _mean(tau_g))
    _, den = sp.fraction(ratio)
    if den.subs(psi, 0) == 0:  # pragma: no cover - not for these torques
        return _ratio_at_small_psi(inertia)
    return ratio.subs(psi, 0)


def _lower_bound(inertia):
    ratio = _small_psi_ratio(inertia).subs(S.g, _g_from_omega0())
    # ratio = 1: a quadratic in a once the denominator is cleared (the ratio is a^2 times
    # a factor free of a), its positive root by the quadratic formula
    num, _ = sp.fraction(sp.cancel(ratio - 1))
    a_min = quadratic_root(num, S.a, "eq. 18 at small psi")
    return to_dimensionless(a_min / S.l)


@functools.lru_cache(maxsize=None)
def lower_bound_source():
    """000 eq. 19 as printed: the least a/l, following the source's eqs. 13-18.

    |<tau_i>| > |<tau_g>| at small psi (000 eq. 18) with the source's delta,
    solved for a/l (expression in w0_over_w and inertia_ratio).
    """
    return _lower_bound("source")


@functools.lru_cache(maxsize=None)
def lower_bound_physical():
    """The least a/l for a physical pendulum: eq. 18 with the fast part derived for inertia I.

    Equal to the lower end of 000 eq. 12 and to the exact Floquet slope
    (:func:`pendulab.analyses.phelps_hunter.lower_limit_small_ratio`).
    """
    return _lower_bound("I")


@functools.lru_cache(maxsize=None)
def lower_bound_kapitza():
    """The least a/l from Kapitza's potential: U_eff''(0) > 0 (psi = 0 a minimum)."""
    curvature = sp.diff(effective_potential(), psi, 2).subs(psi, 0)
    curvature = curvature.subs(S.g, _g_from_omega0())
    solutions = [s for s in sp.solve(sp.Eq(curvature, 0), S.a) if s.is_positive is not False]
    (a_min,) = solutions
    return to_dimensionless(a_min / S.l)


def _psi_m(inertia):
    torques = averaged_torques(inertia)
    balance = sp.simplify((torques["inertial"] + torques["gravitational"]) / sp.sin(psi))
    c = sp.Symbol("c")
    balance = sp.expand(sp.expand_trig(balance)).subs(sp.cos(psi), c)
    if balance.has(psi):  # pragma: no cover
        raise RuntimeError(f"torque balance is not a function of cos(psi): {balance}")
    (cos_psi,) = sp.solve(balance, c)
    cos_psi = to_dimensionless(cos_psi.subs(S.g, _g_from_omega0()))
    return sp.acos(cos_psi)


@functools.lru_cache(maxsize=None)
def psi_M_source():
    """The angle of unstable equilibrium |<tau_i>| = |<tau_g>|, psi != 0, the source's way.

    Expression in a_over_l, w0_over_w, inertia_ratio (000, after eq. 19).
    """
    return _psi_m("source")


@functools.lru_cache(maxsize=None)
def psi_M_physical():
    """The angle of unstable equilibrium for a physical pendulum (fast part derived for I)."""
    return _psi_m("I")
