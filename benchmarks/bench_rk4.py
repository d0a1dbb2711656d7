"""The source's Fig. 3 sweep with RK4 (000 sec. 4), ours against the baselines a Python user
would pick, one command:

    python benchmarks/bench_rk4.py [--repeats R] [--numpy-steps S] [--sample K] [--threads T]

(the Numba baseline needs `pip install numba`; without it that line says so and the rest runs).

The sweep as the source ran it: 10^4 pairs (a/l, omega0/omega) on linspace(0, 1, 100)^2,
the rod, theta(0) = 0.06, theta'(0) = 0.01 in tau, 300 drive periods (period pi in tau),
100 RK4 steps per period (30 000 steps, dt = pi/100), the full nonlinear equation, no early
exit, the running statistics (signed mean, mean |theta|, max |theta|) kept.

Every side is timed the same way: the best wall time of --repeats runs (default 3) after one
warm-up call (which is where Numba compiles and our kernel is compiled or loaded from the cache;
that first-call cost is printed separately), and its CPU time over the same runs.

1. Ours: pendulab.numerics.integrate.ensemble_rk4 with the compiled C kernel generated from
   the derivation (vectorisable sine), both cores.  Targets: <= 1.5 s, peak memory < 300 MB
   (peak resident set of this process after our run, the imports included).  The same kernel
   with the C library's sine beside it (what the sine costs).
2. Baseline A: a plain NumPy-vectorised RK4 over the ensemble with the lambdified RHS
   (FirstOrderSystem.lambdified), the same statistics.  Run over --numpy-steps steps (default:
   all 30 000) and scaled linearly to 30 000 if fewer.  Ours must be >= 25x faster.
3. Baseline C: what a Python user who wants speed writes: the RK4 loop compiled by Numba
   (@njit(parallel=True), prange over the trajectories, the same threads as ours), calling the
   derivation's right-hand side lambdified to scalar math and compiled by Numba (the equation is
   not typed by hand on either side), the same statistics.  Its results are compared with ours.
4. For scale only, not a speed claim: SciPy solve_ivp per trajectory with a lambdified scalar
   RHS, PyDy-style (RK45, rtol 1e-8, atol 1e-10, t_eval on the 30 001 RK4 times), on a seeded
   sample of --sample trajectories, extrapolated to 10^4.  An adaptive method at a stated
   tolerance does other work than fixed-step RK4, so the ratio says what the usual ODE-solver
   route costs, not how much faster our RK4 is.

Also printed: sine evaluations (counted from the generated code: per trajectory and RHS
evaluation, and per time level for the hoisted drive terms) and ns per RK4 step per trajectory.
"""

import argparse
import math
import os
import resource
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from pendulab.canonical import periodic_form  # noqa: E402
from pendulab.equations import derive  # noqa: E402
from pendulab.numerics import ckernel, codegen  # noqa: E402
from pendulab.numerics.integrate import default_threads, ensemble_rk4  # noqa: E402
from pendulab.numerics.model import pivot_system  # noqa: E402
from pendulab.systems import DrivenPivot  # noqa: E402

