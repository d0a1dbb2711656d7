"""The scalar DOP853 (pendulab.numerics.dop853) against solve_ivp, closed forms and mpmath.

Provenance of the references:
* the old route, SciPy's solve_ivp(method="DOP853") on the generated NumPy module
  (SciPy's solve_ivp on the generated NumPy module, below): same method, so the
  states agree to rounding and the evaluation counts are equal;
* y'' = -y from (1, 0): y = cos t, y' = -sin t, zeros of y at pi/2 + k pi (closed form);
* the rod's nonlinear equation (the derivation's ``fos.rhs`` lambdified for mpmath)
  by mpmath.odefun (a Taylor series method) at 30 digits.
"""

import math

import mpmath
import numpy as np
import pytest
import sympy as sp

from pendulab.errors import InputError
from pendulab.numerics import dop853
from pendulab.numerics.integrate import reference_trajectory

from test_codegen import system  # noqa: E402



def _reference_solve_ivp(fos, y0, params, t_eval, *, linear=False, rtol=1e-13, atol=1e-15):
    """The former reference, the independent method compared with: SciPy's
    solve_ivp(method="DOP853") on the generated NumPy module; (states, nfev)."""
    from scipy.integrate import solve_ivp

    from pendulab.numerics.codegen import numpy_functions
    f = numpy_functions(fos)["linear_rhs" if linear else "rhs"]
    pc = np.asarray(params, float).reshape(-1, 1)
    t_eval = np.asarray(t_eval, float)
    with np.errstate(all="ignore"):
        sol = solve_ivp(lambda t, y: f(t, y, pc), (t_eval[0], t_eval[-1]), np.asarray(y0, float),
                        method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol, vectorized=True)
    return sol.y.T.copy(), sol.nfev

def oscillator(t, a, b):
    return b, -a


def test_oscillator_closed_form_and_events():
    t = np.linspace(0.0, 50.0, 2001).tolist()

    def zero(t, a, b):
        return a
    zero.direction = -1  # only downward crossings: pi/2 + 2k pi
    tt, ya, yb, found, nfev, stopped = dop853.solve(oscillator, t, (1.0, 0.0), 1e-13, 1e-15,
                                                    events=(zero,))
    assert not stopped and tt == t
    assert np.max(np.abs(np.array(ya) - np.cos(t))) < 1e-11
    assert np.max(np.abs(np.array(yb) + np.sin(t))) < 1e-11
    ev = np.array(found[0][0])
    expected = math.pi / 2 + 2 * math.pi * np.arange(len(ev))
    assert len(ev) == 8 and np.max(np.abs(ev - expected)) < 1e-11
    assert max(abs(s[0]) for s in found[0][1]) < 1e-11


def test_terminal_event_stops_the_outputs():
    def zero(t, a, b):
        return a
    zero.terminal = True
    t = np.linspace(0.0, 5.0, 11).tolist()
    tt, ya, yb, found, nfev, stopped = dop853.solve(oscillator, t, (1.0, 0.0), 1e-13, 1e-15,
                                                    events=(zero,))
    assert stopped and abs(found[0][0][0] - math.pi / 2) < 1e-12
    assert tt == t[:4]  # 0, 0.5, 1.0, 1.5 < pi/2


def test_evaluation_bound_and_overflow():
    t = np.linspace(0.0, 50.0, 11).tolist()
    with pytest.raises(dop853.TooManyEvaluations):
        dop853.solve(oscillator, t, (1.0, 0.0), 1e-13, 1e-15, max_evaluations=100)

    def blowup(t, a, b):
        return a * a, 0.0  # y = 1/(1 - t): infinite at t = 1 (solve_ivp: the step collapses)
    with pytest.raises((dop853.NotFinite, dop853.StepTooSmall)):
        dop853.solve(blowup, [0.0, 2.0], (1.0, 0.0), 1e-13, 1e-15)


