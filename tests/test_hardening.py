"""Input hardening: bounded work, no traceback, right errors, the newcomer's command line.

References are independent of the code under test: Fourier coefficients by
numerical quadrature (scipy.integrate.quad) of the linearised equation's
coefficient in t; the direct trigonometric spectrum checked by evaluating the
sum of exponentials it claims; I >= m l^2 from the parallel-axis theorem
(000 after eq. 2); zeros of lengths solved by hand.
"""

import math

import pytest
import sympy as sp
from scipy.integrate import quad

from pendulab import limits, symbols as S
from pendulab.canonical import periodic_form
from pendulab.cli import join_negative_values, main, make_parser
from pendulab.equations import derive
from pendulab.errors import InputError, ParameterError, SceneError
from pendulab.exprs import MAX_HARMONICS, expanded_terms, parse, trig_spectrum
from pendulab.scene import parse_scene
from pendulab.systems import DrivenPivot, VariableLength

# numbers for the symbols (arbitrary, non-special)
VALUES = {S.a: 0.037, S.omega: 1.9, S.omega0: 0.61, S.l: 0.83, S.m: 1.7, S.I: 1.45,
          sp.Symbol("b", real=True): -0.021, sp.Symbol("c", real=True): 0.013,
          sp.Symbol("phi", real=True): 0.4}


def _quad_fourier(form, eqs, kmax):
    """(A_k, B_k) of the tau-coefficient by quadrature of the t-equation's theta coefficient."""
    coeff_t = sp.expand(eqs.linear).coeff(S.theta(S.t)).subs(VALUES)
    f_t = sp.lambdify(S.t, coeff_t, "math")
    omega_cap = float(form.frequency.subs(VALUES))
    # P(tau) = (4/Omega^2) c(2 tau/Omega), 000 before eq. 5; the period in tau divides 2 pi
    P = lambda tau: 4 / omega_cap**2 * f_t(2 * tau / omega_cap)  # noqa: E731
    out = {}
    for k in range(kmax + 1):
        a = quad(lambda x: P(x) * math.cos(k * x), 0, 2 * math.pi, limit=200)[0] / math.pi
        b = quad(lambda x: P(x) * math.sin(k * x), 0, 2 * math.pi, limit=200)[0] / math.pi
        out[k] = (a / 2 if k == 0 else a, b)
    return out


@pytest.mark.parametrize("drive", [
    "a*cos(omega*t) + b*sin(2*omega*t) - c*sin(3*omega*t)",
    "a*sin(omega*t) + c*cos(omega*t)*sin(omega*t)",
    "b*sin(omega*t + phi) + a*cos(3*omega*t)",
    "+".join(f"{(-1)**k}*a*sin({k}*omega*t)/{k}" for k in range(1, 13)),
])
def test_hill_fourier_coefficients_signs_against_quadrature(drive):
    """The sine parts B_k (and cosine parts A_k) of a Hill drive, sign included.

    Flipping the sign of B_k in canonical._real_fourier fails this test.
    """
    eqs = derive(DrivenPivot("rod", parse(drive)))
    form = periodic_form(eqs)
    assert form.kind in ("hill", "mathieu")
    kmax = max(form.fourier)
    reference = _quad_fourier(form, eqs, kmax + 1)
    sines = 0
    for k in range(kmax + 2):
        a_ref, b_ref = reference[k]
        a, b = form.fourier.get(k, (0, 0))
        a, b = float(sp.sympify(a).subs(VALUES)), float(sp.sympify(b).subs(VALUES))
        assert a == pytest.approx(a_ref, abs=1e-9), (k, "A")
        assert b == pytest.approx(b_ref, abs=1e-9), (k, "B")
        sines += abs(b_ref) > 1e-6
    assert sines >= 1  # the case really has sine parts


def test_trig_spectrum_reproduces_the_expression():
    """sum c_r exp(i r t) from trig_spectrum equals the expression at random points."""
    import random
    rng = random.Random(10)
    exprs = ["a*cos(omega*t)**3*sin(2*t + phi)", "(1 + sin(t))**4", "cos(t/2)*sin(3*t/4) - 7",
             "sin(omega*t)*cos(omega*t)*b"]
    for text in exprs:
        e = parse(text)
        spec = trig_spectrum(e, S.t)
        total = sum(c * sp.exp(sp.I * r * S.t) for r, c in spec.items())
        for _ in range(3):
            point = {S.t: rng.uniform(-3, 3), **VALUES}
            assert complex(total.subs(point).evalf()) == pytest.approx(
                complex(e.subs(point).evalf()), abs=1e-12)
    assert trig_spectrum(parse("t*cos(t)"), S.t) is None
    assert trig_spectrum(parse("cos(t**2)"), S.t) is None


