"""The RK4 step check (pendulab.numerics.step_check): the bound, its refusals, its warnings.

The stability limit is computed here independently of the code: the amplification polynomial
of classical RK4, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24 (Butcher, "Numerical Methods for
Ordinary Differential Equations"; Hairer-Wanner II, sec. IV.2), on the imaginary axis, by
numpy's polynomial roots and by bisection.  max |q| is compared with the canonical stage's
own (theta0, theta1), and a refused step is shown to make RK4 itself grow.
"""

import json
import math
from fractions import Fraction

import numpy as np
import pytest

from pendulab.cli import main
from pendulab.errors import InputError
from pendulab.numerics import step_check as SC
from pendulab.numerics import sweep as S

#: The RK4 amplification polynomial, coefficients 1/k! for k = 0..4 (lowest first).
RK4_R = [1.0 / math.factorial(k) for k in range(5)]


def _abs_r_squared_minus_one():
    """|R(iy)|^2 - 1 as a real polynomial in y (lowest first), from R's coefficients."""
    r_iy = np.array([c * (1j) ** k for k, c in enumerate(RK4_R)])  # R(iy) in powers of y
    prod = np.polynomial.polynomial.polymul(r_iy, np.conj(r_iy))
    prod[0] -= 1
    assert np.allclose(prod.imag, 0)
    return prod.real


def imaginary_limit_by_roots():
    roots = np.polynomial.polynomial.polyroots(_abs_r_squared_minus_one())
    real = sorted(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 1e-6)
    return real[0]


def imaginary_limit_by_bisection():
    def f(y):
        return abs(np.polyval(RK4_R[::-1], 1j * y)) - 1
    lo, hi = 1.0, 4.0  # |R(i)| < 1, |R(4i)| > 1
    assert f(lo) < 0 < f(hi)
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if f(mid) <= 0 else (lo, mid)
    return lo


def test_the_imaginary_axis_limit_is_rk4s_own():
    by_roots, by_bisection = imaginary_limit_by_roots(), imaginary_limit_by_bisection()
    assert by_roots == pytest.approx(by_bisection, rel=1e-12)
    assert SC.RK4_IMAGINARY_LIMIT == pytest.approx(by_roots, rel=1e-12)
    # and it is where the region meets the axis: |R(iy)| <= 1 below, > 1 above
    ys = np.linspace(1e-3, by_roots * (1 - 1e-9), 2001)
    assert np.all(np.abs(np.polyval(RK4_R[::-1], 1j * ys)) <= 1 + 1e-15)
    assert abs(np.polyval(RK4_R[::-1], 1j * by_roots * (1 + 1e-6))) > 1


@pytest.mark.parametrize("system", [S.SystemSpec("rod"), S.SystemSpec("point"),
                                    S.SystemSpec("explicit", inertia_ratio=2.5),
                                    S.SystemSpec("rod", angle="down")])
def test_max_q_is_that_of_the_canonical_theta0_theta1(system):
    """max over tau of |theta0 + 2 theta1 cos 2 tau| = |theta0| + 2 |theta1| (000 eq. 7), with
    the pair from the canonical stage, against the check's grid maximum of the first-order
    system's own coefficient."""
    a = np.array([0.0, 0.1, 0.7, 3.0])
    w = np.array([0.05, 0.0, 0.9, 2.0])
    theta0, theta1 = (np.broadcast_to(np.asarray(v, float), a.shape)
                      for v in S.mathieu_pair(system)(a, w))
    fos = S.first_order_system(system)
    for k in range(len(a)):
        spec = S.make_spec(system, a_over_l=[a[k]], w0_over_w=[w[k]], steps_per_period=100)
        found = SC.check_spec(spec)
        assert found.rate ** 2 == pytest.approx(abs(theta0[k]) + 2 * abs(theta1[k]), rel=1e-13)
        assert found.harmonic == (2.0 if a[k] else 0.0)
    assert float(fos.period) == pytest.approx(math.pi)


def test_the_grid_maximum_of_a_hill_drive_is_bracketed():
    """Two harmonics (q has cos 2 tau and cos 4 tau): the grid max and its Bernstein bound
    bracket the maximum over 200001 points of the first-order system's linearised rhs."""
    system = S.SystemSpec("rod", drive="a*cos(omega*t) + a*cos(2*omega*t)")
    fos = S.first_order_system(system)
    params = {"a_over_l": 0.3, "w0_over_w": 0.4}
    p = [params[s.name] for s in fos.params]
    tau = np.linspace(0, math.pi, 200001)
    f = fos.lambdified(linear=True)
    dense = np.max(np.abs(f(tau, np.array([np.ones_like(tau), np.zeros_like(tau)]), p)[1]))
    found = SC.check_step(fos, 0.01, [p])
    assert found.harmonic == 4.0
    assert found.rate ** 2 <= dense * (1 + 1e-12)
    assert dense <= found.rate_upper ** 2 * (1 + 1e-12)


