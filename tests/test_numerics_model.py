"""numerics.model: the first-order systems are the derived equations, in the source's time.

The checks evaluate the equations stage itself (in t, with every physical
symbol a number) and compare with the first-order system at the same
instant, so an error in the change of time tau = Omega t/2, in the groups or
in the substitution of numbers shows up as a mismatch.
"""

import math

import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.canonical import periodic_form
from pendulab.equations import derive
from pendulab.errors import InputError
from pendulab.numerics.model import (DTHETA, THETA, length_system, mathieu_parameters,
                                     pivot_system)
from pendulab.systems import DrivenPivot, VariableLength


def _theta_ddot_t(eqs, subs, t, th, thd):
    """theta''(t) from the normalised equation of motion (000 eq. 3) at numbers."""
    acc = S.theta(S.t).diff(S.t, 2)
    expr = sp.expand(eqs.eom).subs(subs)
    rest = (expr - acc).subs({S.theta(S.t).diff(S.t): thd}).subs({S.theta(S.t): th, S.t: t})
    return -float(rest)


@pytest.mark.parametrize("body,drive", [
    ("rod", S.a * sp.cos(S.omega * S.t)),
    ("point", S.a * sp.cos(S.omega * S.t) + S.a * sp.cos(2 * S.omega * S.t)),
    ("rod", S.a * sp.cos(S.omega * S.t) ** 2),
])
def test_pivot_system_is_the_equation_of_motion_in_tau(body, drive, rng):
    eqs = derive(DrivenPivot(body=body, drive=drive))
    form = periodic_form(eqs)
    fos = pivot_system(eqs, form)
    assert fos.params == (S.a_over_l, S.w0_over_w)
    f = fos.lambdified()
    freq = form.frequency
    for _ in range(5):
        l, m, om = rng.uniform(0.1, 2.0, 3)
        al, rho = rng.uniform(0, 1, 2)
        t, th, thd = rng.uniform(-3, 3, 3)
        inertia = float(sp.sympify(eqs.system.inertia).subs({S.m: m, S.l: l}))
        subs = {S.a: al * l, S.l: l, S.m: m, S.omega: om, S.omega0: rho * om, S.I: inertia}
        want = _theta_ddot_t(eqs, subs, t, th, thd)
        half = float(freq.subs(S.omega, om)) / 2          # d tau / d t
        got = f(t * half, [th, thd / half], [al, rho])
        assert got[0] == pytest.approx(thd / half, rel=1e-13)
        assert got[1] * half**2 == pytest.approx(want, rel=1e-11, abs=1e-12)


def test_linear_rhs_is_the_jacobian_at_the_inverted_position():
    eqs = derive(DrivenPivot(body="rod"))
    fos = pivot_system(eqs, periodic_form(eqs))
    jac = fos.jacobian().subs({THETA: fos.about, DTHETA: 0})
    assert sp.simplify(jac - fos.linear_matrix()) == sp.zeros(2, 2)


def test_fig2_numbers_give_the_source_parameters():
    # 000 sec. 4, Fig. 2: a rod 10 cm long (l = 5 cm), pivot amplitude 6 mm at
    # 86 Hz; the source quotes theta0 = -2e-3 and theta1 = 0.2 for it.
    eqs = derive(DrivenPivot(body="rod"))
    th0, th1 = mathieu_parameters(eqs, periodic_form(eqs), groups=False,
                                  values={"l": 0.05, "a": 0.006, "omega": "2*pi*86", "g": 9.81})
    assert float(th0) == pytest.approx(-2.0e-3, rel=0.01)
    assert float(th1) == pytest.approx(0.18, rel=1e-12)
    assert round(float(th1), 1) == 0.2


def test_numbers_leave_no_symbols_in_the_system():
    eqs = derive(DrivenPivot(body="rod"))
    fos = pivot_system(eqs, periodic_form(eqs), groups=False,
                       values={"l": 0.05, "a": 0.006, "omega": "2*pi*86", "g": 9.81})
    assert fos.params == ()
    th0, th1 = mathieu_parameters(eqs, periodic_form(eqs), groups=False,
                                  values={"l": 0.05, "a": 0.006, "omega": "2*pi*86", "g": 9.81})
    # the linear equation is Mathieu's with these parameters (000 eq. 7)
    y = fos.lambdified(linear=True)(0.3, [1.0, 0.0])
    assert y[1] == pytest.approx(-(float(th0) + 2 * float(th1) * math.cos(0.6)), rel=1e-12)