@pytest.mark.parametrize("linear", [False, True])
def test_same_as_solve_ivp(linear):
    fos = system("rod")
    t = math.pi / 100 * np.arange(3001)
    ours = reference_trajectory(fos, [0.3, 0.01], [0.2, 0.05], t, linear=linear)
    old, nfev = _reference_solve_ivp(fos, [0.3, 0.01], [0.2, 0.05], t, linear=linear)
    assert np.max(np.abs(ours - old)) < 1e-12
    f = _scalar(fos, linear)
    _, _, _, _, our_nfev, _ = dop853.solve(lambda s, a, b: tuple(f(s, (a, b), (0.2, 0.05))),
                                           t.tolist(), (0.3, 0.01), 1e-13, 1e-15)
    # the same steps (12 evaluations each, 3 more per dense output, 2 to start); solve_ivp
    # counts one dense output more (measured: 19355 against 19352 for the nonlinear case)
    assert abs(our_nfev - nfev) <= 3


def _scalar(fos, linear):
    from pendulab.numerics.codegen import scalar_function
    return scalar_function(fos, linear)


def test_rod_against_mpmath_taylor():
    fos = system("rod")
    p = {s: v for s, v in zip(fos.params, (0.2, 0.05))}
    exprs = [sp.sympify(e).subs(p) for e in fos.rhs]
    fn = sp.lambdify((fos.time, *fos.states), exprs, "mpmath")
    times = [0.0, 2.5, 5.0, 7.5, 10.0]
    with mpmath.workdps(30):
        sol = mpmath.odefun(lambda s, y: fn(s, y[0], y[1]), 0, [mpmath.mpf("0.3"), mpmath.mpf("0.01")])
        exact = np.array([[float(c) for c in sol(mpmath.mpf(x))] for x in times])
    ours = reference_trajectory(fos, [0.3, 0.01], [0.2, 0.05], times)
    assert np.max(np.abs(ours - exact)) < 1e-12
    # the test can fail: a 100-fold looser tolerance is visibly further off
    loose = reference_trajectory(fos, [0.3, 0.01], [0.2, 0.05], times, rtol=1e-7, atol=1e-9)
    assert np.max(np.abs(loose - exact)) > 1e-12


def test_overflow_is_an_input_error():
    fos = system("rod")
    with pytest.raises(InputError, match="overflowed|evaluations"):
        reference_trajectory(fos, [0.3, 1e200], [0.2, 0.05], [0.0, 10.0])


def test_step_too_small():
    def stiff(t, a, b):  # y' = -1/(1-t)^3 ... a singularity the step cannot cross
        return 1.0 / (1.0 - t) ** 2 if t != 1.0 else math.inf, 0.0
    with pytest.raises((dop853.StepTooSmall, dop853.NotFinite)):
        dop853.solve(stiff, [0.0, 2.0], (1.0, 0.0), 1e-13, 1e-15)


def test_variable_length_t_eval_outside_the_span():
    from pendulab.analyses import variable_length_motion as vm
    from pendulab.equations import derive
    from pendulab.exprs import parse
    from pendulab.numerics.model import length_system
    from pendulab.systems import VariableLength
    system = VariableLength(length=parse("L0 + v0*t"))
    fos = length_system(derive(system))
    values = {"g": 9.81, "L0": 1.0, "v0": 0.01}
    with pytest.raises(InputError, match="t_eval"):
        vm.integrate(fos, system.length, values, 1.0, 0.05, t_eval=[0.0, 2.0])
    tr = vm.integrate(fos, system.length, values, 1.0, 0.05, t_eval=[0.5, 1.0])
    assert tr.t.tolist() == [0.5, 1.0] and len(tr.theta) == 2


def test_tables_read_from_the_file_are_scipys():
    """dop853._tables loads SciPy's coefficient module from its file (no scipy.integrate
    package initialisation); its arrays are those of the module imported by name."""
    import subprocess
    import sys
    code = ("import sys\n"
            "from pendulab.numerics import dop853\n"
            "mine = dop853._tables()\n"
            "assert 'scipy.integrate' not in sys.modules\n"
            "import numpy as np\n"
            "from scipy.integrate._ivp import dop853_coefficients as D\n"
            "names = [n for n in dir(D) if n.isupper()]\n"
            "assert names and all(np.array_equal(getattr(mine, n), getattr(D, n)) for n in names)\n"
            "assert dop853._tables() is not None\n"
            "print(len(names))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert int(out.stdout) >= 8  # N_STAGES, A, B, C, E3, E5, D and more
