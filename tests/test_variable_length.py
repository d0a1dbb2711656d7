"""The variable-length pendulum (002_19b336b29bb1f03b.txt): Lagrangian -> eqs. 3, 4, 7
-> Bessel solution, checked by substitution, against the source, DLMF and an
independent numerical integration.
"""

import mpmath
import numpy as np
import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.analyses.bessel import (check_cross_product_numerically, closed_form,
                                      cross_product, derivative_rule_holds)
from pendulab.canonical import length_form
from pendulab.equations import derive
from pendulab.errors import InputError
from pendulab.exprs import parse
from pendulab.systems import VariableLength

t, g, L0, v0 = S.t, S.g, S.L0, S.v0
th = S.theta(t)
ell = S.L(t)
Lv = S.Lvar


@pytest.fixture(scope="module")
def linear_case():
    system = VariableLength()
    eqs = derive(system)
    form = length_form(eqs)
    return system, eqs, form, closed_form(form, system.length)


def test_lagrangian_gives_eq3():
    """002 eq. 3: -g sin theta = 2 L' theta' + L theta'' (any L(t))."""
    eqs = derive(VariableLength())
    eq3 = 2 * ell.diff(t) * th.diff(t) + ell * th.diff(t, 2) + g * sp.sin(th)
    assert sp.simplify(eqs.source_form - eq3) == 0


def test_lagrange_agrees_with_the_sources_newton_route():
    """The source projects Newton's law on the normal to the string (002 eqs. 1-2)."""
    eqs = derive(VariableLength())
    assert sp.simplify(eqs.source_form - eqs.newton) == 0


def test_eq4_linear():
    eqs = derive(VariableLength())
    eq4 = 2 * ell.diff(t) * th.diff(t) + ell * th.diff(t, 2) + g * th
    assert sp.simplify(eqs.linear - eq4) == 0


def test_length_form_line_before_eq7_and_eq7(linear_case):
    """002: L v0^2 theta_LL + 2 v0^2 theta_L + g theta = 0, then times L/v0^2 (eq. 7)."""
    _, _, form, _ = linear_case
    thL = S.theta(Lv)
    before7 = Lv * v0**2 * thL.diff(Lv, 2) + 2 * v0**2 * thL.diff(Lv) + g * thL
    assert sp.simplify(form.length_equation - before7) == 0
    # 002 eq. 7 as printed is L^2 th'' + 2 L th' + (g/v0^2) th: the last term lost
    # its factor L.  Multiplying the (correct) line before by L/v0^2 gives:
    corrected7 = Lv**2 * thL.diff(Lv, 2) + 2 * Lv * thL.diff(Lv) + g * Lv / v0**2 * thL
    assert sp.simplify(form.euler_form - corrected7) == 0
    printed7 = Lv**2 * thL.diff(Lv, 2) + 2 * Lv * thL.diff(Lv) + g / v0**2 * thL
    assert sp.simplify(form.euler_form - printed7) != 0


def test_generalised_bessel_parameters(linear_case):
    """002: alpha = -1/2, beta = 1/2, k = 2 sqrt(g)/v0, p = 1."""
    _, _, form, _ = linear_case
    assert (form.alpha, form.beta, form.p) == (sp.Rational(-1, 2), sp.Rational(1, 2), 1)
    assert sp.simplify(form.k - 2 * sp.sqrt(g) / v0) == 0


def test_solution_residual_is_exactly_zero(linear_case):
    _, _, _, sol = linear_case
    assert sol.residuals == (0, 0)
    # and it is the source's theta = A z^-1 J1(z) + B z^-1 Y1(z), z = (2/v0) sqrt(g L)
    z = S.z
    assert sp.simplify(sol.general_z - (S.A * sp.besselj(1, z) / z + S.B * sp.bessely(1, z) / z)) == 0
    assert sp.simplify(sol.z_of_L - 2 / v0 * sp.sqrt(g * Lv)) == 0


