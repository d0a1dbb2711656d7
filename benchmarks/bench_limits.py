"""CPU of the stability product's closed forms, exact and series limits: this tree against a baseline commit.

    python benchmarks/bench_limits.py [--baseline 4b84647] [--repeat 3]

Each side runs in a fresh process (the derivations are cached per process):
the closed forms of methods eq12, eq19, eq19-corrected
(pendulab.analyses.stability._formula, what the stability product lambdifies),
the exact limits of the build's calls (kapitza-point: 11 ratios on [0, 1/2],
point mass; kapitza-rod: 21 on [0, 1], rod) and the series limits of a build's
process (eq. 28 on the experiments' 41 ratios k/40 and their 10 x 10 map's grid,
which hold the stability product's grids; series:6 on the rod's 21) and the rod's
first-order system (pendulab.numerics.model.pivot_system, which the experiments
and kernels products integrate and print).  The
baseline's src is exported with git archive into a temporary directory.  CPU
time (time.process_time); the two sides alternate ``--repeat`` times and the
least time of each counts (the machine may be shared).
"""

import argparse
import os
import subprocess
import sys
import tarfile
import tempfile

CHILD = r"""
import sys, time
sys.path.insert(0, sys.argv[1])
from pendulab.analyses import stability
stability.body_map()          # shared with the rest of the build, not counted
c = time.process_time()
for name in ("eq12-lower", "eq12-upper", "eq19", "eq19-corrected"):
    stability._formula(name)
formulas = time.process_time() - c
c = time.process_time()
for n, top, r in ((11, 0.5, 1.0), (21, 1.0, 4 / 3)):
    for k in range(n):
        stability.limits(top * k / (n - 1), r, "exact")
exact = time.process_time() - c
import scipy.optimize  # imported by every build before the products (not counted)
c = time.process_time()
for n, method in ((41, "eq28"), (10, "eq28"), (21, "series:6")):
    for k in range(n):
        stability.limits(k / (n - 1), 4 / 3, method)
series = time.process_time() - c
from pendulab.canonical import periodic_form
from pendulab.equations import derive
from pendulab.numerics import model
from pendulab.systems import DrivenPivot
eqs = derive(DrivenPivot(body="rod"))  # the derivation: shared, not counted
form = periodic_form(eqs)
c = time.process_time()
model.pivot_system(eqs, form)
pivot = time.process_time() - c
print(formulas, exact, series, pivot)
"""


def run(src):
    out = subprocess.run([sys.executable, "-c", CHILD, src], capture_output=True, text=True,
                         check=True).stdout.split()
    return tuple(float(v) for v in out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default="4b84647")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as tmp:
        tar = os.path.join(tmp, "base.tar")
        subprocess.run(["git", "-C", root, "archive", "-o", tar, args.baseline, "src"], check=True)
        with tarfile.open(tar) as t:
            t.extractall(tmp)
        runs = [(run(os.path.join(tmp, "src")), run(os.path.join(root, "src")))
                for _ in range(max(1, args.repeat))]
    base = [min(b[i] for b, _ in runs) for i in range(4)]
    ours = [min(o[i] for _, o in runs) for i in range(4)]
    for i, what in enumerate(("closed forms (_formula)", "exact limits (32 calls)",
                              "series limits (72 calls)", "pivot system (rod)")):
        print(f"{what:26s} ours {ours[i]:.3f} s  baseline {base[i]:.3f} s  "
              f"ratio {base[i] / ours[i]:.2f}x")


if __name__ == "__main__":
    main()
