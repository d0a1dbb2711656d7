"""The DOP853 reference trajectory (pendulab.numerics.integrate.reference_trajectory), one command:

    python benchmarks/bench_reference.py [--repeat N]

Fig. 5's case (000 sec. 4): the rod, a/l = 0.2, omega0/omega = 0.05, theta(0) = 0.06,
theta'(0) = 0.01 in tau, 40 drive periods at 100 RK4 steps each (4001 output times),
DOP853 at rtol 1e-13, atol 1e-15, full and linear equation.

* ours - reference_trajectory: SciPy's solve_ivp on the generated scalar right-hand
  side (pendulab.numerics.codegen.scalar_function; math functions on floats);
* baseline - the same solve_ivp call on the generated NumPy right-hand side with
  vectorized=True (what reference_trajectory did before 0.5.0).

Prints the CPU time of each (fastest of --repeat rounds), the ratio, and the largest
difference between the two answers (the same algorithm on the same equation: 0 or a
few units of the last place).
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    import numpy as np
    from scipy.integrate import solve_ivp

    from pendulab.canonical import periodic_form
    from pendulab.equations import derive
    from pendulab.numerics.codegen import numpy_functions
    from pendulab.numerics.integrate import reference_trajectory
    from pendulab.numerics.model import pivot_system
    from pendulab.systems import DrivenPivot

    eqs = derive(DrivenPivot(body="rod"))
    fos = pivot_system(eqs, periodic_form(eqs))
    y0, p = np.array([0.06, 0.01]), np.array([0.2, 0.05])
    t = np.arange(4001) * (np.pi / 100)

    def baseline(linear):
        f = numpy_functions(fos)["linear_rhs" if linear else "rhs"]
        pc = p.reshape(-1, 1)
        with np.errstate(all="ignore"):
            sol = solve_ivp(lambda tt, y: f(tt, y, pc), (t[0], t[-1]), y0, method="DOP853",
                            t_eval=t, rtol=1e-13, atol=1e-15, vectorized=True)
        return sol.y.T

    def ours(linear):
        return reference_trajectory(fos, y0, p, t, linear=linear)

    ours(False), baseline(False)  # generated code made and loaded outside the timing
    for linear in (False, True):
        best = {}
        answers = {}
        for name, fn in (("ours", ours), ("baseline", baseline)):
            for _ in range(args.repeat):
                c = time.process_time()
                answers[name] = fn(linear)
                dt = time.process_time() - c
                best[name] = min(best.get(name, dt), dt)
        diff = float(np.max(np.abs(answers["ours"] - answers["baseline"])))
        kind = "linear" if linear else "full"
        print(f"{kind:6s} equation: ours {best['ours']:.3f} s CPU, baseline {best['baseline']:.3f} s, "
              f"ratio baseline/ours {best['baseline'] / best['ours']:.2f}x, "
              f"largest difference {diff:.2e}")


if __name__ == "__main__":
    main()
