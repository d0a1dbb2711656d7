"""The variable-length pendulum integrated (002_19b336b29bb1f03b.txt).

References, each independent of the code under test:

* 002's closed form as printed in "Conseqüência" (typed here from the source,
  with the misprint z -> z^-1 corrected, see test_source_formula_needs_z_to_the_minus_one),
  evaluated with scipy.special - a different method from the DOP853 integration;
* Abramowitz & Stegun Table 9.5 (zeros of J1, J2 to 10 decimals) and 002's
  quarter-period table (22.8438, 21.6315, ..., 4 decimals);
* DLMF 10.17.3 (large-z asymptotics of J_nu, Y_nu) applied to the closed form
  stage's general solution: the WKB envelope gives the amplitude exponent
  independently of the E/omega derivation in src;
* Liouville's formula (det of the monodromy matrix = exp of the integrated
  trace) and a Radau (implicit) integration for the monodromy matrix.
"""

import json
import math
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp
from scipy import special

from pendulab import canonical
from pendulab import symbols as S
from pendulab.analyses import variable_length_motion as vm
from pendulab.analyses.bessel import closed_form
from pendulab.build import build
from pendulab.cli import main
from pendulab.equations import derive
from pendulab.errors import InputError, PendulabError, SceneError
from pendulab.exprs import load_expr, parse
from pendulab.numerics.model import length_system
from pendulab.systems import VariableLength

G = 9.81
# A&S Table 9.5: zeros of J1 and J2.
J1_ZEROS = [3.8317059702, 7.0155866698, 10.1734681351]
J2_ZEROS = [5.1356223018, 8.4172441404, 11.6198411721]
# 002's quarter periods (unit v0/(4 g)), printed to 4 decimals.
SOURCE_QUARTERS = [22.8438, 21.6315, 32.6495, 31.5213, 42.5001, 41.3994]


class Model:
    def __init__(self, length):
        self.system = VariableLength(length=parse(length))
        self.length = self.system.length
        self.eqs = derive(self.system)
        self.form = canonical.length_form(self.eqs)
        ok = self.form is not None and self.form.alpha is not None
        self.cf = closed_form(self.form, self.length) if ok else None
        self.fos = length_system(self.eqs)


@pytest.fixture(scope="module")
def growing():
    return Model("L0 + v0*t")


@pytest.fixture(scope="module")
def shortening():
    return Model("L0 - v0*t")


@pytest.fixture(scope="module")
def periodic():
    return Model("L0*(1 + eps*sin(Omega*t))")


def source_theta(t, theta_0, g, L0, v0, sign=1):
    """002 "Conseqüência": theta = (pi/2) theta_0 z0^2 z^-1 [-Y2(z0) J1(z) + J2(z0) Y1(z)].

    The source prints the factor z where z^-1 belongs (see the test below);
    z = (2/v0) sqrt(g L), L = L0 + sign v0 t.
    """
    z0 = 2 / v0 * math.sqrt(g * L0)
    z = 2 / v0 * np.sqrt(g * (L0 + sign * v0 * np.asarray(t)))
    return (math.pi / 2 * theta_0 * z0**2 / z
            * (-special.yv(2, z0) * special.jv(1, z) + special.jv(2, z0) * special.yv(1, z)))


def test_source_formula_needs_z_to_the_minus_one():
    """At t = 0 the printed formula with z gives theta_0 z0^2, with z^-1 it gives theta_0."""
    z0 = 2 / 0.01 * math.sqrt(G)
    cross = special.jv(1, z0) * special.yv(2, z0) - special.jv(2, z0) * special.yv(1, z0)
    with_z = math.pi / 2 * 0.05 * z0**2 * z0 * -cross
    assert abs(source_theta(0.0, 0.05, G, 1.0, 0.01) - 0.05) < 1e-14
    assert abs(with_z / 0.05 - 1) > 1e5


# -- 1. linear motion against the closed form ------------------------------------

