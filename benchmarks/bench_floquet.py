"""Speed of the exact Floquet analysis, one command:

    python benchmarks/bench_floquet.py

1. Exact stable/unstable map of the inverted pendulum on a 1000 x 1000 grid of
   (a/l, omega0/omega) in [0, 1]^2 (point mass): pendulab.analyses.floquet.
   stability_map (characteristic values per row + vectorised comparison).
   Target: <= 2 s.
2. lambda at 50 digits per point (characteristic_exponent, method "hill",
   and "cf"), averaged over a few points.  Target: <= 20 ms per point.
3. The monodromy-matrix approach with scipy.integrate.solve_ivp (DOP853,
   rtol 1e-10) on a random subsample of the grid; the time per point is
   extrapolated to the full grid (said so in the output), and the verdicts of
   the subsample are compared with the map.  The ratio is printed from this run.
4. Per point: lambda at 50 digits (hill, cf) beside solve_ivp's time per point
   (which gives only a double-precision trace, rtol 1e-10) and their ratio.
"""

import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from pendulab.analyses.floquet import characteristic_exponent, stability_map  # noqa: E402


def monodromy_trace_scipy(theta0, theta1):
    def rhs(t, y):
        p = theta0 + 2 * theta1 * np.cos(2 * t)
        return [y[1], -p * y[0], y[3], -p * y[2]]
    sol = solve_ivp(rhs, (0.0, np.pi), [1.0, 0.0, 0.0, 1.0], method="DOP853",
                    rtol=1e-10, atol=1e-12)
    return sol.y[0, -1] + sol.y[3, -1]


def main():
    n = 1000
    al = np.linspace(0.0, 1.0, n)
    ratio = np.linspace(0.0, 1.0, n)
    stability_map(al[:10], ratio[:10])  # imports and first-call set-up
    t = time.perf_counter()
    smap = stability_map(al, ratio)
    t_map = time.perf_counter() - t
    print(f"exact map {n}x{n}: {t_map:.3f} s  (target <= 2 s); stable points: {int(smap.sum())}")

    pts = [("-0.002", "0.2"), ("-0.04", "0.3"), ("-0.25", "1.1"), ("0.5", "0.7"), ("-1", "2.5")]
    per = {}
    for method in ("hill", "cf"):
        characteristic_exponent(*pts[0], dps=50, method=method)
        t = time.perf_counter()
        for p in pts:
            characteristic_exponent(*p, dps=50, method=method)
        per[method] = (time.perf_counter() - t) / len(pts)
        print(f"lambda at 50 digits ({method}): {1e3 * per[method]:.1f} ms per point  (target <= 20 ms)")

    rng = np.random.default_rng(4)
    m = 300
    ii = rng.integers(0, n, m)
    jj = rng.integers(0, n, m)
    t = time.perf_counter()
    traces = [monodromy_trace_scipy(-4 * ratio[i] ** 2, 2 * al[j]) for i, j in zip(ii, jj)]
    t_sub = time.perf_counter() - t
    per_point = t_sub / m
    t_full = per_point * n * n
    verdict = np.abs(np.array(traces)) < 2
    clear = np.abs(np.abs(np.array(traces)) - 2) > 1e-6
    agree = np.array_equal(verdict[clear], smap[ii, jj][clear])
    print(f"solve_ivp monodromy: {1e3 * per_point:.2f} ms per point on a {m}-point subsample; "
          f"extrapolated to {n}x{n}: {t_full:.0f} s")
    print(f"ratio (solve_ivp extrapolated / exact map): {t_full / t_map:.0f}x; "
          f"verdicts agree on the subsample: {agree} ({int(clear.sum())} points clear of the curves)")
    for method in ("hill", "cf"):
        print(f"per point: lambda at 50 digits ({method}) {1e3 * per[method]:.1f} ms vs solve_ivp "
              f"(double, rtol 1e-10) {1e3 * per_point:.2f} ms; ratio {per[method] / per_point:.1f}x")


if __name__ == "__main__":
    main()
