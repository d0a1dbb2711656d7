"""Floquet verdict of any periodic drive: monodromy (DOP853, mp Taylor) and Hill's determinant.

Independent references:
* the Mathieu routes of pendulab.analyses.floquet (continued fractions, at
  30 digits) for a pure cosine drive - a different algorithm (000 eqs. 8-10);
* the characteristic values a_0, b_1 (mathieu_a/mathieu_b) for points next to
  the band edges: the verdict must change across the curve;
* for the variable-length pendulum with a constant length, theta'' + (g/L0)
  theta = 0, whose monodromy trace is 2 cos(sqrt(g/L0) T) exactly;
* for several harmonics, the two numeric routes against each other (Hill's
  determinant against the integrated monodromy matrix).
"""

import math
from functools import lru_cache

import mpmath
import pytest
import sympy as sp

from pendulab.analyses.floquet import characteristic_exponent, mathieu_a, mathieu_b
from pendulab.analyses.hill_general import hill_trace, numeric_fourier
from pendulab.canonical import periodic_form
from pendulab.equations import derive
from pendulab.errors import InputError
from pendulab.exprs import parse
from pendulab.numerics.model import length_system, pivot_system
from pendulab.numerics.monodromy import floquet_verdict, traces_along
from pendulab.systems import DrivenPivot, VariableLength


@lru_cache(maxsize=None)
def _pivot(drive="a*cos(omega*t)", body="point"):
    eqs = derive(DrivenPivot(body=body, drive=parse(drive)))
    form = periodic_form(eqs)
    return eqs, form, pivot_system(eqs, form)


def _point_params(theta0, theta1):
    """(a/l, omega0/omega) of a point mass with the source's drive at (theta0, theta1) <= 0."""
    # for a point mass, theta0 = -4 (omega0/omega)^2 and theta1 = 2 a/l (000 eqs. 5-6)
    return {"a_over_l": theta1 / 2, "w0_over_w": math.sqrt(-theta0 / 4)}


def test_the_point_mass_system_is_mathieus_equation():
    _, form, fos = _pivot()
    assert form.kind == "mathieu" and fos.period == sp.pi
    assert fos.params == tuple(sorted(fos.params, key=lambda s: s.name))


# Points of the first band, of the first gap beyond b_1 and below a_0 (theta0 <= 0).
MATHIEU_POINTS = [(-0.002, 0.2), (-0.04, 0.3), (-0.25, 1.0), (-0.01, 1.2), (-1.0, 0.3), (-0.5, 3.0)]


@pytest.mark.parametrize("theta0,theta1", MATHIEU_POINTS)
def test_dop853_monodromy_agrees_with_the_continued_fractions(theta0, theta1):
    _, _, fos = _pivot()
    v = floquet_verdict(fos, _point_params(theta0, theta1))
    ref = characteristic_exponent(str(theta0), str(theta1), dps=30, method="cf")
    tr = float(mpmath.re(ref.multipliers[0] + ref.multipliers[1]))
    assert abs(v.trace - tr) <= 1e-10 * max(1.0, abs(tr))
    assert v.stable == ref.stable
    assert abs(v.det - 1) < 1e-10
    # the folded exponent has the multipliers exp(+-i pi lam) of the unfolded one
    assert abs(math.cos(math.pi * v.exponent.real) * math.cosh(math.pi * v.exponent.imag)
               - tr / 2) < 1e-9 * max(1, abs(tr))


@pytest.mark.parametrize("theta0,theta1", [(-0.002, 0.2), (-0.5, 3.0)])
def test_mp_monodromy_agrees_with_the_continued_fractions_to_30_digits(theta0, theta1):
    _, _, fos = _pivot()
    exact = {"a_over_l": sp.Rational(str(theta1)) / 2,
             "w0_over_w": sp.sqrt(-sp.Rational(str(theta0)) / 4)}
    v = floquet_verdict(fos, exact, dps=30, method="mp")
    ref = characteristic_exponent(str(theta0), str(theta1), dps=40, method="cf")
    with mpmath.workdps(40):
        tr = mpmath.re(ref.multipliers[0] + ref.multipliers[1])
        assert abs(v.trace - tr) <= mpmath.mpf(10) ** -29 * max(1, abs(tr))
    assert v.stable == ref.stable