def test_linear_motion_agrees_with_the_closed_form(growing):
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    tr = vm.integrate(growing.fos, growing.length, values, 100.0, 0.05, linear=True, points=1001)
    ref = source_theta(tr.t, 0.05, **values)
    err = vm.relative_agreement(tr.theta, ref)
    assert err < 1e-10, err
    # the pipeline's closed form stage, evaluated by pendulab, is the same function
    ours = vm.closed_form_theta(growing.cf, growing.length, values, 0.05, tr.t)
    assert vm.relative_agreement(ours, ref) < 1e-12
    # and at 30 digits (mpmath) at a few times
    few = vm.closed_form_theta(growing.cf, growing.length, values, 0.05, tr.t[::100], engine="mpmath")
    assert vm.relative_agreement(few, ref[::100]) < 1e-12


def test_a_loose_tolerance_fails_the_agreement(growing):
    """The 1e-10 claim needs the tight tolerance: at rtol 1e-6 the same run misses it."""
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    tr = vm.integrate(growing.fos, growing.length, values, 100.0, 0.05, linear=True, rtol=1e-6)
    assert vm.relative_agreement(tr.theta, source_theta(tr.t, 0.05, **values)) > 1e-8


def test_nonlinear_motion_tends_to_the_closed_form_as_theta0_squared(growing):
    """sin theta = theta - theta^3/6 + ...: the departure from the linear solution is O(theta_0^2)."""
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    dev = []
    for th0 in (0.01, 0.02):
        tr = vm.integrate(growing.fos, growing.length, values, 20.0, th0, linear=False, points=801)
        dev.append(vm.relative_agreement(tr.theta, source_theta(tr.t, th0, **values)))
    assert 1e-6 < dev[0] < 1e-3
    assert 3.6 < dev[1] / dev[0] < 4.4, dev


# -- 2. z0 at a zero of J2: B = 0 ------------------------------------------------

def test_b_zero_length_puts_z0_at_j21(growing):
    values = {"g": G, "L0": 1.0, "v0": 1.0}
    l0, k, j = vm.b_zero_length(growing.cf, growing.length, values, k=1)
    assert k == 1 and abs(float(j) - J2_ZEROS[0]) < 1e-10
    # 002: z0 = (2/v0) sqrt(g L0)  =>  L0 = (v0 j_{2,1})^2 / (4 g)
    assert abs(l0 - J2_ZEROS[0] ** 2 / (4 * G)) < 1e-10
    vb = dict(values, L0=l0)
    _, a, b = vm.closed_form_constants(growing.cf, growing.length, vb, 0.05, z0=j)
    assert abs(b / a) < 1e-25
    # with the scene's L0 instead (z0 not a zero of J2) B is not small
    _, a1, b1 = vm.closed_form_constants(growing.cf, growing.length, values, 0.05)
    assert abs(b1 / a1) > 1e-2


def test_b_zero_motion_is_one_bessel_function(growing):
    """002: theta(t) = -C L^-1/2 J1((2/v0) sqrt(g L)); C fixed by theta(0) = theta_0."""
    values = {"g": G, "L0": 1.0, "v0": 1.0}
    l0, _, _ = vm.b_zero_length(growing.cf, growing.length, values, k=1)
    vb = dict(values, L0=l0)
    tr = vm.integrate(growing.fos, growing.length, vb, 9.0, 0.05, linear=True)
    ell = l0 + tr.t
    form = ell ** -0.5 * special.jv(1, 2 * np.sqrt(G * ell))
    ref = 0.05 * form / form[0]
    assert vm.relative_agreement(tr.theta, ref) < 1e-10
    # the nearest-zero choice (k=None) from L0 = 1, v0 = 1 is k = 1 as well
    assert vm.b_zero_length(growing.cf, growing.length, values)[1] == 1


