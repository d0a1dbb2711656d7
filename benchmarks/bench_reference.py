"""The adaptive DOP853 references, ours against SciPy's solve_ivp, one command:

    python benchmarks/bench_reference.py [--repeat R]

1. reference_trajectory (pendulab.numerics.integrate): the rod of kapitza-experiments,
   a/l = 0.2, omega0/omega = 0.05, theta(0) = 0.06, theta'(0) = 0.01, 300 drive periods at
   100 RK4 times each (30 001 output times), rtol 1e-13, atol 1e-15, nonlinear and linear.
   Ours: the scalar DOP853 (pendulab.numerics.dop853) on the generated scalar right-hand
   side; baseline: solve_ivp(method="DOP853") on the generated NumPy module (the former
   route, reference_solve_ivp below).
2. variable_length_motion.integrate: the scene variable-length (L = L0 + v0 t, g 9.81,
   L0 1, v0 0.01, theta_0 0.05, t_end 100, 2001 points, the three events), linear and
   nonlinear.  Baseline: solve_ivp(method="DOP853") with the same scalar right-hand side,
   tolerances and events (the former body of integrate).

Each line prints ours, the baseline and their ratio from the same run (best of --repeat),
and the largest difference between the two answers.
"""

import argparse
import math
import time

import numpy as np


def best(fn, repeat):
    out, times = None, []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def rod():
    from pendulab.canonical import periodic_form
    from pendulab.equations import derive
    from pendulab.numerics.model import pivot_system
    from pendulab.systems import DrivenPivot
    eqs = derive(DrivenPivot(body="rod"))
    return pivot_system(eqs, periodic_form(eqs))


def length_scene():
    from pendulab.equations import derive
    from pendulab.exprs import parse
    from pendulab.numerics.model import length_system
    from pendulab.systems import VariableLength
    system = VariableLength(length=parse("L0 + v0*t"))
    return length_system(derive(system)), system.length


def old_integrate(fos, length, values, t_end, theta_0, linear, points):
    """The former body of variable_length_motion.integrate (solve_ivp, same events)."""
    from scipy.integrate import solve_ivp

    from pendulab.analyses import variable_length_motion as vm
    p = vm._param_values(fos.params, values, "the equation of motion")
    lfun, _ = vm.length_function(length, values)
    f = vm._rhs(fos, linear)
    floor = vm.LENGTH_FLOOR * lfun(0.0)

    def short(t, y):
        return lfun(t) - floor
    short.terminal, short.direction = True, -1
    atol = vm.RTOL * 1e-3 * abs(theta_0)
    sol = solve_ivp(lambda t, y: f(t, (y[0], y[1]), p), (0.0, t_end), [theta_0, 0.0],
                    method="DOP853", rtol=vm.RTOL, atol=atol, t_eval=np.linspace(0.0, t_end, points),
                    events=(short, lambda t, y: y[1], lambda t, y: y[0]))
    return sol.y[0]



def reference_solve_ivp(fos, y0, params, t_eval, linear):
    """The former reference (the baseline): solve_ivp(method="DOP853") on the generated
    NumPy module, vectorized; (states, nfev)."""
    from scipy.integrate import solve_ivp

    from pendulab.numerics.codegen import numpy_functions
    f = numpy_functions(fos)["linear_rhs" if linear else "rhs"]
    pc = np.asarray(params, float).reshape(-1, 1)
    with np.errstate(all="ignore"):
        sol = solve_ivp(lambda t, y: f(t, y, pc), (t_eval[0], t_eval[-1]), np.asarray(y0, float),
                        method="DOP853", t_eval=t_eval, rtol=1e-13, atol=1e-15, vectorized=True)
    return sol.y.T.copy(), sol.nfev

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    from pendulab.analyses import variable_length_motion as vm
    from pendulab.numerics import integrate as I

    fos = rod()
    t = math.pi / 100 * np.arange(300 * 100 + 1)
    y0, p = [0.06, 0.01], [0.2, 0.05]
    I.reference_trajectory(fos, y0, p, t[:3])  # generate and compile outside the timings
    I.reference_trajectory(fos, y0, p, t[:3], linear=True)
    print("reference_trajectory, rod, 30 001 times, rtol 1e-13:")
    for linear in (False, True):
        ours, a = best(lambda: I.reference_trajectory(fos, y0, p, t, linear=linear), args.repeat)
        base, (b, nfev) = best(lambda: reference_solve_ivp(fos, y0, p, t, linear),
                               args.repeat)
        print(f"  {'linear   ' if linear else 'nonlinear'}  ours {ours:7.3f} s   solve_ivp {base:7.3f} s"
              f"   ratio {base / ours:5.1f}x   max |diff| {np.max(np.abs(a - b)):.1e}"
              f"   solve_ivp nfev {nfev}")

    lfos, length = length_scene()
    values = {"g": 9.81, "L0": 1.0, "v0": 0.01}
    vm.integrate(lfos, length, values, 1.0, 0.05, linear=True, points=3)
    vm.integrate(lfos, length, values, 1.0, 0.05, linear=False, points=3)
    print("variable_length_motion.integrate, L0 + v0 t, t_end 100, 2001 points, rtol 1e-13:")
    for linear in (True, False):
        ours, a = best(lambda: vm.integrate(lfos, length, values, 100.0, 0.05, linear=linear),
                       args.repeat)
        base, b = best(lambda: old_integrate(lfos, length, values, 100.0, 0.05, linear, 2001),
                       args.repeat)
        print(f"  {'linear   ' if linear else 'nonlinear'}  ours {ours:7.3f} s   solve_ivp {base:7.3f} s"
              f"   ratio {base / ours:5.1f}x   max |diff| {np.max(np.abs(a.theta - b)):.1e}"
              f"   nfev {a.nfev}")


if __name__ == "__main__":
    main()