def test_the_printed_eq7_is_not_solved_by_the_sources_solution(linear_case):
    """Numerically: the Bessel solution fails the printed eq. 7 (so the typo is real)."""
    _, _, _, sol = linear_case
    theta_L = sol.general_z.subs(S.z, sol.z_of_L)
    printed = (Lv**2 * theta_L.diff(Lv, 2) + 2 * Lv * theta_L.diff(Lv) + g / v0**2 * theta_L)
    val = printed.subs({S.A: 1, S.B: 0, g: sp.Rational(981, 100), v0: sp.Rational(1, 10), Lv: 2})
    assert abs(complex(val.evalf(30))) > 1e-3


def test_derivative_rule_dlmf_10_6_6():
    for p in range(4):
        assert derivative_rule_holds(p, "J") and derivative_rule_holds(p, "Y")


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_cross_product_against_dlmf_10_5_3(n):
    """DLMF 10.5.3: J_{n+1} Y_n - J_n Y_{n+1} = 2/(pi z); 002 'Afirmação' for n = 1."""
    assert sp.simplify(cross_product(n) - (-2 / (sp.pi * S.z))) == 0


def test_cross_product_to_50_digits():
    """mpmath at 50 digits over z in [0.1, 40]: residual below 1e-48."""
    zs = [mpmath.mpf(k) / 7 for k in range(1, 280, 13)]
    for n in (1, 2, 5):
        assert check_cross_product_numerically(n, zs, dps=50) < mpmath.mpf("1e-48")


def test_initial_value_constants(linear_case):
    """A, B from theta(z0) = theta_0, dtheta/dz(z0) = 0 (002, Cramer's rule).

    The source's Cramer form is compared exactly; its 'Consequência' gives
    A = -(pi/2) theta_0 z0^2 Y2(z0) (agrees) and B = -(pi/2) theta_0 z0^2 J2(z0)
    (sign differs: the Cramer form and the cross product give +); the initial
    conditions decide, checked numerically with mpmath at 30 digits.
    """
    _, _, _, sol = linear_case
    z0, th0 = S.z0, S.theta_0
    J, Y = sp.besselj, sp.bessely
    W = J(1, z0) * Y(2, z0) - J(2, z0) * Y(1, z0)
    assert sp.simplify(sol.cramer[S.A] - th0 * z0 * Y(2, z0) / W) == 0
    assert sp.simplify(sol.cramer[S.B] + th0 * z0 * J(2, z0) / W) == 0
    assert sp.simplify(sol.constants[S.A] - (-sp.pi / 2 * th0 * z0**2 * Y(2, z0))) == 0
    assert sp.simplify(sol.constants[S.B] - (+sp.pi / 2 * th0 * z0**2 * J(2, z0))) == 0
    f = sp.lambdify([S.z, z0, th0], sol.particular_z, "mpmath")
    with mpmath.workdps(30):
        for z0v in (mpmath.mpf("0.7"), mpmath.mpf("3.1"), mpmath.mpf("9.25")):
            assert abs(f(z0v, z0v, 1) - 1) < mpmath.mpf("1e-25")
            assert abs(mpmath.diff(lambda zz: f(zz, z0v, 1), z0v)) < mpmath.mpf("1e-20")


def test_closed_form_against_numerical_integration(linear_case):
    """Independent method: integrate 002 eq. 4 with scipy (rtol 1e-11) and compare."""
    from scipy.integrate import solve_ivp
    _, _, _, sol = linear_case
    vals = {g: 9.81, v0: 0.05, L0: 0.5, S.theta_0: 0.1}
    z_t = sol.z_of_L.subs(Lv, L0 + v0 * t)
    theta_t = sol.particular_z.subs({S.z0: sol.z0, S.z: z_t}).subs(vals)
    f = sp.lambdify(t, theta_t, "mpmath")

    def rhs(tt, y):
        Lt = 0.5 + 0.05 * tt
        return [y[1], -(2 * 0.05 * y[1] + 9.81 * y[0]) / Lt]
    ts = np.linspace(0, 20, 41)
    num = solve_ivp(rhs, (0, 20), [0.1, 0.0], t_eval=ts, rtol=1e-11, atol=1e-13, method="DOP853")
    closed = np.array([float(f(tt)) for tt in ts])
    assert np.max(np.abs(num.y[0] - closed)) < 1e-8