def test_b_zero_quarter_periods_are_the_sources_table(growing):
    """The swings measured from the integration (events theta = 0, theta' = 0) are 002's table."""
    values = {"g": G, "L0": 1.0, "v0": 1.0}
    l0, k, _ = vm.b_zero_length(growing.cf, growing.length, values, k=1)
    tr = vm.integrate(growing.fos, growing.length, dict(values, L0=l0), 7.0, 0.05, linear=True)
    swings = vm.quarter_periods(tr)[:6]
    measured = [(b - a) * 4 * G / 1.0 for _, a, b in swings]
    assert [s[0] for s in swings] == ["toward", "outward"] * 3
    for m, printed in zip(measured, SOURCE_QUARTERS):
        assert abs(m - printed) < 6e-5, (m, printed)
    expected = vm.zero_quarter_periods(k, 6)
    assert all(abs(m - float(e[1])) < 1e-8 for m, e in zip(measured, expected))


# -- 3. the amplitude law ----------------------------------------------------------

def _wkb_exponent(cf):
    """Amplitude exponent of the closed form stage's solution from DLMF 10.17.3.

    J_nu(z) ~ sqrt(2/(pi z)) cos(w), Y_nu(z) ~ sqrt(2/(pi z)) sin(w),
    w = z - nu pi/2 - pi/4: theta = A z^-1 J1 + B z^-1 Y1 has the envelope
    sqrt(A^2 + B^2) z^-1 sqrt(2/(pi z)); its power of z times the power of L in
    z(L) is the exponent of L.
    """
    z = S.z
    w = z - sp.pi / 2 - sp.pi / 4
    asym = {sp.besselj(1, z): sp.sqrt(2 / (sp.pi * z)) * sp.cos(w),
            sp.bessely(1, z): sp.sqrt(2 / (sp.pi * z)) * sp.sin(w)}
    wkb = cf.general_z.subs(asym)
    envelope = sp.simplify(wkb.subs({S.A: 1, S.B: 0}) / sp.cos(w))
    assert sp.simplify(wkb.subs({S.A: 0, S.B: 1}) / sp.sin(w) - envelope) == 0
    power_z = sp.simplify(z * sp.diff(sp.log(envelope), z))
    power_L = sp.simplify(S.Lvar * sp.diff(sp.log(cf.z_of_L), S.Lvar))
    return sp.nsimplify(power_z * power_L)


def test_derived_exponent_is_the_wkb_exponent_of_the_closed_form(growing):
    derived = vm.amplitude_exponent(growing.system, growing.eqs)
    assert derived == _wkb_exponent(growing.cf)
    assert derived.is_Rational


FIT_TOL = 1e-4  # linear, v0/sqrt(g L0) = 3.2e-3, L from 1 to 2: measured |fit + 3/4| = 1.7e-6


def test_fitted_exponent_matches_the_derived_one(growing):
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    exponent = float(_wkb_exponent(growing.cf))
    tr = vm.integrate(growing.fos, growing.length, values, 100.0, 0.05, linear=True)
    slope, n, _ = vm.fit_exponent(tr, growing.length)
    assert n > 60
    assert abs(slope - exponent) < FIT_TOL
    # the test discriminates: E = const (L^-1/2), L^-1 and L^-2/3 are far outside the tolerance
    for wrong in (-0.5, -1.0, -2 / 3):
        assert abs(slope - wrong) > 100 * FIT_TOL
    non = vm.integrate(growing.fos, growing.length, values, 100.0, 0.05, linear=False)
    assert abs(vm.fit_exponent(non, growing.length)[0] - exponent) < 10 * FIT_TOL


def test_fast_lengthening_breaks_the_adiabatic_law(growing):
    """v0 comparable to sqrt(g L): the fit is far from -3/4 (the law needs slow lengthening)."""
    values = {"g": G, "L0": 0.1, "v0": 1.0}
    tr = vm.integrate(growing.fos, growing.length, values, 8.0, 0.05, linear=True)
    assert abs(vm.fit_exponent(tr, growing.length)[0] - float(_wkb_exponent(growing.cf))) > 100 * FIT_TOL


