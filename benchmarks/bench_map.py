"""Speed of the inverted pendulum's exact map and of the vectorised exponent and
inverse, one command:

    python benchmarks/bench_map.py

1. stability_map for the rod (I/(m l^2) = 4/3) on 1000 x 1000 and 4000 x 4000
   grids of a/l in [0, 1] x omega0/omega in [0, 1] (targets: 10 ms and 0.2 s),
   beside the SciPy baseline written here: scipy.special.mathieu_a(0, q) and
   mathieu_b(1, q) for the grid's q = 2 (a/l)/(4/3), then theta0 = -4 ratio^2
   compared with them (first band only; 000 eqs. 5-6).  Best of 5 (3 for the
   large grid).  Prints the number of cells that needed an exact decision, the
   agreement with the baseline, and with characteristic_exponent's pointwise
   verdicts at the exact values of the grid's doubles on a random sample.
2. The vectorised exponent and inverse on MathieuFunctions.jl's lambda grid
   (nu = 0, 0.01, ..., 2; q = -5, -4.99, ..., 5; 201 x 1001 points), per
   point, beside scipy.special.mathieu_a on the same grid with the order
   m = floor(nu) (the order must be an integer for SciPy: for non-integer
   nu it returns nan without computing, which is timed too).  Ours with the C
   band kernel (pendulab.numerics.ckernel) and with its NumPy fallback
   (PENDULAB_BAND_NUMPY=1), in the same run; they must give the same bits.
3. With the full grid file of MathieuFunctions.jl (test/MathieuCharacteristicL-1.csv,
   Mathematica's values; not shipped, a 17-row extract is in tests/data/):

       python benchmarks/bench_map.py path/to/MathieuCharacteristicL-1.csv

   the accuracy of the inverse on all 201 x 1001 points (relative to
   max(1, |lambda|)) and the backward error of the exponent (|lam - nu| times
   d lambda/d nu from the grid's rows, relative to max(1, |lambda|)).
"""

import os
import sys
import time
from fractions import Fraction

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numpy as np  # noqa: E402
import scipy.special as sc  # noqa: E402

from pendulab.analyses.floquet import (  # noqa: E402
    characteristic_exponent, exponent, theta0_of_exponent,
)
from pendulab.analyses.stability_map import map_stability, stability_map  # noqa: E402

INERTIA = 4.0 / 3.0


def best(fn, repeat):
    """Best wall-clock time of ``repeat`` runs (the machine is shared: the CPU
    time of the same runs is in CPU[-1])."""
    times, cpu = [], []
    out = None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        times.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    CPU.append(min(cpu))
    return min(times), out


CPU = []


def scipy_map(al, ratio):
    q = 2.0 * al / INERTIA
    lo = sc.mathieu_a(0, q)
    up = sc.mathieu_b(1, q)
    th0 = -4.0 * ratio[:, None] ** 2
    return (th0 > lo[None, :]) & (th0 < up[None, :])


def maps():
    rng = np.random.default_rng(12)
    stability_map(np.linspace(0, 1, 10), np.linspace(0, 1, 10), INERTIA)  # derivation, imports
    for n, target, repeat in ((1000, 0.010, 5), (4000, 0.2, 3)):
        al = np.linspace(0.0, 1.0, n)
        ratio = np.linspace(0.0, 1.0, n)
        t_ours, m = best(lambda: stability_map(al, ratio, INERTIA), repeat)
        c_ours = CPU[-1]
        exact_cells = map_stability.last_exact
        t_sp, ref = best(lambda: scipy_map(al, ratio), repeat)
        c_sp = CPU[-1]
        print(f"map {n}x{n} (rod): ours {1e3 * t_ours:.2f} ms (target <= {1e3 * target:g} ms), "
              f"SciPy a_0/b_1 + compare {1e3 * t_sp:.2f} ms, ratio ours/SciPy "
              f"{t_ours / t_sp:.2f} (CPU time: {1e3 * c_ours:.2f} / {1e3 * c_sp:.2f} ms); "
              f"stable cells {int(m.sum())}")
        print(f"    cells decided exactly (within the error bound of a curve): {exact_cells} "
              f"of {n * n}; cells where the SciPy first-band map differs: "
              f"{int(np.count_nonzero(m != ref))}")
        k = 60 if n == 1000 else 30
        ii, jj = rng.integers(0, n, k), rng.integers(0, n, k)
        agree = sum(bool(m[i, j]) == characteristic_exponent(
            -4 * Fraction(float(ratio[i])) ** 2,
            2 * Fraction(float(al[j])) / Fraction(INERTIA)).stable for i, j in zip(ii, jj))
        print(f"    pointwise exact verdicts (characteristic_exponent, exact inputs) on "
              f"{k} random cells: {agree}/{k} agree")


