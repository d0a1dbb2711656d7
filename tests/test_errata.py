"""pendulab.products.errata: every misprint it lists is one, shown by a method of its own.

Each entry's "found" is checked here against something the errata module does
not use: the Lagrangian formed from the coordinates, torques from lever arms,
Kapitza's effective potential averaged by quadrature (Landau & Lifshitz,
Mechanics, sec. 30), SciPy's Mathieu characteristic value a_0 (DLMF 28.2.16,
28.6.1), SciPy's and mpmath's Bessel functions (DLMF 10.8.1 for the series of
Y_1), SciPy's DOP853 integration of 002 eq. 4, a NumPy RK4 of 000 sec. 4's
equation, and SymPy's unit system.  Each "printed" must differ from "found"
numerically (an entry that is not a misprint fails).  Equations typed below
are the sources' own, as reference, never fed to pendulab.
"""

import math
import re
import shutil
import subprocess

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy import special
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from pendulab.products import errata

FIELDS = ("source", "where", "printed", "found", "evidence", "text")


@pytest.fixture(scope="module")
def cases():
    return {(c.source, c.where): c for c in errata.cases()}


def _value(expr, point):
    """A SymPy object evaluated at ``point`` (symbol name -> number): a complex or a tuple."""
    rep = {s: point[s.name] for s in expr.free_symbols}
    missing = {s.name for s in expr.free_symbols} - set(point)
    assert not missing, f"no value for {missing}"
    if isinstance(expr, sp.Tuple):
        return tuple(complex(sp.N(e.subs(rep), 20)) for e in expr)
    return complex(sp.N(expr.subs(rep), 20))


# ---------------------------------------------------------------------------
# the shape of the entries
# ---------------------------------------------------------------------------

def test_every_entry_has_every_field_in_both_languages():
    entries = errata.entries()
    assert len(entries) == len(errata.cases()) >= 10
    for e in entries:
        assert tuple(e) == FIELDS
        assert e["source"] in ("000", "002")
        for key in FIELDS[1:5]:
            assert isinstance(e[key], str) and e[key].strip(), (e["where"], key)
        assert set(e["text"]) == {"en", "pt"}
        assert all(isinstance(v, str) and len(v.split()) >= 5 for v in e["text"].values())
        assert e["text"]["en"] != e["text"]["pt"]
        assert "$" not in e["printed"] and "$" not in e["found"]   # bare math
        assert e["printed"] != e["found"]
        assert e["evidence"].count("$") % 2 == 0                 # math closed in the evidence
        # the builders flag a computation that did not confirm them with "[...]"
        assert "[" not in e["evidence"].replace("\\left[", "").replace("\\right]", ""), e["evidence"]
        assert "nan" not in e["evidence"].lower()


def _outside_math(tex):
    return re.sub(r"\$[^$]*\$", "", tex)


def test_the_text_fields_are_latex_text():
    """where, evidence and the sentences go into running text: math only between $...$."""
    for e in errata.entries():
        for value in (e["where"], e["evidence"], e["text"]["en"], e["text"]["pt"]):
            assert value.count("$") % 2 == 0, value
            bare = _outside_math(value)
            assert not set(bare) & set("^_#%&\\{}"), (value, bare)


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex not installed")
def test_the_entries_compile(tmp_path):
    items = []
    for e in errata.entries():
        items.append(f"\\paragraph{{{e['source']}, {e['where']}.}} {e['text']['en']} {e['text']['pt']}\n"
                     f"\\begin{{itemize}}\\item ${e['printed']}$\n\\item ${e['found']}$\n"
                     f"\\item {e['evidence']}\n\\end{{itemize}}\n")
    doc = ("\\documentclass{article}\\usepackage[utf8]{inputenc}"
           "\\usepackage{amsmath,amssymb}\\begin{document}\n" + "".join(items) + "\\end{document}\n")
    (tmp_path / "e.tex").write_text(doc)
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "e.tex"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stdout[-3000:]


def test_entries_are_fresh_dicts():
    first = errata.entries()
    first[0]["text"]["en"] = "changed"
    assert errata.entries()[0]["text"]["en"] != "changed"