# -- 4. the shortening string ----------------------------------------------------

def test_shortening_string_is_refused_at_the_zero_of_L(shortening):
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    with pytest.raises(vm.LengthReachesZeroError) as info:
        vm.integrate(shortening.fos, shortening.length, values, 150.0, 0.05)
    assert isinstance(info.value, InputError) and isinstance(info.value, PendulabError)
    assert abs(info.value.time - 100.0) < 1e-12  # L0 - v0 t = 0 at t = L0/v0
    msg = str(info.value)
    assert "\n" not in msg and "t = 100" in msg and "L0 - t*v0" in msg
    with pytest.raises(vm.LengthReachesZeroError):
        vm.integrate(shortening.fos, shortening.length, values, 100.0, 0.05)


def test_shortening_event_catches_a_zero_not_found_in_advance(shortening, monkeypatch):
    """With the a-priori zero switched off, the L(t) event stops the run and raises, no NaN."""
    monkeypatch.setattr(vm, "length_zero_time", lambda *a, **k: None)
    values = {"g": G, "L0": 1.0, "v0": 0.5}
    with pytest.raises(vm.LengthReachesZeroError) as info:
        vm.integrate(shortening.fos, shortening.length, values, 3.0, 0.05, linear=True)
    assert abs(info.value.time - 2.0) < 1e-5  # L = 1e-6 L0 at t = 2 (1 - 1e-6)


def test_shortening_string_agrees_with_the_closed_form_until_near_zero(shortening):
    values = {"g": G, "L0": 1.0, "v0": 0.01}
    tr = vm.integrate(shortening.fos, shortening.length, values, 90.0, 0.05, linear=True)
    ref = source_theta(tr.t, 0.05, G, 1.0, 0.01, sign=-1)
    assert vm.relative_agreement(tr.theta, ref) < 1e-10
    slope = vm.fit_exponent(tr, shortening.length)[0]
    assert abs(slope - float(_wkb_exponent(shortening.cf))) < FIT_TOL


def test_shortening_quarter_periods(shortening):
    """z0 = j_{2,3}, L0 - v0 t: z runs down through j_{1,3}, j_{2,2}, ..., j_{1,1} to 0 at L = 0.

    The swings are 002's durations in reverse order, then j_{2,1}^2 - j_{1,1}^2
    (A&S 9.5); the inward swing is now the shorter one.
    """
    values = {"g": G, "L0": 1.0, "v0": 1.0}
    l0, k, _ = vm.b_zero_length(shortening.cf, shortening.length, values, k=3)
    vb = dict(values, L0=l0)
    t_zero = vm.length_zero_time(shortening.length, vb)
    assert abs(t_zero - l0) < 1e-15
    tr = vm.integrate(shortening.fos, shortening.length, vb, t_zero * (1 - 1e-6), 0.05, linear=True)
    swings = vm.quarter_periods(tr)
    measured = [(b - a) * 4 * G for _, a, b in swings]
    expected = [31.5213, 32.6495, 21.6315, 22.8438, J2_ZEROS[0] ** 2 - J1_ZEROS[0] ** 2]
    assert [s[0] for s in swings[:5]] == ["toward", "outward", "toward", "outward", "toward"]
    for m, e in zip(measured, expected):
        assert abs(m - e) < 6e-5, (m, e)
    # after theta = 0 at j_{1,1} the string runs out before another turning point
    assert len(swings) == 5
    assert [k for k, _ in vm.zero_quarter_periods(3, 10, growing=False)] == ["toward", "outward"] * 2 + ["toward"]


# -- 5. periodic length: Floquet verdict, parametric resonance --------------------

