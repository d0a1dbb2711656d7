"""The source's Fig. 3 sweep with RK4 (000 sec. 4), ours against two baselines, one command:

    python benchmarks/bench_rk4.py [--numpy-steps S] [--sample K] [--threads T]

The sweep as the source ran it: 10^4 pairs (a/l, omega0/omega) on linspace(0, 1, 100)^2,
the rod, theta(0) = 0.06, theta'(0) = 0.01 in tau, 300 drive periods (period pi in tau),
100 RK4 steps per period (30 000 steps, dt = pi/100), the full nonlinear equation, no early
exit, the running statistics (signed mean, mean |theta|, max |theta|) kept.

1. Ours: pendulab.numerics.integrate.ensemble_rk4 with the compiled C kernel generated from
   the derivation (vectorisable sine), both cores.  Targets: <= 1.5 s, peak memory < 300 MB
   (peak resident set of this process after our run, the imports included).  The same kernel
   with the C library's sine beside it (what the sine costs).
2. Baseline A: a plain NumPy-vectorised RK4 over the ensemble with the lambdified RHS
   (FirstOrderSystem.lambdified), the same statistics.  Run over --numpy-steps steps (default:
   all 30 000) and scaled linearly to 30 000 if fewer.  Ours must be >= 25x faster.
3. Baseline B: SciPy solve_ivp per trajectory with a lambdified scalar RHS, PyDy-style (RK45,
   rtol 1e-8, atol 1e-10, t_eval on the 30 001 RK4 times for the statistics), on a seeded sample
   of --sample trajectories, extrapolated to 10^4.  Ours must be >= 2000x faster.

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


def numpy_baseline(fos, y0, params, dt, steps):
    """Plain vectorised RK4 with the lambdified derivation; (seconds, CPU s, signed mean)."""
    f = fos.lambdified()
    y = y0.T.copy()
    p = params.T
    s, sa, mx = y[0].copy(), np.abs(y[0]), np.abs(y[0])
    t0, c0 = time.perf_counter(), time.process_time()
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
    return time.perf_counter() - t0, time.process_time() - c0, s / (steps + 1)


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

    best, cpu = math.inf, math.inf
    for _ in range(3):
        t, c = time.perf_counter(), time.process_time()
        res = ensemble_rk4(fos, y0, params, 0.0, dt, steps, threads=args.threads)
        best = min(best, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
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
    print(f"ours (C, vectorisable sine): {best:.3f} s (best of 3; target <= 1.5 s), "
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

    t_np, c_np, mean_np = numpy_baseline(fos, y0, params, dt, args.numpy_steps)
    scaled = t_np * steps / args.numpy_steps
    scaled_cpu = c_np * steps / args.numpy_steps
    note = "" if args.numpy_steps == steps else f" (ran {args.numpy_steps} steps, scaled)"
    if args.numpy_steps == steps:
        note += f"; criterion mean: {int(np.sum(np.abs(mean_np) < 0.1))} stable points"
    print(f"baseline A, NumPy-vectorised RK4 (lambdified RHS): {scaled:.2f} s{note}")
    print(f"  ours {best:.3f} s, baseline {scaled:.2f} s, ratio {scaled / best:.0f}x "
          f"(target >= 25x); by CPU time: ours {cpu:.2f} s, baseline {scaled_cpu:.2f} s, "
          f"ratio {scaled_cpu / cpu:.0f}x (x{args.threads} threads: "
          f"{scaled_cpu / cpu * args.threads:.0f}x on an idle machine)")

    per, per_cpu, k = scipy_baseline(fos, params, dt, steps, args.sample)
    total = per * n
    print(f"baseline B, solve_ivp per trajectory (RK45 rtol 1e-8, lambdified): {per:.2f} s per "
          f"trajectory on {k} sampled, extrapolated to {n}: {total:.0f} s")
    print(f"  ours {best:.3f} s, baseline {total:.0f} s, ratio {total / best:.0f}x "
          f"(target >= 2000x); by CPU time {per_cpu * n / cpu:.0f}x "
          f"(x{args.threads} threads: {per_cpu * n / cpu * args.threads:.0f}x on an idle machine)")


if __name__ == "__main__":
    main()