def test_every_case_has_an_independent_check_here(cases):
    assert set(cases) == set(CHECKS), set(cases) ^ set(CHECKS)


def test_printed_differs_from_found(cases):
    for key, c in cases.items():
        if c.printed_expr is None:
            continue  # a statement, not a formula: its check below shows the difference
        p, f = _value(c.printed_expr, c.point), _value(c.found_expr, c.point)
        if isinstance(p, tuple):
            assert p != f, key
        else:
            assert abs(p - f) > 1e-6 * max(abs(f), 1e-300), key




# ---------------------------------------------------------------------------
# 000
# ---------------------------------------------------------------------------

def _lagrangian_cross_term():
    """The theta'-y0' term of T - V formed from the coordinates (000 eq. 2 and after)."""
    t, m, l, I0, g = sp.symbols("t m l I0 g", positive=True)
    th, y0 = sp.Function("th")(t), sp.Function("y0")(t)
    x, y = l * sp.sin(th), y0 + l * sp.cos(th)
    T = m * (x.diff(t)**2 + y.diff(t)**2) / 2 + I0 * th.diff(t)**2 / 2
    lag = sp.expand(T - m * g * y)
    d_th, d_y0 = sp.Symbol("d_th"), sp.Symbol("d_y0")
    lag = lag.subs({th.diff(t): d_th, y0.diff(t): d_y0})
    cross = sp.Add(*[term for term in sp.Add.make_args(lag) if term.has(d_th) and term.has(d_y0)])
    return cross, {"m": m, "l": l, "theta": th, "d_th": d_th, "d_y0": d_y0, "y0": y0}


def check_lagrangian(c, _):
    cross, s = _lagrangian_cross_term()
    p = c.point
    ours = cross.subs(s["theta"], p[r"\theta"]).subs({s["m"]: p["m"], s["l"]: p["l"],
                                                      s["d_th"]: p[r"\dot{\theta}"], s["d_y0"]: p[r"\dot{y}_0"]})
    assert abs(_value(c.found_expr, p) - float(ours)) < 1e-12
    assert c.data["euler_lagrange_matches_stage"]


def _lever_torque(force_y, angle, l=1.0):
    """Torque of a vertical force on the centre of mass (l sin angle, l cos angle) about the pivot,
    counted clockwise, the sense in which the source's theta grows: -(x F_y - y F_x)."""
    return -(l * mpmath.sin(angle) * force_y)


def _drive_acceleration(a, omega, t):
    return -a * omega**2 * mpmath.cos(omega * t)  # y0 = a cos(omega t), 000 eq. 1


def check_eq13(c, _):
    # I delta'' = inertial torque at theta = psi (the force -m y0'' of the pivot's frame), mean 0
    p = c.point
    t = sp.Symbol("t", real=True)
    delta = c.found_expr.subs({s: p[s.name] for s in c.found_expr.free_symbols if s.name != "t"})
    delta_t = sp.lambdify(t, delta, "mpmath")
    accel = sp.lambdify(t, delta.diff(t, 2), "mpmath")
    for tv in (0.0, 0.03, 0.1, 0.25):
        force = -p["m"] * _drive_acceleration(p["a"], p["omega"], tv)
        torque = _lever_torque(force, p["psi"], p["l"])
        assert abs(p["I"] * accel(tv) - torque) < 1e-12
    period = 2 * math.pi / p["omega"]
    assert abs(mpmath.quad(delta_t, [0, period])) < 1e-15
    # the source's sign and amplitude do not solve it
    printed = c.printed_expr.subs({s: p[s.name] for s in c.printed_expr.free_symbols if s.name != "t"})
    tv = 0.1
    force = -p["m"] * _drive_acceleration(p["a"], p["omega"], tv)
    assert abs(p["I"] * float(printed.diff(t, 2).subs(t, tv)) - _lever_torque(force, p["psi"], p["l"])) > 1e-4