def _rod_a_for(stiffness, steps):
    """a/l of the rod at omega0/omega = 0 whose step pi/steps has h sqrt(max|q|) = stiffness:
    max |q| = 2 |theta1| = 3 a/l (000 eq. 6, theta1 = 2 (a/l)/(I/(m l^2)), I/(m l^2) = 4/3)."""
    rate = stiffness * steps / math.pi
    return float(rate ** 2 / 3)


def test_a_step_just_above_the_bound_is_refused_just_below_accepted(capsys):
    limit = imaginary_limit_by_roots()  # the test's own limit, not the module's constant
    steps = 100
    above = _rod_a_for(limit * (1 + 1e-6), steps)
    below = _rod_a_for(limit * (1 - 1e-6), steps)
    argv = ["simulate", "--w0-over-w", "0", "--periods", "1", "--steps-per-period", str(steps),
            "--every", "100", "--json"]
    assert main(argv + ["--a-over-l", repr(above)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and "unstable" in err and "--steps-per-period 100" in err
    assert "2*sqrt(2)" in err and "at least 101 steps" in err
    assert main(argv + ["--a-over-l", repr(below)]) == 0
    out, err = capsys.readouterr()
    record = json.loads(out)
    assert "stable but coarse" in record["step_warning"] and "warning" in err


def test_the_check_refuses_a_wrong_too_large_step():
    """A candidate step 1e-9 beyond the limit for the derived rate is refused; 1e-9 inside it
    passes (the check is sharp at the bound, in both directions)."""
    fos = S.first_order_system(S.SystemSpec("rod", angle="down"))
    p = {"a_over_l": 0.0, "w0_over_w": 3.0}  # |q| = 4 (omega0/omega)^2 = 36, no drive harmonic
    row = [[p[s.name] for s in fos.params]]
    rate = math.sqrt(36.0)
    limit = imaginary_limit_by_bisection()
    wrong = SC.check_step(fos, limit / rate * (1 + 1e-9), row)
    assert wrong.unstable == 1 and wrong.refusal("dt").startswith("dt: the RK4 step")
    right = SC.check_step(fos, limit / rate * (1 - 1e-9), row)
    assert right.unstable == 0 and right.refusal("dt") is None and right.warning("dt")


def _rk4_amplitude(c, h, steps):
    """Largest |x| of classical RK4 (written here, not pendulab's) on x'' + c x = 0 from
    x = 1, x' = 0, in the coordinates (x, x'/sqrt(c)) where the exact flow is a rotation."""
    def f(y):
        return np.array([y[1], -c * y[0]])
    y, top = np.array([1.0, 0.0]), 1.0
    for _ in range(steps):
        k1 = f(y)
        k2 = f(y + h / 2 * k1)
        k3 = f(y + h / 2 * k2)
        k4 = f(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        top = max(top, math.hypot(y[0], y[1] / math.sqrt(c)))
    return top


def test_a_refused_step_really_grows_under_rk4():
    """x'' + 36 x = 0 (frozen |q| = 36): RK4 just beyond the step the check refuses grows,
    just inside it does not; the check is given the same rate by a system with max|q| = 36."""
    fos = S.first_order_system(S.SystemSpec("rod"))
    row = [[{"a_over_l": 0.0, "w0_over_w": 3.0}[s.name] for s in fos.params]]  # q = -4 * 9
    limit = imaginary_limit_by_bisection()
    for factor, grows in ((1.01, True), (0.99, False)):
        dt = limit / 6.0 * factor
        assert bool(SC.check_step(fos, dt, row).unstable) == grows
        top = _rk4_amplitude(36.0, dt, 3000)
        assert (top > 10.0) if grows else (top <= 1.0 + 1e-9), (factor, top)


def test_one_step_per_period_aliases_the_drive(capsys):
    """One RK4 step per drive period samples cos 2 tau at tau = 0, pi/2, pi only; the run is
    refused where the drive is on (a/l > 0) and accepted without it (a/l = 0)."""
    base = ["simulate", "--w0-over-w", "0.05", "--periods", "10", "--steps-per-period", "1",
            "--every", "10"]
    assert main(base + ["--a-over-l", "0.1"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "aliased" in err and err.count("\n") == 1
    assert main(base + ["--a-over-l", "0"]) == 0
    out, err = capsys.readouterr()
    assert "mean theta" in out and err == ""
    # two steps per period: accepted, with the warning (the measured error there is 5 rad)
    assert main(base + ["--a-over-l", "0.1", "--steps-per-period", "2"]) == 0
    out, err = capsys.readouterr()
    assert "stable but coarse" in err and "13 or more steps" in err


def test_the_default_steps_are_silent(capsys):
    assert main(["simulate", "--a-over-l", "0.1", "--w0-over-w", "0.05", "--periods", "2"]) == 0
    assert capsys.readouterr().err == ""


def test_sweep_at_one_step_per_period_is_refused(capsys):
    assert main(["sweep", "--steps-per-period", "1", "--quiet", "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "a_over_l = 1, w0_over_w = 1" in err and "of 100 cells" in err
    # the floquet criterion integrates nothing: no step to check
    assert main(["sweep", "--steps-per-period", "1", "--quiet", "--criterion", "floquet",
                 "--grid", "3"]) == 0
    assert capsys.readouterr().err == ""


def test_sweep_warns_about_a_coarse_step_in_text_and_json(capsys):
    assert main(["sweep", "--steps-per-period", "4", "--periods", "2", "--grid", "3",
                 "--quiet", "--json"]) == 0
    out, err = capsys.readouterr()
    assert "stable but coarse" in json.loads(out)["step_warning"]
    assert err.startswith("pendulab: warning: --steps-per-period 4")


SCENE = """name = "{name}"
system = "kapitza"
description = "a step check"

[parameters]
body = "rod"
drive = "a*cos(omega*t)"
angle = "up"

[products.experiments]
maps = ["text"]
grid = 3
periods = 2
steps_per_period = {steps}
criteria = ["mean"]
fig5 = false
fig2 = false
figures = false
"""


def test_a_scene_with_an_unstable_step_is_refused_naming_file_and_key(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text(SCENE.format(name="bad-step", steps=1))
    out = tmp_path / "out"
    assert main(["build", str(scene), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"{scene}: products.experiments: steps_per_period = 1: the RK4 step" in err
    assert not (out / "bad-step").exists()


def test_the_rule_on_fractions_of_the_bound():
    """Below WARN_RATE and resolving the drive: silent; between WARN_RATE and the limit:
    warned; beyond: refused (no drive: q constant, the hanging pendulum)."""
    fos = S.first_order_system(S.SystemSpec("rod", angle="down"))
    row = [[{"a_over_l": 0.0, "w0_over_w": 0.5}[s.name] for s in fos.params]]  # |q| = 1
    for stiffness, unstable, inaccurate in ((0.99, 0, 0), (1.01, 0, 1), (2.8, 0, 1),
                                            (2.83, 1, 0)):
        found = SC.check_step(fos, stiffness, row)
        assert (found.unstable, found.inaccurate) == (unstable, inaccurate), stiffness
    assert float(Fraction(SC.WARN_RATE)) < SC.RK4_IMAGINARY_LIMIT


def test_a_system_not_of_the_pendulum_shape_is_refused():
    import sympy as sp

    from pendulab.numerics.model import DTHETA, THETA
    fos = S.first_order_system(S.SystemSpec("rod"))
    from dataclasses import replace
    damped = replace(fos, rhs=(DTHETA, fos.rhs[1] - DTHETA / 10))
    with pytest.raises(InputError, match="needs theta'' = -q"):
        SC.check_step(damped, 0.01, [[0.1, 0.05]])
    cubic = replace(fos, rhs=(DTHETA, fos.rhs[1] + THETA ** 3), name=fos.name + "-cubic")
    with pytest.raises(InputError, match="needs theta''"):
        SC.check_step(cubic, 0.01, [[0.1, 0.05]])
    assert sp.diff(fos.rhs[1], DTHETA) == 0


@pytest.mark.parametrize("drive, words", [
    # a harmonic far beyond any step: refused at once, before a grid of its cycles is built
    ("a*cos(omega*t)+a*cos(10**60*omega*t)", "turns 1e+60 times per drive period"),
    # a coefficient beyond double precision: one line, not an OverflowError
    ("1e308*a*cos(omega*t)", "too large for double precision"),
])
@pytest.mark.parametrize("command", [
    ["simulate", "--a-over-l", "0.3", "--w0-over-w", "0.1", "--periods", "5"],
    ["sweep", "--grid", "2", "--periods", "1"],
])
def test_a_drive_the_step_check_cannot_take_is_one_line(command, drive, words, capsys):
    from pendulab.cli import main
    assert main(command + ["--drive", drive]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert out == "" and len(lines) == 1 and words in lines[0], err