def test_nonlinear_length_has_no_bessel_form():
    system = VariableLength(length=parse("L0 + v0*t + t**2"))
    assert length_form(derive(system)) is None


@pytest.mark.parametrize("length, fragment", [
    ("-1 + t", "length: must be positive"),
    ("0", "length: must be positive"),
    ("L0 + v0*Abs(t - 1)", "length: must be twice differentiable"),
    ("theta(t)", "may not contain theta"),
])
def test_bad_lengths(length, fragment):
    with pytest.raises(InputError, match=fragment):
        VariableLength(length=parse(length))


def test_bad_mass():
    with pytest.raises(InputError, match="mass: must be positive"):
        VariableLength(mass=-2)
    with pytest.raises(InputError, match="mass: must be a constant"):
        VariableLength(mass=parse("m*cos(t)"))


def test_amplitude_constant_C_when_z0_is_a_zero_of_J2(linear_case):
    """002: with J2(z0) = 0, theta(t) = -C L^-1/2 J1(z).  Derived C = pi theta_0 L0 sqrt(g) Y2(z0)/v0.

    The source prints C = (pi/2)(4 g L0/v0^2) theta_0 Y2(z0), which lacks the
    factor v0/(2 sqrt(g)) that z^-1 = v0/(2 sqrt(g L)) brings; the test checks
    the derived C numerically against the initial condition instead.
    """
    _, _, _, sol = linear_case
    theta_L = sol.particular_z.subs(S.z, sol.z_of_L).subs(S.z0, sol.z0)
    theta_L = theta_L.subs(sp.besselj(2, sol.z0), 0)      # z0 is a zero of J2
    C = sp.simplify(-theta_L * sp.sqrt(Lv) / sp.besselj(1, sol.z_of_L))
    expected = sp.pi * S.theta_0 * L0 * sp.sqrt(g) * sp.bessely(2, sol.z0) / v0
    assert sp.simplify(C - expected) == 0
    printed = sp.pi / 2 * 4 * g * L0 / v0**2 * S.theta_0 * sp.bessely(2, sol.z0)
    assert sp.simplify(C / printed - v0 / (2 * sp.sqrt(g))) == 0
    # numerically: L0 chosen so that z0 = j_{2,1}; theta(0) = theta_0 to 30 digits
    with mpmath.workdps(30):
        j21 = mpmath.besseljzero(2, 1)
        gv, vv = mpmath.mpf("9.81"), mpmath.mpf("0.2")
        L0v = (j21 * vv / 2)**2 / gv
        Cv = mpmath.pi * L0v * mpmath.sqrt(gv) * mpmath.bessely(2, j21) / vv
        theta0_back = -Cv / mpmath.sqrt(L0v) * mpmath.besselj(1, 2 / vv * mpmath.sqrt(gv * L0v))
        assert abs(theta0_back - 1) < mpmath.mpf("1e-25")


def test_chain_rule_derivatives_are_the_direct_ones(linear_case):
    """The closed form's fast residual route (bessel.chain_derivatives: F'(z) z', F'' z'^2 + F' z'')
    gives the derivatives SymPy forms by differentiating F(z(L)) and F(z(t)) directly."""
    from pendulab.analyses.bessel import _fast_zero, chain_derivatives
    _, _, _, sol = linear_case
    for var, inner in ((Lv, sol.z_of_L), (t, sol.z_of_L.subs(Lv, L0 + v0 * t))):
        direct = sol.general_z.subs(S.z, inner)
        chained = [e.subs(S.z, inner) for e in chain_derivatives(sol.general_z, inner, var)]
        for n in range(3):
            assert _fast_zero(chained[n] - direct.diff(var, n))
        # and the test can fail: the first derivative is not the second
        assert not _fast_zero(chained[1] - direct.diff(var, 2))