def check_eq14(c, _):
    p = c.point
    force = -p["m"] * _drive_acceleration(p["a"], p["omega"], p["t"])
    assert abs(_value(c.found_expr, p) - _lever_torque(force, p[r"\theta"], p["l"])) < 1e-12
    # the same lever-arm rule gives the source's gravitational torque m g l sin theta (eq. 17)
    m, g, l, th = 1.0, 9.81, p["l"], p[r"\theta"]
    assert abs(_lever_torque(-m * g, th, l) - m * g * l * mpmath.sin(th)) < 1e-12


def _kapitza_inertial_torque(psi, a, l, m, I, omega):
    """-d/dpsi <f^2>/(2 I omega^2), f the fast torque at psi (Landau & Lifshitz sec. 30),
    the mean taken by quadrature."""
    period = 2 * mpmath.pi / omega

    def u(ps):
        f2 = lambda t: (_lever_torque(-m * _drive_acceleration(a, omega, t), ps, l))**2
        return mpmath.quad(f2, [0, period]) / period / (2 * I * omega**2)
    return -mpmath.diff(u, psi)


def check_eq16(c, _):
    p = c.point
    ours = _kapitza_inertial_torque(p["psi"], p["a"], p["l"], p["m"], p["I"], p["omega"])
    assert abs(_value(c.found_expr, p) - float(ours)) < 1e-9 * abs(float(ours))
    assert c.data["kapitza_agrees"]


def _exact_lower_limit(rho, r):
    """a/l where a_0(q) = theta0 = -4 rho^2, q = theta1 = 2 (a/l)/r (000 eqs. 5-7 with
    DLMF 28.2.16: a_0 is even in q), by SciPy's mathieu_a."""
    q = brentq(lambda q: special.mathieu_a(0, q) + 4 * rho**2, 1e-9, 2.0, xtol=1e-14)
    return q * r / 2


def check_eq19(c, _):
    r = c.point["inertia_ratio"]
    for rho in (0.01, 0.02):
        exact = _exact_lower_limit(rho, r)
        pt = {"inertia_ratio": r, "w0_over_w": rho}
        found, printed = _value(c.found_expr, pt).real, _value(c.printed_expr, pt).real
        assert abs(found / exact - 1) < 0.5 * rho**2   # the next term is (7/16) rho^2 (DLMF 28.6.1)
        assert abs(printed / exact - 1) > 0.1
    rho = float(errata.EQ19_W0_OVER_W)
    assert abs(c.data["exact"] / _exact_lower_limit(rho, r) - 1) < 1e-6


def check_psi_m(c, _):
    p = c.point
    r, rho, al = p["inertia_ratio"], p["w0_over_w"], p["a_over_l"]
    m, l, omega = 1.0, 1.0, 1.0
    I, g, a = r * m * l**2, r * rho**2 * omega**2 * l, al * l   # omega0^2 = m g l/I
    with mpmath.workdps(20):
        torque = lambda ps: (m * g * l * mpmath.sin(ps)
                             + _kapitza_inertial_torque(ps, a, l, m, I, omega))
        # the averaged torques balance once between 1.2 and 1.45 rad (69 and 83 degrees)
        peak = mpmath.findroot(torque, (1.2, 1.45), solver="illinois")
        assert 1.2 < peak < 1.45
    assert abs(_value(c.found_expr, p).real - float(peak)) < 1e-8
    assert abs(c.data["kapitza"] - float(peak) * 180 / math.pi) < 1e-6