STEPS_PER_PERIOD, PERIODS, GRID = 100, 300, 100
Y0 = (0.06, 0.01)


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def timed(run, repeats):
    """(best wall s, best CPU s, last result) of ``repeats`` calls of ``run()``."""
    best, cpu, out = math.inf, math.inf, None
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        out = run()
        best = min(best, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return best, cpu, out


def numpy_baseline(fos, y0, params, dt, steps):
    """Plain vectorised RK4 with the lambdified derivation; the signed mean of theta."""
    f = fos.lambdified()
    y = y0.T.copy()
    p = params.T
    s, sa, mx = y[0].copy(), np.abs(y[0]), np.abs(y[0])
    for i in range(steps):
        t = i * dt
        k1 = f(t, y, p)
        k2 = f(t + dt / 2, y + dt / 2 * k1, p)
        k3 = f(t + dt / 2, y + dt / 2 * k2, p)
        k4 = f(t + dt, y + dt * k3, p)
        y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        s += y[0]
        sa += np.abs(y[0])
        mx = np.maximum(mx, np.abs(y[0]))
    return s / (steps + 1)


def numba_baseline(fos, threads):
    """The RK4 sweep compiled by Numba, or None where Numba is missing.  The right-hand side is
    the derivation's, lambdified to scalar math per component and compiled by Numba."""
    try:
        import numba
    except ImportError:
        return None
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    args = (fos.time, *fos.states, *fos.params)
    assert len(fos.states) == 2 and len(fos.params) == 2
    f0 = numba.njit(sp.lambdify(args, fos.rhs[0], "math"))
    f1 = numba.njit(sp.lambdify(args, fos.rhs[1], "math"))

    @numba.njit(parallel=True)
    def sweep(y0, params, t0, dt, steps):
        n = y0.shape[0]
        out = np.empty((n, 2))
        mean = np.empty(n)
        mean_abs = np.empty(n)
        max_abs = np.empty(n)
        for j in numba.prange(n):
            a, b = params[j, 0], params[j, 1]
            x, v = y0[j, 0], y0[j, 1]
            s, sa, mx = x, abs(x), abs(x)
            for i in range(steps):
                t = t0 + i * dt
                k1x, k1v = f0(t, x, v, a, b), f1(t, x, v, a, b)
                h = 0.5 * dt
                k2x = f0(t + h, x + h * k1x, v + h * k1v, a, b)
                k2v = f1(t + h, x + h * k1x, v + h * k1v, a, b)
                k3x = f0(t + h, x + h * k2x, v + h * k2v, a, b)
                k3v = f1(t + h, x + h * k2x, v + h * k2v, a, b)
                k4x = f0(t + dt, x + dt * k3x, v + dt * k3v, a, b)
                k4v = f1(t + dt, x + dt * k3x, v + dt * k3v, a, b)
                x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
                v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
                s += x
                sa += abs(x)
                mx = max(mx, abs(x))
            out[j, 0], out[j, 1] = x, v
            mean[j] = s / (steps + 1)
            mean_abs[j] = sa / (steps + 1)
            max_abs[j] = mx
        return out, mean, mean_abs, max_abs

    return sweep


def scipy_baseline(fos, params, dt, steps, sample, seed=3):
    """solve_ivp per trajectory with a lambdified scalar RHS; (s and CPU s per trajectory, n)."""
    from scipy.integrate import solve_ivp
    fn = sp.lambdify((fos.time, fos.states, fos.params), list(fos.rhs), "math")
    rng = np.random.default_rng(seed)
    rows = rng.choice(len(params), size=sample, replace=False)
    times = dt * np.arange(steps + 1)
    t0, c0 = time.perf_counter(), time.process_time()
    for r in rows:
        p = tuple(params[r])
        sol = solve_ivp(lambda t, y, p=p: fn(t, y, p), (0.0, times[-1]), list(Y0),
                        method="RK45", rtol=1e-8, atol=1e-10, t_eval=times)
        th = sol.y[0]
        _ = (th.mean(), np.abs(th).mean(), np.abs(th).max())
    return (time.perf_counter() - t0) / sample, (time.process_time() - c0) / sample, sample


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3,
                    help="timed runs of every side (the best is quoted)")
    ap.add_argument("--numpy-steps", type=int, default=PERIODS * STEPS_PER_PERIOD)
    ap.add_argument("--sample", type=int, default=12)
    ap.add_argument("--threads", type=int, default=default_threads())
    args = ap.parse_args()

    eqs = derive(DrivenPivot(body="rod"))
    fos = pivot_system(eqs, periodic_form(eqs))
    g = np.linspace(0.0, 1.0, GRID)
    a_l, w_w = np.meshgrid(g, g, indexing="ij")
    params = np.column_stack([a_l.ravel(), w_w.ravel()])          # (a_over_l, w0_over_w)
    assert [s.name for s in fos.params] == ["a_over_l", "w0_over_w"]
    n = len(params)
    y0 = np.tile(Y0, (n, 1))
    steps = PERIODS * STEPS_PER_PERIOD
    dt = float(fos.period) / STEPS_PER_PERIOD
    print(f"Fig. 3 sweep: {n} trajectories x {steps} RK4 steps (dt = pi/{STEPS_PER_PERIOD}), "
          f"{args.threads} threads, rod, y0 = {Y0}")

    t = time.perf_counter()
    kernel = ckernel.load(fos, required=True)
    print(f"kernel: compile or cache load {time.perf_counter() - t:.2f} s, flags "
          f"{' '.join(kernel.flags)}")
    ensemble_rk4(fos, y0[:64], params[:64], 0.0, dt, 10, threads=args.threads)  # warm

    reps = args.repeats
    best, cpu, res = timed(
        lambda: ensemble_rk4(fos, y0, params, 0.0, dt, steps, threads=args.threads), reps)
    mem = peak_mb()
    t = time.perf_counter()
    *lib, _reruns = kernel.ensemble(y0, params, 0.0, dt, steps, threads=args.threads,
                                    library_sine=True)
    t_lib = time.perf_counter() - t
    traj_steps = n * steps
    info = codegen.kernel_info(fos)
    lane_sines = info.lane_trig[0] * 4 * traj_steps
    blocks = -(-n // codegen.LANES)
    time_cos = info.time_trig[0] * 3 * steps * blocks
    stable = int(np.sum(np.abs(res.mean_theta) < 0.1))
    print(f"ours (C, vectorisable sine): {best:.3f} s (best of {reps}; target <= 1.5 s), "
          f"peak memory {mem:.0f} MB (target < 300 MB), trajectories rerun {res.exact_trajectories}")
    print(f"  {best / traj_steps * 1e9:.2f} ns per RK4 step per trajectory (wall); CPU time "
          f"{cpu:.3f} s = {cpu / traj_steps * 1e9:.2f} ns per step per trajectory per core; "
          f"load average now {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"  sine evaluations: {lane_sines:.3e} of theta ({info.lane_trig[0]} per RHS, 4 RHS "
          f"per step) + {time_cos:.3e} cos(2 tau) (hoisted: 3 time levels per step per block "
          f"of {codegen.LANES}); {best / lane_sines * 1e9:.3f} ns per sine incl. the step")
    dev = max(float(np.max(np.abs(res.y - lib[0]))), 0.0)
    print(f"same kernel, C library sine: {t_lib:.3f} s ({t_lib / best:.2f}x ours); "
          f"max |y difference| {dev:.1e}; criterion mean: {stable} stable points")

    t = time.perf_counter()
    sweep = numba_baseline(fos, args.threads)
    if sweep is None:
        print("baseline C, Numba-compiled parallel RK4: not run (pip install numba)")
    else:
        sweep(y0[:64], params[:64], 0.0, dt, 10)                    # warm: Numba compiles
        first = time.perf_counter() - t
        t_nb, c_nb, nb = timed(lambda: sweep(y0, params, 0.0, dt, steps), reps)
        both = (np.abs(nb[1]) < 0.1) & (np.abs(res.mean_theta) < 0.1)
        dev = float(np.max(np.abs(nb[0][both] - res.y[both]), initial=0.0))
        differ = int(np.sum((np.abs(nb[1]) < 0.1) != (np.abs(res.mean_theta) < 0.1)))
        print(f"baseline C, Numba-compiled parallel RK4 (njit(parallel=True), prange, the "
              f"lambdified derivation njit-compiled): {t_nb:.3f} s (best of {reps}; compile "
              f"{first:.1f} s once); criterion mean: {int(np.sum(np.abs(nb[1]) < 0.1))} stable "
              f"points, {differ} verdicts differ from ours; max |y - ours| over the "
              f"{int(both.sum())} stable in both: {dev:.1e}")
        print(f"  ours {best:.3f} s, baseline {t_nb:.3f} s, ratio {t_nb / best:.2f}x; by CPU "
              f"time: ours {cpu:.2f} s, baseline {c_nb:.2f} s, ratio {c_nb / cpu:.2f}x")

    t_np, c_np, mean_np = timed(
        lambda: numpy_baseline(fos, y0, params, dt, args.numpy_steps), reps)
    scaled = t_np * steps / args.numpy_steps
    scaled_cpu = c_np * steps / args.numpy_steps
    note = "" if args.numpy_steps == steps else f" (ran {args.numpy_steps} steps, scaled)"
    if args.numpy_steps == steps:
        note += f"; criterion mean: {int(np.sum(np.abs(mean_np) < 0.1))} stable points"
    print(f"baseline A, NumPy-vectorised RK4 (lambdified RHS): {scaled:.2f} s (best of "
          f"{reps}){note}")
    print(f"  ours {best:.3f} s, baseline {scaled:.2f} s, ratio {scaled / best:.0f}x "
          f"(target >= 25x); by CPU time: ours {cpu:.2f} s, baseline {scaled_cpu:.2f} s, "
          f"ratio {scaled_cpu / cpu:.0f}x (x{args.threads} threads: "
          f"{scaled_cpu / cpu * args.threads:.0f}x on an idle machine)")

    per, per_cpu, k = scipy_baseline(fos, params, dt, steps, args.sample)
    total = per * n
    print(f"for scale, not a speed claim: solve_ivp per trajectory (adaptive RK45 at rtol 1e-8, "
          f"lambdified; other work than fixed-step RK4): {per:.2f} s per trajectory on {k} "
          f"sampled, extrapolated to {n}: {total:.0f} s, {total / best:.0f}x our time")


if __name__ == "__main__":
    main()
