"""The driven-pivot pendulum: Lagrangian -> 000 eqs. 3, 4, 7.

References are the source's printed equations (000_8cba66c4fdf94ac6.txt), typed
here from the source with their numbers, and SymPy's own LagrangesMethod as
an independent derivation.
"""

import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.canonical import periodic_form
from pendulab.equations import derive
from pendulab.errors import InputError
from pendulab.exprs import parse
from pendulab.systems import DrivenPivot

t, a, w, w0, g, m, l, I = S.t, S.a, S.omega, S.omega0, S.g, S.m, S.l, S.I
th = S.theta(t)


def _zero(expr):
    return sp.simplify(sp.expand(expr)) == 0


def _numerically_zero(expr, rng, n=5):
    """|expr| < 1e-12 at n random non-special points (theta, its derivatives too)."""
    d1, d2 = sp.symbols("d1 d2")
    e = expr.subs({th.diff(t, 2): d2}).subs({th.diff(t): d1})
    free = sorted(e.free_symbols | {th}, key=str)
    for _ in range(n):
        vals = {s: sp.Float(rng.uniform(0.3, 1.7)) for s in free if s != th}
        vals_th = sp.Float(rng.uniform(-1.0, 1.0))
        v = complex(e.subs(th, vals_th).subs(vals).evalf(30))
        assert abs(v) < 1e-12, (expr, v)


@pytest.mark.parametrize("body", ["rod", "point", "explicit"])
def test_general_form_before_eq3(body):
    """(I/(m l)) theta'' - (y0'' + g) sin theta = 0 for ANY y0(t) (000, before eq. 3)."""
    y0 = sp.Function("y0")(t)
    eqs = derive(DrivenPivot(body, drive=y0))
    source = (I / (m * l)) * th.diff(t, 2) - (y0.diff(t, 2) + g) * sp.sin(th)
    assert _zero(eqs.source_form - source)


def test_eq3_for_the_cosine_drive(rng):
    """000 eq. 3: theta'' + (-omega0^2 + (a l m omega^2/I) cos omega t) sin theta = 0."""
    eqs = derive(DrivenPivot("rod"))
    eq3 = th.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * sp.sin(th)
    assert _zero(eqs.eom - eq3)
    _numerically_zero(eqs.eom - eq3, rng)


def test_against_sympy_lagranges_method():
    """Independent derivation with sympy.physics.mechanics.LagrangesMethod."""
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols
    q = dynamicsymbols("q")
    t = dynamicsymbols._t  # mechanics' own time symbol
    qd = q.diff(t)
    y0 = a * sp.cos(w * t)
    x, y = l * sp.sin(q), y0 + l * sp.cos(q)
    T = m * (x.diff(t)**2 + y.diff(t)**2) / 2 + (I - m * l**2) * qd**2 / 2
    V = m * g * y
    lm = LagrangesMethod(T - V, [q])
    theirs = lm.form_lagranges_equations()[0]
    ours = derive(DrivenPivot("explicit")).euler_lagrange
    ours_q = ours.subs(S.t, t).subs(S.theta(t), q).doit()
    assert _zero(sp.expand(theirs) - ours_q)


def test_angle_from_downward_vertical():
    """Measured from below: I phi'' + m l (y0'' + g) sin phi = 0; linearised about phi = pi."""
    eqs = derive(DrivenPivot("point", angle="down"))
    y0 = a * sp.cos(w * t)
    expected = (I / (m * l)) * th.diff(t, 2) + (y0.diff(t, 2) + g) * sp.sin(th)
    assert _zero(eqs.source_form - expected)
    assert eqs.linear_about == sp.pi
    # The deviation from the inverted position obeys 000 eq. 4 again.
    eq4 = th.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * th
    assert _zero(eqs.linear - eq4)


def test_eq4_and_mathieu_form_eq7():
    """000 eq. 4, then tau = omega t/2 gives eq. 7 with eqs. 5-6."""
    eqs = derive(DrivenPivot("rod"))
    eq4 = th.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * th
    assert _zero(eqs.linear - eq4)
    form = periodic_form(eqs)
    assert form.kind == "mathieu"
    assert _zero(form.theta0 - (-4 * w0**2 / w**2))          # 000 eq. 5
    assert _zero(form.theta1 - 2 * a * l * m / I)              # 000 eq. 6
    thtau = S.theta(S.tau)
    eq7 = thtau.diff(S.tau, 2) + (form.theta0 + 2 * form.theta1 * sp.cos(2 * S.tau)) * thtau
    assert _zero(form.equation - eq7)