def test_residuals_are_proved_by_the_fast_route(linear_case, monkeypatch):
    """Both residuals (L-form and t-form) are shown to be 0 without SymPy's simplify."""
    from pendulab.analyses import bessel

    def refuse(expr):
        raise AssertionError("the fast route did not prove the residual")
    monkeypatch.setattr(bessel, "_simplified_residual", refuse)
    _, _, form, _ = linear_case
    for length in (L0 + v0 * t, L0 - v0 * t, parse("3/2 + t/7")):
        system = VariableLength(length=length)
        sol = closed_form(length_form(derive(system)), system.length)
        assert sol.residuals == (0, 0)


def test_a_wrong_solution_leaves_a_residual(linear_case):
    """The residual checks can fail: with the order p = 2 in place of 1 (theta = A z^-1 J2(z) + ...),
    neither the L-form nor the t-form residual is 0."""
    import dataclasses
    _, _, form, _ = linear_case
    sol = closed_form(dataclasses.replace(form, p=sp.Integer(2)), L0 + v0 * t)
    assert sol.residual_L != 0 and sol.residual_t != 0


def test_cramer_rule_agrees_with_sympy_solve(linear_case):
    """The constants by Cramer's rule (bessel._cramer) are sp.solve's, after factor (srepr)."""
    from pendulab.analyses.bessel import _cramer
    _, _, _, sol = linear_case
    z0 = S.z0
    eqs = [sol.general_z.subs(S.z, z0) - S.theta_0, sol.dtheta_dz.subs(S.z, z0)]
    by_solve = sp.solve(eqs, [S.A, S.B], dict=True)[0]
    by_cramer = _cramer(eqs, [S.A, S.B])
    assert set(by_cramer) == set(by_solve)
    for key in by_solve:
        assert sp.srepr(sp.factor(by_cramer[key])) == sp.srepr(sp.factor(by_solve[key]))
    with pytest.raises(InputError, match="determinant 0"):
        _cramer([S.A + S.B - 1, 2 * S.A + 2 * S.B], [S.A, S.B])


@pytest.mark.parametrize("mass", ["m", "2", "3/2", "m + M"])
def test_lagrangian_is_trigsimps(mass):
    """VariableLength.lagrangian (sin^2 = 1 - cos^2 put in) is what trigsimp gives (srepr), and
    it is T - V: the difference simplifies to 0."""
    system = VariableLength(mass=parse(mass))
    raw = sp.expand(system.kinetic_energy - system.potential_energy)
    by_trigsimp = sp.expand(sp.trigsimp(raw))
    assert sp.srepr(system.lagrangian) == sp.srepr(by_trigsimp)
    assert sp.simplify(system.lagrangian - raw) == 0
    assert not system.lagrangian.has(sp.sin(th) ** 2)


def test_newton_projection_by_repeated_diff_is_diff_twice():
    """equations.newton_projection differentiates the velocity again; diff(t, 2) of the
    position gives the same projection (srepr)."""
    from pendulab.equations import newton_projection
    x, y = ell * sp.sin(th), ell * sp.cos(th)
    projected = sp.expand(x.diff(t, 2) * sp.cos(th) - y.diff(t, 2) * sp.sin(th) + g * sp.sin(th))
    direct = sp.expand(projected.subs(sp.sin(th) ** 2, 1 - sp.cos(th) ** 2))
    assert sp.srepr(newton_projection()) == sp.srepr(direct)


@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_cross_product_constant_is_sympys_limit(n):
    """cross_product takes the leading term at 0+ of the constant z (J_n Y_n+1 - J_n+1 Y_n);
    sp.limit gives the same (srepr), -2/pi."""
    z = S.z
    cross = sp.besselj(n, z) * sp.bessely(n + 1, z) - sp.besselj(n + 1, z) * sp.bessely(n, z)
    limit = sp.limit(z * cross, z, 0, "+")
    assert sp.srepr(cross_product(n) * z) == sp.srepr(limit) == sp.srepr(-2 / sp.pi)