def _rk4_counts(initial, grid=10, periods=300, steps=100):
    """Stable pairs by |mean theta| < 0.1 (the mean over every step, the start included) on the
    10 x 10 grid of 000 sec. 4 for a rod, one count per initial condition, by RK4 on
    d2theta/dtau2 + (-4 (w0/w)^2 + 4 (m l^2/I)(a/l) cos 2 tau) sin theta = 0 (000 sec. 4)."""
    vals = np.linspace(0.0, 1.0, grid)
    al, rho = np.meshgrid(vals, vals)
    n = al.size
    al, rho = np.tile(al.ravel(), len(initial)), np.tile(rho.ravel(), len(initial))
    th = np.repeat([float(p[0]) for p in initial], n)
    om = np.repeat([float(p[1]) for p in initial], n)
    total = th.copy()
    h = math.pi / steps
    c0, c1 = 4 * rho**2, -4 * (3 / 4) * al          # the rod: m l^2/I = 3/4
    cos_half = [math.cos(2 * (k * h + h / 2)) for k in range(steps)]
    cos_start = [math.cos(2 * k * h) for k in range(steps + 1)]
    for period in range(periods):
        for k in range(steps):
            w0, wh, w1 = c0 + c1 * cos_start[k], c0 + c1 * cos_half[k], c0 + c1 * cos_start[k + 1]
            k1t, k1o = om, w0 * np.sin(th)
            k2t, k2o = om + h / 2 * k1o, wh * np.sin(th + h / 2 * k1t)
            k3t, k3o = om + h / 2 * k2o, wh * np.sin(th + h / 2 * k2t)
            k4t, k4o = om + h * k3o, w1 * np.sin(th + h * k3t)
            th = th + h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t)
            om = om + h / 6 * (k1o + 2 * k2o + 2 * k3o + k4o)
            total += th
    stable = np.abs(total / (periods * steps + 1)) < 0.1
    return [int(stable[i * n:(i + 1) * n].sum()) for i in range(len(initial))]


def check_fig3(c, _):
    found = tuple(float(x) for x in c.found_expr)
    printed = tuple(float(x) for x in c.printed_expr)
    # 000 sec. 4: the text's 14-pair initial condition, the one Fig. 5's caption repeats
    assert found == (0.06, 0.01)
    at_found, at_printed = _rk4_counts([found, printed])
    # the text: 14 stable pairs at Fig. 3's initial condition; chaotic cells may tip by one
    assert abs(at_found - 14) <= 1
    assert abs(at_printed - 14) >= 3
    assert abs(c.data["counts"]["text"] - at_found) <= 1
    assert abs(c.data["counts"]["caption"] - at_printed) <= 1


# ---------------------------------------------------------------------------
# 002
# ---------------------------------------------------------------------------

G, V0 = 9.81, 0.05