def test_many_harmonics_are_derived_and_too_many_refused():
    """40 harmonics (today's direct method; the old rewrite(exp) route took minutes)."""
    drive = "+".join(f"a{k}*cos({k}*omega*t)" for k in range(1, 41))
    eqs = derive(DrivenPivot("rod", parse(drive)))
    form = periodic_form(eqs)
    assert form.kind == "hill" and sorted(form.fourier) == list(range(0, 81, 2))  # tau = omega t/2
    amplitudes = {sp.Symbol(f"a{k}", real=True): 0.01 / k for k in range(1, 41)}
    VALUES.update(amplitudes)
    try:
        omega_cap = float(form.frequency.subs(VALUES))
        coeff_t = sp.lambdify(S.t, sp.expand(eqs.linear).coeff(S.theta(S.t)).subs(VALUES), "math")
        for k in (2, 34, 80):
            ref = quad(lambda x: 4 / omega_cap**2 * coeff_t(2 * x / omega_cap) * math.cos(k * x),
                       0, 2 * math.pi, limit=400)[0] / math.pi
            assert float(sp.sympify(form.fourier[k][0]).subs(VALUES)) == pytest.approx(ref, abs=1e-9)
    finally:
        for key in amplitudes:
            VALUES.pop(key)
    with pytest.raises(ParameterError, match=f"limit {MAX_HARMONICS} harmonics"):
        DrivenPivot("rod", parse("cos(t)**999"))


@pytest.mark.parametrize("text, fragment", [
    ("inf", "not allowed"), ("nan", "not allowed"), ("zoo", "not allowed"), ("oo", "not allowed"),
    ("Eq(t, 1)", "a relation"), ("Tuple(1, 2)", "a container"), ("(1, 2)", "tuple"),
    ("Rational(1, 0)*cos(t)", "division by zero"), ("log(0)", "not finite"), ("0**-1", "zero"),
    ("-" * 3990 + "a", "nested too deeply"),
    ("(a+b+c+d+t)**200", "multiplied out"),
    ("Derivative(Derivative(Derivative(Derivative(Derivative(Derivative(cos(t), (t, 20)), "
     "(t, 20)), (t, 20)), (t, 20)), (t, 20)), (t, 20))", "total order 40"),
    ("Derivative(cos(t)**40*t**30*exp(t)*sin(3*t)**20, (t, 20))", "derivative number 9"),
])
def test_expressions_refused_with_the_cause(text, fragment):
    with pytest.raises(InputError, match=re_escape(fragment)):
        parse(text)


def re_escape(text):
    import re
    return re.escape(text)


def test_flat_sums_and_sign_runs_are_not_deep():
    assert parse("+".join(f"a{k}" for k in range(70))) == sp.Add(
        *[sp.Symbol(f"a{k}", real=True) for k in range(70)])
    assert parse("-" * 51 + "a") == -S.a
    assert parse("2*(nu - 1)") == 2 * S.nu - 2  # folded as Python would (SymPy distributes)
    with pytest.raises(InputError, match="nested too deeply"):
        parse("sin(" * 70 + "t" + ")" * 70)


def test_expanded_terms_estimate():
    assert expanded_terms(parse("(a + b)**3")) == 4
    assert expanded_terms(parse("(a + b)*(c + t + 1)")) == 6
    assert expanded_terms(parse("1/(a + b)**40")) == 1  # a denominator stays one factor


@pytest.mark.parametrize("inertia", ["m*l**2/2", "m*l**2 - I0", "l**2*m*9/10"])
def test_inertia_below_m_l2_refused_for_the_equations_too(inertia):
    with pytest.raises(SceneError, match="less than m\\*l\\*\\*2"):
        parse_scene({"system": "kapitza", "parameters": {"body": "explicit", "inertia": inertia},
                     "products": {"equations": {}}}, path="s.toml")


@pytest.mark.parametrize("inertia", ["m*l**2", "m*l**2 + I0", "2", "I0"])
def test_inertia_not_provably_small_accepted(inertia):
    parse_scene({"system": "kapitza", "parameters": {"body": "explicit", "inertia": inertia},
                 "products": {"equations": {}}}, path="s.toml")