@pytest.mark.parametrize("family,q,side", [("a0", 0.4, +1), ("a0", 0.4, -1),
                                           ("b1", 1.5, +1), ("b1", 1.5, -1)])
def test_the_verdict_changes_across_the_band_edges(family, q, side):
    # theta0 = a_0(q) (lower edge) or b_1(q) with q = -theta1 < 0: b_1(|q|) = a_1(-|q|)
    edge = mathieu_a(0, q) if family == "a0" else mathieu_b(1, q)
    theta0 = edge + side * 1e-6
    _, _, fos = _pivot()
    v = floquet_verdict(fos, _point_params(theta0, q))
    h = hill_trace({0: (theta0, 0.0), 2: (2 * q, 0.0)}, math.pi)
    inside = side > 0 if family == "a0" else side < 0
    assert v.stable is inside and h.stable is inside
    assert not v.on_boundary
    assert abs(v.trace - h.trace) < 1e-10


@pytest.mark.parametrize("theta0,theta1", MATHIEU_POINTS + [(3.99, 0.001), (0.7, -1.2)])
def test_hill_determinant_of_a_pure_cosine_agrees_with_mathieu(theta0, theta1):
    ref = characteristic_exponent(str(theta0), str(theta1), dps=30, method="cf")
    tr = float(mpmath.re(ref.multipliers[0] + ref.multipliers[1]))
    # cos 2 tau coefficient A_2 = 2 theta1 (000 eq. 7)
    h = hill_trace({0: (theta0, 0.0), 2: (2 * theta1, 0.0)}, math.pi)
    assert abs(h.trace - tr) <= 1e-10 * max(1.0, abs(tr))
    # the same equation seen with period 2 pi: tr(M^2) = tr^2 - 2
    h2 = hill_trace({0: (theta0, 0.0), 2: (2 * theta1, 0.0)}, 2 * math.pi)
    assert abs(h2.trace - (tr * tr - 2)) <= 1e-9 * max(1.0, tr * tr)


def test_a_sine_drive_has_the_trace_of_the_cosine():
    # sin 2 tau = cos 2(tau - pi/4): a shift of time does not change the multipliers
    a = hill_trace({0: (-0.01, 0.0), 2: (0.4, 0.0)}, math.pi)
    b = hill_trace({0: (-0.01, 0.0), 2: (0.0, 0.4)}, math.pi)
    assert abs(a.trace - b.trace) < 1e-11


TWO_HARMONICS = "a*cos(omega*t) + a*cos(2*omega*t)"


@pytest.mark.parametrize("al,w", [(0.1, 0.05), (0.2, 0.1), (0.05, 0.1), (0.35, 0.02)])
def test_hill_determinant_agrees_with_monodromy_for_two_harmonics(al, w):
    eqs, form, fos = _pivot(TWO_HARMONICS, "rod")
    assert form.kind == "hill"
    values = {sp.Symbol("a_over_l", positive=True): al}
    from pendulab import symbols as S
    sub = {S.a: S.a_over_l * S.l, S.omega0: S.w0_over_w * S.omega,
           S.I: eqs.system.inertia}
    fourier = {k: tuple(sp.sympify(c).subs(sub) for c in pair) for k, pair in form.fourier.items()}
    h = hill_trace(numeric_fourier(fourier, {S.a_over_l: al, S.w0_over_w: w}), float(form.period))
    v = floquet_verdict(fos, {"a_over_l": al, "w0_over_w": w})
    assert values and abs(h.trace - v.trace) < 1e-9 * max(1, abs(v.trace))
    assert h.stable == v.stable


def test_mp_and_dop853_agree_for_two_harmonics():
    _, _, fos = _pivot(TWO_HARMONICS, "rod")
    p = {"a_over_l": "1/10", "w0_over_w": "1/20"}
    a = floquet_verdict(fos, p)
    b = floquet_verdict(fos, p, dps=25, method="mp")
    assert abs(a.trace - float(b.trace)) < 1e-11
    assert a.stable == b.stable