def test_parametric_resonance(periodic):
    w0 = math.sqrt(G / 1.0)
    verdicts, growth = {}, {}
    for ratio in (2.0, 1.5):
        values = {"g": G, "L0": 1.0, "eps": 0.05, "Omega": ratio * w0}
        fv = vm.periodic_verdict(periodic.fos, values)
        # Liouville: det M = exp(-int 2 L'/L dt) = (L(0)/L(T))^2 = 1 over a period
        assert abs(fv.det - 1) < 1e-10
        tr = vm.integrate(periodic.fos, periodic.length, values, 40 * fv.period, 0.01, linear=True)
        verdicts[ratio], growth[ratio] = fv, vm.growth_factor(tr, fv.period)
    assert vm.verdict_word(verdicts[2.0]) == "unstable" and vm.verdict_word(verdicts[1.5]) == "stable"
    mu = max(abs(m) for m in verdicts[2.0].multipliers)
    assert growth[2.0] > 20 and growth[1.5] < 1.5
    # the long run grows at the monodromy's rate: log(growth)/N within 5% of log|mu|
    assert abs(math.log(growth[2.0]) / 40 / math.log(mu) - 1) < 0.05


def test_monodromy_against_an_implicit_integrator(periodic):
    from scipy.integrate import solve_ivp
    values = {"g": G, "L0": 1.0, "eps": 0.05, "Omega": 2 * math.sqrt(G)}
    fv = vm.periodic_verdict(periodic.fos, values)
    p = tuple(values[s.name] for s in periodic.fos.params)
    a = sp.lambdify((periodic.fos.time, periodic.fos.params), periodic.fos.linear_matrix().tolist())
    cols = []
    for y0 in ([1.0, 0.0], [0.0, 1.0]):
        sol = solve_ivp(lambda t, y: np.asarray(a(t, p), dtype=float) @ y, (0, fv.period), y0,
                        method="Radau", rtol=1e-12, atol=1e-14)
        cols.append(sol.y[:, -1])
    assert np.max(np.abs(np.column_stack(cols) - np.array(fv.matrix))) < 1e-8


def test_non_periodic_length_has_no_verdict(growing):
    with pytest.raises(InputError, match="not periodic"):
        vm.periodic_verdict(growing.fos, {"g": G, "L0": 1.0, "v0": 0.01})


# -- bad input ------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, fragment", [
    ({"t_end": -1.0}, "t_end: must be positive"),
    ({"t_end": float("nan")}, "t_end: must be a finite"),
    ({"theta_0": float("inf")}, "theta_0: must be a finite"),
    ({"values": {"g": G, "L0": 1.0}}, "needs numbers for v0"),
    ({"values": {"g": G, "L0": "x", "v0": 0.01}}, "L0: must be a number"),
    ({"values": {"g": G, "L0": -1.0, "v0": 0.01}}, "L(0)"),
])
def test_bad_integrate_arguments(growing, kwargs, fragment):
    args = {"values": {"g": G, "L0": 1.0, "v0": 0.01}, "t_end": 1.0, "theta_0": 0.05}
    args.update(kwargs)
    with pytest.raises(InputError) as info:
        vm.integrate(growing.fos, growing.length, args["values"], args["t_end"], args["theta_0"])
    assert fragment in str(info.value) and "\n" not in str(info.value)


# -- the product -----------------------------------------------------------------

FAST = "t_end = 20.0\npoints = 201\n"


def _scene(tmp_path, length, options=FAST, name="vl"):
    p = tmp_path / f"{name}.toml"
    p.write_text(f'system = "variable-length"\nname = "{name}"\n[parameters]\nlength = "{length}"\n'
                 f"[products.motion]\n{options}")
    return p