@pytest.mark.parametrize("length, when, tol", [
    ("L0 - v0*t", S.L0 / S.v0, 1e-12), ("3 - 2*t", sp.Rational(3, 2), 0),
    ("2 - t**3", 2**sp.Rational(1, 3), 0), ("L0*cos(t)", sp.pi / 2, 1e-5),
    ("1/(1 + t) - 1/2", sp.Integer(1), 1e-5),
    ("L0*(2 - exp(t))", sp.log(2), 1e-5),           # L0 factored out before the scan
    ("2 - t**999", 2**sp.Rational(1, 999), 1e-5),    # degree > 8: scanned, not solved
    ("1 + cos(t)", sp.pi, 5e-3),                     # touches zero without crossing
])
def test_length_zero_found_with_its_time(length, when, tol):
    found, certain = VariableLength(parse(length)).length_zero
    assert certain
    at = {S.L0: 2.5, S.v0: 0.7}
    assert float(found.subs(at)) == pytest.approx(float(when.subs(at)), abs=tol)


@pytest.mark.parametrize("length", ["L0 + v0*t", "L0*(2 + cos(t))", "exp(-t)", "3 + 2*t",
                                    "exp(-10*t)",  # 0.0 in floats past t = 74.5: underflow
                                    # a pole at pi/2 first: the zeros after it (pi - atan 3,
                                    # 3 pi/4) are no length the string reaches
                                    "3 + tan(t)", "1 + tan(t)"])
def test_length_that_stays_positive(length):
    assert VariableLength(parse(length)).length_zero is None


def test_length_with_one_rate_symbol_is_scanned_in_its_phase():
    # L0 cos(omega t) = 0 first at omega t = pi/2: t = pi/(2 omega) when omega > 0
    found, certain = VariableLength(parse("L0*cos(omega*t)")).length_zero
    assert not certain
    assert float((found * S.omega).evalf()) == pytest.approx(math.pi / 2, rel=1e-5)


def test_length_zero_in_equations_note_and_quarter_periods_refused():
    from pendulab.pipeline import Context
    from pendulab.products import equations
    # lengths that are not L0 + v0 t: no Bessel closed form to compute, the test stays quick
    scene = parse_scene({"system": "variable-length", "parameters": {"length": "3 - 2*t - t**2"},
                         "products": {"equations": {}}}, path="s.toml")
    doc = equations.document(Context(scene))
    assert "reaches zero at t = 1:" in doc["length_note"]
    positive = parse_scene({"system": "variable-length",
                            "parameters": {"length": "L0*(2 + cos(t))"},
                            "products": {"equations": {}}}, path="s.toml")
    assert "length_note" not in equations.document(Context(positive))
    # (a linear L0 - r t is the shortening string, whose quarter periods end at L = 0:
    # tests/test_bessel_cli.py; any other length that reaches zero is refused with the time)
    with pytest.raises(SceneError, match="quarter_periods.*t = 1"):
        parse_scene({"system": "variable-length", "parameters": {"length": "3 - 2*t - t**2"},
                     "products": {"quarter_periods": {}}}, path="s.toml")
    # a shortening L0 + v0 t (v0 < 0) is accepted: the product stops at L = 0
    parse_scene({"system": "variable-length", "parameters": {"length": "3 - 2*t"},
                 "products": {"quarter_periods": {}}}, path="s.toml")


def test_option_ranges_reported_with_the_other_problems():
    with pytest.raises(SceneError) as info:
        parse_scene({"system": "kapitza", "parameters": {"drive": "inf"},
                     "products": {"series": {"order": 0}, "floquet": {"dps": 20000},
                                  "stability": {"points": 1}}}, path="s.toml")
    text = str(info.value)
    for key in ("parameters.drive", "products.series.order", "products.floquet.dps",
                "products.stability.points"):
        assert key in text
    assert len(text.splitlines()) == 4


def test_nan_and_inf_anywhere_in_a_scene():
    with pytest.raises(SceneError) as info:
        parse_scene({"system": "kapitza", "description": "x", "parameters": {"drive": math.inf},
                     "products": {"floquet": {"points": [[math.nan, 0.2]]}}}, path="s.toml")
    text = str(info.value)
    assert "parameters.drive: is inf" in text and "points[0][0]: is nan" in text