@pytest.fixture(scope="module")
def string_motion():
    """002 eq. 4, L theta'' + 2 L' theta' + g theta = 0 with L = L0 + v0 t, integrated by SciPy's
    DOP853 from theta = 0.1, theta' = 0 at z0 = j_2,1 (L0 = (z0 v0/2)^2/g), with dense output."""
    z0 = special.jn_zeros(2, 1)[0]
    L0 = (z0 * V0 / 2) ** 2 / G

    def rhs(t, y):
        L = L0 + V0 * t
        return [y[1], -(2 * V0 * y[1] + G * y[0]) / L]
    t_end = 60.0
    sol = solve_ivp(rhs, (0, t_end), [0.1, 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
                    dense_output=True)
    assert sol.success
    return {"sol": sol, "L0": L0, "z0": z0, "theta0": 0.1, "t_end": t_end}


def _z_of_t(motion, t):
    return 2 / V0 * math.sqrt(G * (motion["L0"] + V0 * t))


def _t_of_z(motion, z):
    return ((z * V0 / 2) ** 2 / G - motion["L0"]) / V0


def check_references(c, _):
    t, v0, g, L0 = sp.symbols("t v0 g L0", positive=True)
    Lv = sp.Symbol("L", positive=True)
    Theta = sp.Function("Theta")
    L = L0 + v0 * t
    th = Theta(L)
    eq4 = 2 * L.diff(t) * th.diff(t) + L * th.diff(t, 2) + g * th          # 002 eq. 4
    eq3 = 2 * L.diff(t) * th.diff(t) + L * th.diff(t, 2) + g * sp.sin(th)  # 002 eq. 3
    TL = Theta(Lv)
    line = Lv * v0**2 * TL.diff(Lv, 2) + 2 * v0**2 * TL.diff(Lv) + g * TL   # the line 002 prints

    def in_l(expr):
        return sp.expand(expr.doit().subs(L, Lv).subs(t, (Lv - L0) / v0))
    assert sp.simplify(in_l(eq4) - line) == 0
    assert sp.simplify(in_l(eq3) - line) != 0
    ours = c.data["length_equation"]
    free = {s.name: s for s in ours.free_symbols}
    theta = [f for f in ours.atoms(sp.Function) if f.func.__name__ == "theta"][0]
    ours = ours.subs(theta, Theta(free["L"])).subs({free["L"]: Lv, free["v0"]: v0, free["g"]: g})
    assert sp.simplify(ours.doit() - line) == 0
    assert tuple(c.found_expr) == (5, 6, 4) and tuple(c.printed_expr) != tuple(c.found_expr)


def check_eq7(c, _):
    g, v0 = c.point["g"], c.point["v0"]
    with mpmath.workdps(30):
        for bessel in (mpmath.besselj, mpmath.bessely):
            theta = lambda L: bessel(1, 2 / v0 * mpmath.sqrt(g * L)) / (2 / v0 * mpmath.sqrt(g * L))
            for Lv in (0.3, 2.0):
                pt = {"L": Lv, r"\theta": theta(Lv), r"\theta_L": mpmath.diff(theta, Lv),
                      r"\theta_{LL}": mpmath.diff(theta, Lv, 2), "g": g, "v0": v0}
                pt = {k: float(v) for k, v in pt.items()}
                scale = abs(pt[r"\theta"]) * g / v0**2 * Lv
                assert abs(_value(c.found_expr, pt)) < 1e-12 * scale
                assert abs(_value(c.printed_expr, pt)) > 1e-3 * scale


def check_y1(c, _):
    for z in (0.5, 2.0, 5.0):
        found = _value(c.found_expr, {"z": z}).real
        assert abs(found - special.y1(z)) < 1e-13
        with mpmath.workdps(30):
            assert abs(found - float(mpmath.bessely(1, z))) < 1e-13
        assert abs(_value(c.printed_expr, {"z": z}).real - special.y1(z)) > 1e-3
    assert c.data["ball_decides"]


def _initial_value_constants(z0, theta0):
    """A, B of theta = A z^-1 J1 + B z^-1 Y1 with theta(z0) = theta0, dtheta/dz(z0) = 0 (mpmath)."""
    with mpmath.workdps(30):
        fj = lambda z: mpmath.besselj(1, z) / z
        fy = lambda z: mpmath.bessely(1, z) / z
        M = mpmath.matrix([[fj(z0), fy(z0)], [mpmath.diff(fj, z0), mpmath.diff(fy, z0)]])
        A, B = mpmath.lu_solve(M, mpmath.matrix([theta0, 0]))
    return float(A), float(B)


def check_b(c, _):
    p = c.point
    _, B = _initial_value_constants(p["z0"], p["theta_0"])
    assert abs(_value(c.found_expr, p).real - B) < 1e-12 * abs(B)


def check_theta_z(c, _):
    p = c.point
    z0, theta0 = p["z0"], p["theta_0"]
    A, B = _initial_value_constants(z0, theta0)
    for z in (z0, 4.0, 9.5):
        ref = (A * special.jv(1, z) + B * special.yv(1, z)) / z
        assert abs(_value(c.found_expr, dict(p, z=z)).real - ref) < 1e-12
    assert abs(_value(c.printed_expr, dict(p, z=z0)).real - theta0) > 0.1 * theta0


def check_c(c, motion):
    sol = motion["sol"]
    pt = {"g": G, "L0": motion["L0"], "v0": V0, "theta_0": motion["theta0"]}
    C_found = _value(c.found_expr, pt).real
    C_printed = _value(c.printed_expr, pt).real
    for t in (5.0, 30.0, 55.0):
        z = _z_of_t(motion, t)
        shape = -special.jv(1, z) / math.sqrt(motion["L0"] + V0 * t)
        assert abs(C_found * shape - sol.sol(t)[0]) < 1e-8
        assert abs(C_printed * shape - sol.sol(t)[0]) > 1e-3


def check_item1(c, motion):
    sol = motion["sol"]
    j1 = special.jn_zeros(1, 2)
    j2 = special.jn_zeros(2, 2)
    # the first zero crossing of the integrated theta(t): where J1(z) = 0, z = j_1,2
    t_cross = brentq(lambda t: sol.sol(t)[0], 0.0, _t_of_z(motion, (j1[1] + j2[1]) / 2), xtol=1e-13)
    assert abs(_z_of_t(motion, t_cross) - j1[1]) < 1e-7
    assert abs(sol.sol(t_cross)[1]) > 1e-3   # theta' (so d theta/dz) is not 0 there
    # at z = j_2,2 theta' = 0 and theta = -0.487... theta_0, a turning point, not theta = 0
    t2 = _t_of_z(motion, j2[1])
    assert abs(sol.sol(t2)[1]) < 1e-9
    ratio = sol.sol(t2)[0] / motion["theta0"]
    assert abs(ratio) > 0.4 and abs(float(c.data["theta_at_j22"]) - ratio) < 1e-8
    assert abs(float(c.data["theta_at_j12"])) < 1e-25


def check_caption(c, _):
    j0, j1, j2 = (special.jn_zeros(n, 2) for n in (0, 1, 2))
    assert f"{j1[1] ** 2 - j2[0] ** 2:.4f}" == "22.8438" == c.data["text"][:7]   # 002's table
    assert abs(float(c.data["caption"]) - (j0[1] ** 2 - j1[0] ** 2)) < 1e-4
    assert abs((j0[1] ** 2 - j1[0] ** 2) - 22.8438) > 1
    # the functions named: zeros of found's J1(sqrt x) lie at j_1,k^2, of the printed J0 elsewhere
    x = j1[1] ** 2
    assert abs(_value(c.found_expr, {"x": x})[0]) < 1e-12
    assert abs(_value(c.printed_expr, {"x": x})[0]) > 0.1


def check_unit(c, motion):
    from sympy.physics.units import acceleration, time, velocity
    from sympy.physics.units.systems.si import dimsys_SI
    assert dimsys_SI.equivalent_dims(velocity / acceleration, time)
    assert not dimsys_SI.equivalent_dims(velocity / acceleration, sp.physics.units.length)
    # the first quarter period in seconds is (v0/(4 g)) (j_1,2^2 - j_2,1^2)
    sol = motion["sol"]
    j1, j2 = special.jn_zeros(1, 2), special.jn_zeros(2, 1)
    t_cross = brentq(lambda t: sol.sol(t)[0], 0.0, _t_of_z(motion, j1[1] + 0.5), xtol=1e-13)
    per_z2 = float(c.data["time_per_z2"].subs({s: {"v0": V0, "g": G}[s.name]
                                               for s in c.data["time_per_z2"].free_symbols}))
    assert abs(t_cross - per_z2 * (j1[1] ** 2 - j2[0] ** 2)) < 1e-8
    assert abs(per_z2 - V0 / (4 * G)) < 1e-15


CHECKS = {
    ("000", "after eq. 2, the Lagrangian"): check_lagrangian,
    ("000", "eq. 13"): check_eq13,
    ("000", "eq. 14"): check_eq14,
    ("000", "eq. 16"): check_eq16,
    ("000", "eq. 19"): check_eq19,
    ("000", r"after eq. 19, $\psi_M$"): check_psi_m,
    ("000", "sec. 4, Fig. 3 caption"): check_fig3,
    ("002", "before eqs. 5 and 7, equation numbers"): check_references,
    ("002", "eq. 7"): check_eq7,
    ("002", "Demonstração, series of $Y_1$"): check_y1,
    ("002", "Consequência, $B$"): check_b,
    ("002", r"Consequência, $\theta(z)$"): check_theta_z,
    ("002", "Consequência, $C$"): check_c,
    ("002", "item 1"): check_item1,
    ("002", "Figure 1 caption"): check_caption,
    ("002", "quarter periods, the unit"): check_unit,
}


@pytest.mark.parametrize("key", sorted(CHECKS), ids=lambda k: f"{k[0]} {k[1]}")
def test_found_agrees_with_an_independent_check(cases, key, string_motion):
    CHECKS[key](cases[key], string_motion)