def test_mathieu_form_numerically_matches_time_form(rng):
    """The tau-equation times omega^2/4 equals the t-equation at t = 2 tau/omega."""
    eqs = derive(DrivenPivot("rod"))
    form = periodic_form(eqs)
    coeff_t = eqs.linear.coeff(th)
    for _ in range(5):
        vals = {s: rng.uniform(0.2, 2.0) for s in (a, w, w0, l, m, I)}
        tv = rng.uniform(0, 10)
        lhs = float(coeff_t.subs(vals).subs(t, tv))
        rhs = float((w**2 / 4 * form.coefficient).subs(S.tau, w * tv / 2).subs(vals))
        assert lhs == pytest.approx(rhs, rel=1e-12)


@pytest.mark.parametrize("body, ratio", [("rod", sp.Rational(4, 3)), ("point", 1)])
def test_body_inertia(body, ratio):
    """Rod of length 2l about its end: I = m (2l)^2/3 (000: l = L/2, I0 = m L^2/12)."""
    sysm = DrivenPivot(body)
    assert sysm.inertia_ratio == ratio
    i_rod = m * l**2 + m * (2 * l)**2 / 12  # parallel axes: I = m l^2 + I0
    if body == "rod":
        assert _zero(sysm.inertia - i_rod)


def test_sine_drive_is_a_shifted_mathieu_equation():
    form = periodic_form(derive(DrivenPivot("rod", drive=a * sp.sin(w * t))))
    assert form.kind == "mathieu"
    assert form.shift == sp.pi / 4
    shifted = form.theta0 + 2 * form.theta1 * sp.cos(2 * (S.tau - form.shift))
    assert _zero(form.coefficient - shifted)


def test_two_harmonic_drive_is_hill_not_mathieu():
    b = sp.Symbol("b", positive=True)
    form = periodic_form(derive(DrivenPivot("rod", drive=a * sp.cos(w * t) + b * sp.cos(2 * w * t))))
    assert form.kind == "hill"
    assert "Hill" in form.note
    # The Fourier series reproduces the coefficient exactly.
    rebuilt = sum(c * sp.cos(k * S.tau) + s * sp.sin(k * S.tau) for k, (c, s) in form.fourier.items())
    assert _zero(rebuilt - form.coefficient)
    assert set(form.fourier) == {0, 2, 4}


@pytest.mark.parametrize("kwargs, fragment", [
    ({"body": "stone"}, "body: must be one of"),
    ({"body": "explicit", "inertia_value": -1}, "inertia: must be positive"),
    ({"body": "explicit", "inertia_value": 0}, "inertia: must be positive"),
    ({"body": "explicit", "inertia_value": sp.I}, "inertia: must be a positive real quantity"),
    ({"drive": parse("a*Abs(cos(omega*t))")}, "drive: must be twice differentiable"),
    ({"drive": parse("a*Heaviside(t - 1)")}, "drive: must be twice differentiable"),
    ({"body": "rod", "inertia_value": 2}, "use body='explicit'"),
    ({"angle": "sideways"}, "angle: must be"),
    ({"drive": parse("theta(t)")}, "may not contain theta(t)"),
])
def test_bad_systems(kwargs, fragment):
    with pytest.raises(InputError, match=fragment.replace("(", r"\(").replace(")", r"\)")):
        DrivenPivot(**kwargs)


def test_g_of_omega0_is_what_solve_gives():
    """equations.g_of_omega0 (the slope of a relation linear in g) against SymPy's solve,
    expression for expression (srepr), and the relation it inverts holds."""
    from pendulab import symbols as S
    from pendulab.equations import OMEGA0_SQUARED, g_of_omega0
    solved, = sp.solve(sp.Eq(S.omega0**2, OMEGA0_SQUARED), S.g)
    assert sp.srepr(g_of_omega0()) == sp.srepr(solved)
    assert sp.expand(OMEGA0_SQUARED.subs(S.g, g_of_omega0()) - S.omega0**2) == 0