def test_floquet_work_budget():
    heavy = {"points": [["-2500", "1250"]] * 7, "ratios": [], "dps": 30, "method": "monodromy"}
    assert "would take about" in limits.work_problem("floquet", heavy)
    assert limits.work_problem("floquet", {**heavy, "points": heavy["points"][:1]}) is None
    assert limits.work_problem("floquet", {**heavy, "method": "hill"}) is None


def test_limits_agree_with_the_analyses():
    from pendulab.analyses import stability
    assert limits.LIMITS["stability.ratio"][1:3] == (0, stability.MAX_RATIO)
    assert limits.LIMITS["stability.inertia_ratio"][1:3] == (1, stability.MAX_INERTIA_RATIO)
    assert limits.LIMITS["stability.series_order"][2] == stability.MAX_SERIES_ORDER
    assert limits.LIMITS["stability.integer_series_order"][2] == stability.MAX_SERIES_ORDER


# -- command line ---------------------------------------------------------------------------

def _help(*argv, capsys):
    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    return capsys.readouterr().out


@pytest.mark.parametrize("argv", [("stability",), ("floquet",), ("series",), ("derive", "kapitza"),
                                  ("derive", "variable-length"), ("build",)])
def test_help_has_no_none_or_duplicate_defaults(argv, capsys):
    text = " ".join(_help(*argv, capsys=capsys).split())
    assert "(default: None)" not in text and "(default: False)" not in text
    assert text.count("(default: rod)") <= 1


def test_floquet_help_names_theta_and_states_the_limits(capsys):
    from pendulab.analyses.floquet import SIZE_LIMITS
    from pendulab.commands import floquet
    assert floquet.SIZES == ", ".join(f"{v:g} ({k})" for k, v in SIZE_LIMITS.items())
    text = " ".join(_help("floquet", capsys=capsys).split())
    assert " X " not in text and " Y " not in text and "THETA0" in text
    assert f"decimal digits, {limits.describe('floquet.dps')}" in text


@pytest.mark.parametrize("argv", [
    ["floquet", "--theta0", "-1/5", "--theta1", "-1/10"],
    ["floquet", "--theta1", "-1e-3", "--theta0", "-0.002"],
    ["derive", "kapitza", "--drive", "-a*cos(omega*t)", "--json"],
    ["stability", "--ratio", "0.1", "--method", "eq12"],
])
def test_negative_values_are_accepted(argv, capsys):
    assert main(argv) == 0
    assert capsys.readouterr().err == ""


def test_join_negative_values_keeps_flags():
    every, valued = {"--theta0", "--json", "-h", "--help"}, {"--theta0"}
    assert join_negative_values(["--theta0", "-1/5", "--json"], valued, every) == \
        ["--theta0=-1/5", "--json"]
    assert join_negative_values(["--theta0", "--json"], valued, every) == ["--theta0", "--json"]
    assert join_negative_values(["--theta0", "-h"], valued, every) == ["--theta0", "-h"]
    make_parser()  # builds with every command


# -- the work of the newer products' options together (pendulab.limits.work_problem) ------------

@pytest.mark.parametrize("system, product, options, fragment", [
    ("kapitza", "experiments", {"grid": 100}, "cost model of pendulab.limits"),
    ("kapitza", "experiments", {"first_experiment": True}, "cost model of pendulab.limits"),
    ("variable-length", "bessel", {"zeros": 10000, "dps": 1000}, "digits in all"),
    ("variable-length", "bessel", {"nmax": 20, "points": 400, "dps": 1000}, "identities"),
    ("variable-length", "motion", {"t_end": 1e5}, "oscillations"),
])
def test_work_of_options_together_is_refused_at_validation(system, product, options, fragment):
    with pytest.raises(SceneError) as info:
        parse_scene({"system": system, "products": {product: options}}, path="s.toml")
    msg = str(info.value)
    assert f"products.{product}" in msg and fragment in msg and "\n" not in msg


def test_the_full_size_experiments_are_accepted_with_the_c_kernel():
    # docs/experiments.md: the source's 100 x 100 maps and first experiment with backend = "c"
    scene = parse_scene({"system": "kapitza", "products": {"experiments": {
        "grid": 100, "first_experiment": True, "backend": "c"}}}, path="s.toml")
    assert scene.products["experiments"]["grid"] == 100