def test_product_growing_string(tmp_path):
    out = tmp_path / "out"
    build(_scene(tmp_path, "L0 + v0*t"), out_root=out, log=lambda *a: None)
    d = out / "vl"
    names = sorted(p.name for p in d.iterdir())
    assert names == ["manifest.json", "motion.json", "motion.tex", "motion_envelope.pdf",
                     "motion_envelope.png", "motion_theta.pdf", "motion_theta.png"]
    doc = json.loads((d / "motion.json").read_text())
    cf = doc["closed_form"]
    assert cf["linear_relative_agreement"] < 1e-10
    assert cf["b_zero"]["relative_agreement_with_A_J1_only"] < 1e-10
    assert float(cf["b_zero"]["B_over_A_at_the_zero"]) < 1e-25
    assert cf["b_zero"]["quarter_periods"]["max_abs_difference"] < 1e-6
    amp = doc["amplitude_law"]
    assert load_expr(amp["derived_exponent"]) == sp.Rational(-3, 4)
    assert abs(amp["fitted_exponent_linear"] + 0.75) < 10 * FIT_TOL
    assert doc["values"] == {"L0": 1.0, "g": 9.81, "v0": 0.01}
    png = (d / "motion_theta.png").read_bytes()
    pdf = (d / "motion_theta.pdf").read_bytes()
    assert png.startswith(b"\x89PNG") and b"Software" not in png
    assert pdf.startswith(b"%PDF") and b"CreationDate" not in pdf and b"Producer" not in pdf


def test_product_bytes_are_reproducible(tmp_path):
    scene = _scene(tmp_path, "L0 + v0*t", "t_end = 10.0\npoints = 101\n")
    build(scene, out_root=tmp_path / "a", log=lambda *a: None)
    build(scene, out_root=tmp_path / "b", log=lambda *a: None)
    for f in sorted((tmp_path / "a" / "vl").iterdir()):
        assert f.read_bytes() == (tmp_path / "b" / "vl" / f.name).read_bytes(), f.name
    # up to date on the second look (the manifest hashes bytes)
    status = build(scene, out_root=tmp_path / "a", log=lambda *a: None)
    assert status == {"vl": "up to date"}


def test_product_periodic_length(tmp_path):
    w0 = math.sqrt(G)
    opts = f"t_end = 20.0\npoints = 801\nvalues = {{eps = 0.05, Omega = {2 * w0!r}}}\n"
    out = tmp_path / "out"
    build(_scene(tmp_path, "L0*(1 + eps*sin(Omega*t))", opts), out_root=out, log=lambda *a: None)
    doc = json.loads((out / "vl" / "motion.json").read_text())
    assert doc["floquet"]["verdict"] == "unstable" and doc["floquet"]["growth_linear"] > 5
    assert "motion_envelope.png" not in {p.name for p in (out / "vl").iterdir()}


def test_product_shortening_string(tmp_path):
    out = tmp_path / "out"
    build(_scene(tmp_path, "L0 - v0*t", "t_end = 90.0\npoints = 901\nfigures = false\n"),
          out_root=out, log=lambda *a: None)
    doc = json.loads((out / "vl" / "motion.json").read_text())
    assert doc["length_zero_time"] == 100.0  # L0 - v0 t = 0 at t = L0/v0, beyond t_end = 90
    cf = doc["closed_form"]
    assert cf["linear_relative_agreement"] < 1e-10
    bz = cf["b_zero"]
    assert bz["L0"] >= 1.0 and bz["relative_agreement_with_A_J1_only"] < 1e-10
    qp = bz["quarter_periods"]
    assert qp["kind"][:2] == ["toward", "outward"] and qp["max_abs_difference"] < 1e-6
    # shortening: each inward swing is shorter than the outward swing before it
    m = qp["measured"]
    assert all(m[i] < m[i - 1] for i in range(2, len(m), 2))
    assert abs(doc["amplitude_law"]["fitted_exponent_linear"] + 0.75) < FIT_TOL


