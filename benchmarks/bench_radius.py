"""Time to compute radii of convergence (branch points of a_m, b_m) against a plain
eigenvalue-collision search with mpmath.eig.

    python benchmarks/bench_radius.py [--kinds a0,a4,b6,a7] [--digits 15]

Ours: pendulab.analyses.mathieu_branch.branch_point(kind, digits), everything included
(the exact series that gives the starts, following a_m along the rays, Newton on
{D = 0, dD/da = 0} at two truncations and precisions, the sheet check), each kind in a
fresh cache.  Baseline: near a square-root branch point the squared difference
g(q) = (lam_1(q) - lam_2(q))^2 of the two eigenvalues that meet is analytic with a simple
zero at q_b, so the secant method on g, with lam_1, lam_2 the two eigenvalues nearest to
each other among mpmath.eig's eigenvalues of the truncated matrix (ours' size) at
dps digits + 10, finds q_b; it is given a head start, q_b (1 + 1e-3) and q_b (1 - 1e-3)
from our answer, and stops when the step is below 10^-digits |q|.  It knows neither which
branch point is the nearest nor whether a_m reaches it: the timing favours it.  CPU time
(time.process_time), the radii of both printed with the ratio of the times.
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import mpmath  # noqa: E402

from pendulab.analyses import mathieu_branch as mb  # noqa: E402
from pendulab.analyses.series import parity_rows  # noqa: E402


def baseline(kind, q_start, size, digits):
    rows = parity_rows(kind, size)

    def g(q):
        n = len(rows)
        M = mpmath.zeros(n, n)
        for i, (c, v, w) in enumerate(rows):
            M[i, i] = c + q * v
            if i:
                M[i, i - 1] = M[i - 1, i] = q * mpmath.sqrt(w)
        vals = mpmath.eig(M, left=False, right=False)
        best = min(((abs(x - y), x, y) for i, x in enumerate(vals) for y in vals[i + 1:]),
                   key=lambda t: t[0])
        return (best[1] - best[2]) ** 2

    with mpmath.workdps(digits + 10):
        q0, q1 = q_start * (1 + mpmath.mpf("1e-3")), q_start * (1 - mpmath.mpf("1e-3"))
        g0, g1 = g(q0), g(q1)
        for _ in range(40):
            q2 = q1 - g1 * (q1 - q0) / (g1 - g0)
            if abs(q2 - q1) < mpmath.mpf(10) ** (-digits) * abs(q2):
                return abs(q2)
            q0, g0, q1, g1 = q1, g1, q2, g(q2)
    raise RuntimeError(f"{kind}: the secant search did not converge")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kinds", default="a0,a4,b6,a7")
    ap.add_argument("--digits", type=int, default=15)
    args = ap.parse_args()
    ours_total = base_total = 0.0
    for kind in args.kinds.split(","):
        mb._branch.cache_clear()
        c = time.process_time()
        p = mb.branch_point(kind, args.digits)
        ours = time.process_time() - c
        c = time.process_time()
        r = baseline(kind, p.q, p.size, args.digits)
        base = time.process_time() - c
        ours_total, base_total = ours_total + ours, base_total + base
        print(f"{kind:>4}: ours {p.text} in {ours:.2f} s; mpmath.eig secant "
              f"{mpmath.nstr(r, args.digits)} in {base:.2f} s; ratio {base / ours:.1f}")
    print(f"total: ours {ours_total:.2f} s, baseline {base_total:.2f} s, "
          f"ratio {base_total / ours_total:.1f}")


if __name__ == "__main__":
    main()
