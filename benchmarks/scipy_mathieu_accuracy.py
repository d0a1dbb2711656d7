"""Where do scipy.special.mathieu_a(m, q) and mathieu_b(m, q) go wrong?

Compares SciPy with pendulab's characteristic values computed to 50 digits
(pendulab.analyses.floquet.mathieu_a / mathieu_b, each checked at two working
precisions) on a logarithmic q grid from 0.01 to 1e4: first a_0 and b_1 (the
inverted pendulum's band edges) point by point, then the orders up to 10, and
reports the smallest q at which the relative error exceeds 1e-8 (SciPy issues
4479, 14526).

Run:  python benchmarks/scipy_mathieu_accuracy.py [--points N]
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import mpmath  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.special import mathieu_a as sp_a, mathieu_b as sp_b  # noqa: E402

from pendulab.analyses.floquet import mathieu_a, mathieu_b  # noqa: E402


def scan(points=81, tol=1e-8):
    qs = np.logspace(-2, 4, points)
    rows = []
    for q in qs:
        ref_a = mathieu_a(0, float(q), dps=50)
        ref_b = mathieu_b(1, float(q), dps=50)
        with mpmath.workdps(50):
            ea = float(abs((mpmath.mpf(float(sp_a(0, q))) - ref_a) / ref_a))
            eb = float(abs((mpmath.mpf(float(sp_b(1, q))) - ref_b) / ref_b))
        rows.append((float(q), ea, eb))
    first = {}
    for name, col in (("a0", 1), ("b1", 2)):
        bad = [r[0] for r in rows if r[col] > tol]
        first[name] = min(bad) if bad else None
    return rows, first


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=81)
    args = ap.parse_args()
    rows, first = scan(args.points)
    print(f"scipy {scipy.__version__}; reference: pendulab mathieu_a/b at 50 digits")
    print(f"{'q':>12} {'rel err a0':>12} {'rel err b1':>12}")
    for q, ea, eb in rows:
        print(f"{q:12.5g} {ea:12.3e} {eb:12.3e}")
    for name in ("a0", "b1"):
        v = first[name]
        print(f"first q with relative error > 1e-8 for {name}: "
              f"{'none on this grid' if v is None else f'{v:.5g}'}")
    print("higher orders (30-digit references, q = 1 .. 1e4, 25 points):")
    qs = np.logspace(0, 4, 25)
    for kind, sp_f, ours in (("a", sp_a, mathieu_a), ("b", sp_b, mathieu_b)):
        for m in range(1 if kind == "b" else 0, 11):
            errs = []
            for q in qs:
                ref = ours(m, float(q), dps=30)
                with mpmath.workdps(30):
                    errs.append(float(abs((mpmath.mpf(float(sp_f(m, q))) - ref) / ref)))
            bad = [float(q) for q, e in zip(qs, errs) if e > 1e-8]
            where = "none" if not bad else f"{bad[0]:.5g}"
            print(f"  {kind}_{m:<2d} max rel err {max(errs):9.2e}   first q with error > 1e-8: {where}")


if __name__ == "__main__":
    main()