def test_traces_along_agree_with_single_verdicts():
    _, _, fos = _pivot()
    xs = [0.0, 0.1, 0.3, 0.7]
    tr = traces_along(fos, {"w0_over_w": 0.1}, "a_over_l", xs)
    for x, t in zip(xs, tr):
        assert abs(t - floquet_verdict(fos, {"w0_over_w": 0.1, "a_over_l": x}).trace) < 1e-10


def _periodic_length(eps):
    return length_system(derive(VariableLength(length=parse(f"L0*(1 + {eps}*sin(Omega*t))"))))


def test_variable_length_with_constant_length_is_a_harmonic_oscillator():
    # L0 (1 + 0 sin) = L0: theta'' + (g/L0) theta = 0, tr M = 2 cos(sqrt(g/L0) T), T = 2 pi/Omega
    fos = length_system(derive(VariableLength(length=parse("L0 + 0*sin(Omega*t)"))))
    if fos.period is None:  # the zero term cancels; use a tiny modulation instead
        fos = _periodic_length("1/10**12")
    p = {"L0": 1, "g": "981/100", "Omega": 5}
    T = 2 * math.pi / 5
    expected = 2 * math.cos(math.sqrt(9.81) * T)
    v = floquet_verdict(fos, p)
    assert abs(v.trace - expected) < 1e-10
    assert abs(v.det - 1) < 1e-11


def test_variable_length_periodic_routes_agree():
    fos = _periodic_length("1/10")
    assert fos.period is not None
    p = {"L0": 1, "g": "981/100", "Omega": 6}
    a = floquet_verdict(fos, p)
    b = floquet_verdict(fos, p, dps=20, method="mp")
    assert abs(a.trace - float(b.trace)) < 1e-11
    assert abs(float(b.det) - 1) < 1e-15  # Liouville: tr A = -2 L'/L integrates to 0
    assert a.stable == b.stable


def test_refusals():
    eqs = derive(VariableLength())
    with pytest.raises(InputError, match="not periodic"):
        floquet_verdict(length_system(eqs), {"L0": 1, "g": 9.81, "v0": 1})
    _, _, fos = _pivot()
    with pytest.raises(InputError, match="missing value"):
        floquet_verdict(fos, {"a_over_l": 0.1})
    with pytest.raises(InputError, match="unknown parameter"):
        floquet_verdict(fos, {"a_over_l": 0.1, "w0_over_w": 0.1, "zz": 1})
    with pytest.raises(InputError, match="method"):
        floquet_verdict(fos, {"a_over_l": 0.1, "w0_over_w": 0.1}, method="rk4")
    with pytest.raises(InputError, match="finite"):
        floquet_verdict(fos, {"a_over_l": float("nan"), "w0_over_w": 0.1})
    # parameter values are read exactly, the sign of an mpf included
    from pendulab.numerics.monodromy import _sympy_number
    assert _sympy_number(mpmath.mpf(-3.5), "x") == sp.Rational(-7, 2)
    assert _sympy_number("2*pi", "x") == 2 * sp.pi
    with pytest.raises(InputError, match="needs method='mp'"):
        floquet_verdict(fos, {"a_over_l": 0.1, "w0_over_w": 0.1}, dps=30)


@pytest.mark.parametrize("side", [+1, -1])
def test_mp_monodromy_decides_the_side_1e_20_from_a_0(side):
    # theta0 = a_0(q) +- 1e-20 (a_0 at 60 digits, DLMF 28.4 matrices): stable just above
    q = sp.Rational(2, 5)
    with mpmath.workdps(60):
        edge = mathieu_a(0, "0.4", dps=60)
        theta0 = edge + side * mpmath.mpf(10) ** -20
        sign, man, exp, _ = theta0._mpf_
    theta0_exact = (-1) ** sign * sp.Integer(int(man)) * sp.Integer(2) ** int(exp)
    _, _, fos = _pivot()
    v = floquet_verdict(fos, {"a_over_l": q / 2, "w0_over_w": sp.sqrt(-theta0_exact / 4)},
                        dps=30, method="mp")
    assert v.stable is (side > 0) and not v.on_boundary
    ref = characteristic_exponent(theta0, "0.4", dps=30, method="cf")
    assert ref.stable is v.stable
    with mpmath.workdps(30):
        tr = mpmath.re(ref.multipliers[0] + ref.multipliers[1])
        assert abs(v.trace - tr) < mpmath.mpf(10) ** -28