def test_product_shortening_beyond_zero_is_one_line_exit_2(tmp_path, capsys):
    scene = _scene(tmp_path, "L0 - v0*t", "t_end = 150.0\n")
    out = tmp_path / "out"
    assert main(["build", str(scene), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("pendulab: error:") and "\n" not in err
    assert "products.motion" in err and "reaches 0 at t = 100" in err
    assert not out.exists()


@pytest.mark.parametrize("options, key, fragment", [
    ("g = 0.0\n", "g", "must be a number above 0"),
    ("L0 = -1.0\n", "L0", "must be a number above 0"),
    ("v0 = nan\n", "v0", "NaN and infinity are not allowed"),
    ("t_end = inf\n", "t_end", "NaN and infinity are not allowed"),
    ("theta_0 = 4.0\n", "theta_0", "must be a number from -3.14159 to 3.14159"),
    ("theta_0 = 0.0\n", "theta_0", "0 < |theta_0| < pi"),
    ("g = \"9.81\"\n", "g", "must be a number"),
    ("points = 5\n", "points", "must be an integer from 11 to 100001"),
    ("t_end = 1e5\n", "t_end", "oscillations"),
    ("values = {g = 1.0}\n", "values", "give it as its own option"),
    ("values = {eps = nan}\n", "values", "NaN and infinity are not allowed"),
    ("colour = 1\n", "colour", "unknown option"),
])
def test_bad_product_options(tmp_path, options, key, fragment):
    with pytest.raises(SceneError) as info:
        build(_scene(tmp_path, "L0 + v0*t", options), out_root=tmp_path / "out", log=lambda *a: None)
    msg = str(info.value)
    # the key is named: products.motion.KEY (ranges) or products.motion: KEY (the options together)
    assert f"products.motion.{key}" in msg or f"products.motion: {key}" in msg
    assert fragment in msg and "\n" not in msg
    assert not (tmp_path / "out").exists()


def test_values_for_symbols_the_length_lacks_are_refused(tmp_path):
    with pytest.raises(SceneError) as info:
        build(_scene(tmp_path, "L0 + v0*t", FAST + "values = {eps = 0.1}\n"), out_root=tmp_path / "out",
              log=lambda *a: None)
    assert "values.eps: L(t) = L0 + t*v0 and the equation have no symbol eps" in str(info.value)


def test_missing_values_for_other_symbols(tmp_path):
    with pytest.raises(SceneError) as info:
        build(_scene(tmp_path, "L0*(1 + eps*sin(Omega*t))"), out_root=tmp_path / "out",
              log=lambda *a: None)
    assert "needs numbers for Omega, eps" in str(info.value)


@pytest.mark.skipif(shutil.which("pdflatex") is None,
                    reason="pdflatex not installed (apt-get install texlive-latex-base texlive-latex-recommended)")
@pytest.mark.parametrize("length, options", [
    ("L0 + v0*t", "t_end = 10.0\npoints = 101\nfigures = false\n"),
    ("L0*(1 + eps*sin(Omega*t))", "t_end = 10.0\npoints = 401\nfigures = false\n"
                                  "values = {eps = 0.05, Omega = 6.0}\n"),
])
def test_motion_tex_compiles_without_overfull_boxes(tmp_path, length, options):
    out = tmp_path / "out"
    build(_scene(tmp_path, length, options), out_root=out, log=lambda *a: None)
    # the bare article and the strict log check of tests/test_latex.py
    from test_latex import bare_document, log_problems
    doc = tmp_path / "notes.tex"
    doc.write_text(bare_document((out / "vl" / "motion.tex").read_text()))
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", doc.name],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    log = (tmp_path / "notes.log").read_text(errors="replace")
    assert res.returncode == 0, log[-2000:]
    assert log_problems(log) == []


@pytest.mark.slow
def test_figures_are_byte_identical_across_interpreters(tmp_path):
    """Two processes with different hash seeds write the same PNG and PDF bytes."""
    import os
    import sys
    scene = _scene(tmp_path, "L0 + v0*t", "t_end = 5.0\npoints = 51\n")
    for seed in ("1", "2"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        subprocess.run([sys.executable, "-m", "pendulab", "build", str(scene), "--out",
                        str(tmp_path / seed)], check=True, env=env, capture_output=True, timeout=300)
    for f in sorted((tmp_path / "1" / "vl").iterdir()):
        assert f.read_bytes() == (tmp_path / "2" / "vl" / f.name).read_bytes(), f.name


def test_amplitude_exponent_by_implicit_differentiation_is_the_solved_one(growing):
    """amplitude_exponent differentiates E/omega = C implicitly; solving it for the amplitude
    (sp.solve, the route it replaced) and differentiating log a gives the same exponent."""
    amp, const = sp.Symbol("a_theta", positive=True), sp.Symbol("C_inv", positive=True)
    th, ell = growing.system.coordinate, S.L(S.t)
    v = sp.sympify(growing.system.potential_energy).subs(ell, S.Lvar).subs(th, amp)
    energy = sp.series(v - v.subs(amp, 0), amp, 0, 3).removeO()
    omega = sp.sqrt(S.g / S.Lvar)  # frozen L: the linear equation L theta'' + g theta = 0
    sols = [s for s in sp.solve(sp.Eq(energy / omega, const), amp) if s.is_positive is not False]
    assert len(sols) == 1
    solved = sp.simplify(S.Lvar * sp.diff(sp.log(sols[0]), S.Lvar))
    assert vm.amplitude_exponent(growing.system, growing.eqs) == solved == sp.Rational(-3, 4)


@pytest.mark.parametrize("g, v0", [(9.81, 0.01), (9.81, -0.01), (1.0, 0.3), (9.80665, 0.0123456789),
                                   (55.06588754665608, 1.855402581384097), (0.5, 1e-5)])
def test_l0_roots_are_sympy_solves(g, v0):
    """b_zero_length's L0 from z0 = c sqrt(L0) = j (vm._l0_roots, no solver) is sp.solve's,
    Float for Float (srepr), and none when c < 0; another z0 goes to sp.solve itself."""
    j = sp.Symbol("j", positive=True)
    z0 = vm.substitute(2 * sp.sqrt(S.g) * sp.sqrt(S.L0) / S.v0, {"g": g, "v0": v0})
    assert sp.srepr(vm._l0_roots(z0, j)) == sp.srepr(sp.solve(sp.Eq(z0, j), S.L0))
    other = vm.substitute(2 * sp.sqrt(S.g) * sp.sqrt(S.L0 + 1) / S.v0, {"g": g, "v0": abs(v0)})
    assert sp.srepr(vm._l0_roots(other, j)) == sp.srepr(sp.solve(sp.Eq(other, j), S.L0))


def test_constants_in_one_lambdify_are_the_separate_ones(growing):
    """closed_form_constants evaluates A and B by one lambdify of both; each lambdified alone
    (the former route) gives the same mpmath numbers, digit for digit."""
    import mpmath
    values, th0 = {"g": G, "L0": 1.0, "v0": 0.01}, 0.05
    _, a, b = vm.closed_form_constants(growing.cf, growing.length, values, th0)
    with mpmath.workdps(40):
        z0 = vm.substitute(growing.cf.z_of_L.subs(S.Lvar, growing.length.subs(S.t, 0)), values)
        z0 = sp.lambdify((), z0, "mpmath")()
        alone = []
        for key in (S.A, S.B):
            c = vm.substitute(growing.cf.constants[key].subs(S.theta_0, sp.Float(th0, 17)), values)
            alone.append(+sp.lambdify(growing.cf.z0_symbol, c, "mpmath")(z0))
    assert (a, b) == tuple(+x for x in alone) and a != b


def test_length_function_is_formed_once_per_length_and_numbers(growing):
    f1, e1 = vm.length_function(growing.length, {"g": G, "L0": 1.0, "v0": 0.01})
    f2, e2 = vm.length_function(growing.length, {"L0": 1.0, "v0": 0.01, "g": 2.0})  # g: not in L
    f3, e3 = vm.length_function(growing.length, {"g": G, "L0": 2.0, "v0": 0.01})
    assert f1 is f2 and e1 is e2
    assert f3 is not f1 and f3(0.0) == 2.0 and f1(10.0) == 1.1
    with pytest.raises(InputError, match="needs numbers for v0"):
        vm.length_function(growing.length, {"L0": 1.0})