def test_hill_drive_has_no_single_theta1():
    eqs = derive(DrivenPivot(drive=S.a * sp.cos(S.omega * S.t) + S.a * sp.cos(2 * S.omega * S.t)))
    with pytest.raises(InputError, match="hill"):
        mathieu_parameters(eqs, periodic_form(eqs))


def test_bad_number_is_refused():
    eqs = derive(DrivenPivot(body="rod"))
    with pytest.raises(InputError, match="values.l"):
        pivot_system(eqs, periodic_form(eqs), values={"l": "oo"})


@pytest.mark.parametrize("length", [S.L0 + S.v0 * S.t, S.L0 * (1 + sp.sin(S.omega * S.t) / 5)])
def test_length_system_is_the_equation_of_motion(length, rng):
    eqs = derive(VariableLength(length=length))
    fos = length_system(eqs)
    f = fos.lambdified()
    for _ in range(5):
        vals = {s: float(rng.uniform(0.2, 2.0)) for s in fos.params}
        t, th, thd = rng.uniform(0, 1, 3)
        acc = S.theta(S.t).diff(S.t, 2)
        expr = sp.expand(eqs.eom.subs(vals))
        lead = expr.coeff(acc)
        rest = sp.expand(expr - lead * acc).subs({S.theta(S.t).diff(S.t): thd}).subs({S.theta(S.t): th})
        want = -float((rest / lead).subs(S.t, t))
        got = f(t, [th, thd], [vals[s] for s in fos.params])
        assert got[1] == pytest.approx(want, rel=1e-12)


def test_numbers_reach_the_scene_own_symbols():
    # exprs.parse makes a scene's own names real symbols; a number given by
    # name must still replace them (found when eps stayed symbolic).
    from pendulab.exprs import parse
    eqs = derive(VariableLength(length=parse("L0*(1 + eps*sin(Omega*t))")))
    fos = length_system(eqs, values={"eps": 0.05, "Omega": 6, "L0": 1, "g": 9.81})
    assert fos.params == ()


@pytest.mark.parametrize("body,drive,angle,values", [
    ("rod", S.a * sp.cos(S.omega * S.t), "up", None),               # kapitza-rod, kapitza-experiments
    ("point", S.a * sp.cos(S.omega * S.t), "up", None),             # kapitza-point
    ("explicit", S.a * sp.cos(S.omega * S.t), "up", None),          # I symbolic: inertia_ratio
    ("rod", S.a * sp.sin(S.omega * S.t), "up", None),
    ("rod", S.a * sp.cos(S.omega * S.t), "down", None),
    ("point", S.a * sp.cos(S.omega * S.t) + S.a * sp.cos(2 * S.omega * S.t), "up", None),
    ("rod", S.a * sp.cos(S.omega * S.t) ** 2, "up", None),          # sin^2 and cos^2: simplify's own
    ("rod", S.a * sp.cos(S.omega * S.t), "up", {"l": "1/20", "a": "3/500", "omega": "2*pi*86",
                                               "g": "981/100"}),   # pi: simplify's own
])
def test_pivot_system_right_sides_are_simplifys(body, drive, angle, values):
    """numerics.model._tidy (cancel and factor_terms where they apply) gives simplify's
    expressions, tree for tree: the kernels are printed and lambdified from them."""
    from pendulab.numerics import model
    eqs = derive(DrivenPivot(body=body, drive=drive, angle=angle))
    form = periodic_form(eqs)
    fos = model._pivot_system(eqs, form, values, values is None)
    original, model._tidy = model._tidy, sp.simplify
    try:
        reference = model._pivot_system(eqs, form, values, values is None)
    finally:
        model._tidy = original
    assert [sp.srepr(e) for e in fos.rhs + fos.linear_rhs] == \
        [sp.srepr(e) for e in reference.rhs + reference.linear_rhs]
    assert fos.params == reference.params