def grid():
    nu = np.round(np.arange(201) * 0.01, 2)[:, None]
    q = np.round(np.arange(-500, 501) * 0.01, 2)[None, :]
    return np.broadcast_arrays(nu, q)


def _ours(NU, Q, numpy_path):
    """Best times of the inverse and the exponent on the grid, with the C band
    kernel or (``numpy_path``) its NumPy fallback."""
    if numpy_path:
        os.environ["PENDULAB_BAND_NUMPY"] = "1"
    else:
        os.environ.pop("PENDULAB_BAND_NUMPY", None)
    try:
        theta0_of_exponent(NU[:3, :5], -Q[:3, :5])
        t_inv, th = best(lambda: theta0_of_exponent(NU, -Q), 3)
        c_inv = CPU[-1]
        t_exp, lam = best(lambda: exponent(th, -Q), 3)
        c_exp = CPU[-1]
    finally:
        os.environ.pop("PENDULAB_BAND_NUMPY", None)
    return t_inv, c_inv, t_exp, c_exp, th, lam


def vectorised():
    from pendulab.analyses.floquet._vectorised import _c_band

    NU, Q = grid()
    npts = NU.size
    have_c = _c_band() is not None
    runs = [("C kernel", False)] if have_c else []
    runs.append(("NumPy fallback", True))
    res = {label: _ours(NU, Q, numpy_path) for label, numpy_path in runs}
    M = np.floor(NU)
    t_sp, _ = best(lambda: sc.mathieu_a(M, Q), 3)
    c_sp = CPU[-1]
    t_nan, _ = best(lambda: sc.mathieu_a(NU, Q), 3)
    per = 1e6 / npts
    print(f"lambda grid ({NU.shape[0]} nu x {NU.shape[1]} q = {npts} points), per point:")
    print(f"    SciPy mathieu_a(floor(nu), q) {per * t_sp:.3f} us "
          f"(non-integer orders, nan: {per * t_nan:.3f} us)")
    for label, (t_inv, c_inv, t_exp, c_exp, _, _) in res.items():
        print(f"    ours ({label}): theta0_of_exponent (arrays) {per * t_inv:.3f} us, "
              f"exponent {per * t_exp:.3f} us; ratios ours/SciPy: inverse {t_inv / t_sp:.2f}, "
              f"exponent {t_exp / t_sp:.2f} (CPU time: {c_inv / c_sp:.2f}, {c_exp / c_sp:.2f})")
    if not have_c:
        print("    (no C compiler: the C kernel row is missing)")
    else:
        _, _, _, _, th_c, lam_c = res["C kernel"]
        _, _, _, _, th_n, lam_n = res["NumPy fallback"]
        print(f"    C kernel and NumPy fallback bit-identical: inverse "
              f"{bool(np.array_equal(th_c, th_n))}, exponent {bool(np.array_equal(lam_c, lam_n))}")
    t1, _ = best(lambda: theta0_of_exponent(1.37, 0.8), 5)
    print(f"    theta0_of_exponent(1.37, 0.8) (one double): {1e3 * t1:.3f} ms")


def whole_grid(path):
    ref = np.loadtxt(path, delimiter=",")
    NU, Q = grid()
    got = theta0_of_exponent(NU, -Q)
    err = np.abs(got - ref) / np.maximum(1.0, np.abs(ref))
    i = np.unravel_index(np.argmax(err), err.shape)
    print(f"whole lambda grid ({ref.size} points): inverse max error {err.max():.3g} "
          f"(relative to max(1, |lambda|)) at nu = {NU[i]:.2f}, q = {Q[i]:.2f}; "
          f"points above 2.5e-14: {int(np.count_nonzero(err > 2.5e-14))}")
    lam = exponent(ref, -Q).real
    back = []
    for r in range(1, 200):
        if r % 100 == 0:
            continue
        h = 1 if r % 100 < 50 else -1          # one-sided, inside the band
        slope = np.abs(-3 * ref[r] + 4 * ref[r + h] - ref[r + 2 * h]) / 0.02
        back.append(np.abs(lam[r] - NU[r]) * slope / np.maximum(1.0, np.abs(ref[r])))
    back = np.array(back)
    print(f"    exponent backward error (non-integer nu, {back.size} points): max {back.max():.3g}, "
          f"99th percentile {np.percentile(back, 99):.3g}")


if __name__ == "__main__":
    maps()
    vectorised()
    if len(sys.argv) > 1:
        whole_grid(sys.argv[1])
