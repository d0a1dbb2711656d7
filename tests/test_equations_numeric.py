"""The derived equations against the sources' printed ones at random points.

The symbolic comparisons live in test_kapitza_equations.py and
test_variable_length.py; here every symbol, the angle and its derivatives
(and the time) are replaced by seeded random numbers away from special
values, and the derived left-hand side must equal the source's to 1e-25
relative (30-digit evaluation).  References are typed from the sources with
their equation numbers (000_8cba66c4fdf94ac6.txt, 002_19b336b29bb1f03b.txt).
"""

import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.canonical import fundamental_frequency, length_form, periodic_form
from pendulab.equations import derive
from pendulab.exprs import dump_expr, load_expr, parse
from pendulab.systems import DrivenPivot, VariableLength

t, tau, a, w, w0, g, m, l, I = S.t, S.tau, S.a, S.omega, S.omega0, S.g, S.m, S.l, S.I
L0, v0, Lv = S.L0, S.v0, S.Lvar


def assert_equal_at_random_points(derived, source, var, rng, n=6):
    """|derived - source| <= 1e-25 |source| at n random points."""
    for _ in range(n):
        # the same random values for both sides: drawn once, substituted in each
        free = sorted((derived.free_symbols | source.free_symbols) - {var}, key=str)
        vals = {x: sp.Float(rng.uniform(0.3, 1.7), 30) for x in free}
        vals[var] = sp.Float(rng.uniform(0.1, 3.0), 30)
        th = S.theta(var)
        jet = {th.diff(var, 2): sp.Float(rng.uniform(-1.2, 1.2), 30),
               th.diff(var): sp.Float(rng.uniform(-1.2, 1.2), 30)}
        th_val = sp.Float(rng.uniform(-1.2, 1.2), 30)
        extra = {}
        if var == t:
            ell = S.L(t)
            extra = {ell.diff(t, 2): sp.Float(rng.uniform(-1, 1), 30),
                     ell.diff(t): sp.Float(rng.uniform(-1, 1), 30),
                     ell: sp.Float(rng.uniform(0.5, 2), 30)}

        def value(expr):
            e = expr.subs(jet).subs(extra).subs({th: th_val}).subs(vals)
            return complex(sp.N(e, 30))
        dv, sv = value(derived), value(source)
        assert abs(dv - sv) <= 1e-25 * max(1.0, abs(sv)), (derived, source, dv, sv)


def _check(derived, source, var, rng):
    assert_equal_at_random_points(derived, source, var, rng)
    # and a wrong reference is caught (the check can fail)
    with pytest.raises(AssertionError):
        assert_equal_at_random_points(derived, source + sp.Rational(1, 1000) * S.theta(var), var, rng, n=1)


# ---------------------------------------------------------------------------
# 000: the driven pivot
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("body", ["rod", "point", "explicit"])
def test_000_eq3_and_eq4_at_random_points(body, rng):
    """000 eq. 3 (nonlinear) and eq. 4 (linearised), omega0^2 = m g l / I."""
    eqs = derive(DrivenPivot(body))
    th = S.theta(t)
    eq3 = th.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * sp.sin(th)
    eq4 = th.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * th
    _check(eqs.eom, eq3, t, rng)
    _check(eqs.linear, eq4, t, rng)


def test_000_general_drive_at_random_points(rng):
    """(I/(m l)) theta'' - (y0'' + g) sin theta = 0 (000, before eq. 3) for a drive
    y0 = a cos(omega t) + b t^3 (b a user symbol), with y0'' written out by hand."""
    drive = parse("a*cos(omega*t) + b*t**3")
    b = sp.Symbol("b", real=True)
    th = S.theta(t)
    y0dd = -a * w**2 * sp.cos(w * t) + 6 * b * t
    eqs = derive(DrivenPivot("point", drive=drive))
    _check(eqs.source_form, (I / (m * l)) * th.diff(t, 2) - (y0dd + g) * sp.sin(th), t, rng)


@pytest.mark.parametrize("body", ["rod", "point"])
def test_000_eq7_at_random_points(body, rng):
    """000 eq. 7 with eqs. 5-6: theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0,
    theta0 = -4 omega0^2/omega^2, theta1 = 2 a l m / I."""
    form = periodic_form(derive(DrivenPivot(body)))
    th = S.theta(tau)
    eq7 = th.diff(tau, 2) + (-4 * w0**2 / w**2 + 2 * (2 * a * l * m / I) * sp.cos(2 * tau)) * th
    _check(form.equation, eq7, tau, rng)


def test_000_eq7_from_eq4_by_the_change_of_time(rng):
    """Independent route: eq. 4 typed from the source, t = 2 tau/omega, times 4/omega^2."""
    form = periodic_form(derive(DrivenPivot("rod")))
    th_t, th = S.theta(t), S.theta(tau)
    eq4 = th_t.diff(t, 2) + (-w0**2 + a * l * m * w**2 / I * sp.cos(w * t)) * th_t
    # theta(t) = Theta(tau): theta'' (t) = (omega/2)^2 Theta''(tau)
    changed = (4 / w**2) * eq4.subs(th_t.diff(t, 2), (w / 2)**2 * th.diff(tau, 2)).subs(
        th_t, th).subs(t, 2 * tau / w)
    _check(form.equation, sp.expand(changed), tau, rng)


# ---------------------------------------------------------------------------
# The drive's own frequency sets tau (a drive written with numbers)
# ---------------------------------------------------------------------------

def test_numeric_frequency_gives_mathieu_with_that_frequency():
    """y0 = a cos(3 t): Mathieu's equation with omega = 3 in 000 eqs. 5-6."""
    form = periodic_form(derive(DrivenPivot("rod", drive=a * sp.cos(3 * t))))
    assert form.kind == "mathieu" and form.frequency == 3
    assert sp.simplify(form.theta0 - (-4 * w0**2 / w**2).subs(w, 3)) == 0
    assert sp.simplify(form.theta1 - 2 * a * l * m / I) == 0


def test_half_frequency_and_squared_cosine():
    form = periodic_form(derive(DrivenPivot("point", drive=a * sp.cos(w * t / 2))))
    assert form.kind == "mathieu" and form.frequency == w / 2
    assert sp.simplify(form.theta0 - (-4 * w0**2 / (w / 2)**2)) == 0
    # cos^2 (omega t) = (1 + cos 2 omega t)/2: a pure cosine at 2 omega, amplitude a/2
    form = periodic_form(derive(DrivenPivot("point", drive=a * sp.cos(w * t)**2)))
    assert form.kind == "mathieu" and form.frequency == 2 * w
    assert sp.simplify(form.theta1 - 2 * (a / 2) * l * m / I) == 0


def test_incommensurate_drive_is_neither():
    drive = a * sp.cos(w * t) + a * sp.cos(sp.sqrt(2) * w * t)
    form = periodic_form(derive(DrivenPivot("rod", drive=drive)))
    assert form.kind == "linear" and form.frequency is None
    assert "neither" in form.note


def test_fundamental_frequency_cases():
    assert fundamental_frequency(a * sp.cos(w * t) + a * sp.sin(3 * w * t)) == w
    assert fundamental_frequency(sp.cos(6 * t) + sp.cos(4 * t)) == 2
    assert fundamental_frequency(a * t) is None
    assert fundamental_frequency(a) is None
    assert fundamental_frequency(sp.cos(t) + sp.cos(sp.pi * t)) is None


def test_user_symbols_are_real_and_theta1_reads_back():
    """a cos(omega t) + b sin(omega t) is a cosine of amplitude sqrt(a^2 + b^2):
    theta1 = 2 l m sqrt(a^2 + b^2)/I (000 eq. 6 with that amplitude)."""
    drive = parse("a*cos(omega*t) + b*sin(omega*t)")
    form = periodic_form(derive(DrivenPivot("explicit", drive=drive)))
    b = sp.Symbol("b", real=True)
    assert form.kind == "mathieu"
    assert sp.simplify(form.theta1 - 2 * l * m * sp.sqrt(a**2 + b**2) / I) == 0
    assert load_expr(dump_expr(form.theta1)) == form.theta1
    assert "conjugate" not in dump_expr(form.theta1)


def test_phase_shifted_cosine_has_the_plain_amplitude():
    form = periodic_form(derive(DrivenPivot("rod", drive=parse("a*cos(omega*t + pi/3)"))))
    assert form.theta1 == 2 * a * l * m / I
    assert form.shift == -sp.pi / 6


# ---------------------------------------------------------------------------
# 002: the variable length
# ---------------------------------------------------------------------------

def test_002_eq3_and_eq4_at_random_points(rng):
    """002 eq. 3: L theta'' + 2 L' theta' + g sin theta = 0; eq. 4 with theta for sin."""
    eqs = derive(VariableLength())
    th, ell = S.theta(t), S.L(t)
    eq3 = ell * th.diff(t, 2) + 2 * ell.diff(t) * th.diff(t) + g * sp.sin(th)
    eq4 = ell * th.diff(t, 2) + 2 * ell.diff(t) * th.diff(t) + g * th
    _check(eqs.source_form, eq3, t, rng)
    _check(eqs.linear, eq4, t, rng)


def test_002_eq7_at_random_points(rng):
    """002 eq. 7 with the factor L the printed equation drops (see docs/equations.md):
    L^2 theta_LL + 2 L theta_L + (g L / v0^2) theta = 0."""
    form = length_form(derive(VariableLength()))
    th = S.theta(Lv)
    corrected = Lv**2 * th.diff(Lv, 2) + 2 * Lv * th.diff(Lv) + g * Lv / v0**2 * th
    _check(form.euler_form, corrected, Lv, rng)
    printed = Lv**2 * th.diff(Lv, 2) + 2 * Lv * th.diff(Lv) + g / v0**2 * th
    with pytest.raises(AssertionError):
        assert_equal_at_random_points(form.euler_form, printed, Lv, rng, n=1)
