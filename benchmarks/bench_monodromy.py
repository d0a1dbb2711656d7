"""Floquet verdict of a periodic drive from the derived linear system, one command:

    python benchmarks/bench_monodromy.py

For the two-harmonic drive a cos(omega t) + a cos(2 omega t) (rod), at
omega0/omega = 0.05 and 401 values of a/l in [0, 2] (the scan of
pendulab.analyses.stability.hill_limits):

1. ours: traces_along (one DOP853 run over the ensemble of 401 fundamental
   matrices, rtol 1e-13);
2. baseline: floquet_verdict once per point (one DOP853 run each, as a user
   looping over points would);
3. Hill's determinant (hill_trace) on a 21-point subsample, extrapolated
   to 401 points (said so in the output);
4. per point: the mp Taylor route at 30 digits.

Prints each time, the ratios from this run and the largest trace difference.
"""

import math
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from pendulab import symbols as S  # noqa: E402
from pendulab.analyses.hill_general import hill_trace, numeric_fourier  # noqa: E402
from pendulab.canonical import periodic_form  # noqa: E402
from pendulab.equations import derive  # noqa: E402
from pendulab.exprs import parse  # noqa: E402
from pendulab.numerics.model import pivot_system  # noqa: E402
from pendulab.numerics.monodromy import floquet_verdict, traces_along  # noqa: E402
from pendulab.systems import DrivenPivot  # noqa: E402


def main():
    eqs = derive(DrivenPivot(body="rod", drive=parse("a*cos(omega*t) + a*cos(2*omega*t)")))
    form = periodic_form(eqs)
    fos = pivot_system(eqs, form)
    xs = np.linspace(0.0, 2.0, 401)
    w = 0.05
    traces_along(fos, {"w0_over_w": w}, "a_over_l", xs[:2])  # lambdify once, outside the timing

    t = time.perf_counter()
    ours = traces_along(fos, {"w0_over_w": w}, "a_over_l", xs)
    t_ours = time.perf_counter() - t

    t = time.perf_counter()
    loop = np.array([floquet_verdict(fos, {"a_over_l": x, "w0_over_w": w}).trace for x in xs])
    t_loop = time.perf_counter() - t

    sub = xs[::20]
    sub_map = {S.a: S.a_over_l * S.l, S.omega0: S.w0_over_w * S.omega, S.I: eqs.system.inertia}
    fourier = {k: tuple(sp.sympify(c).subs(sub_map) for c in pair) for k, pair in form.fourier.items()}
    t = time.perf_counter()
    hill = np.array([hill_trace(numeric_fourier(fourier, {S.a_over_l: x, S.w0_over_w: w}),
                                math.pi).trace for x in sub])
    t_hill = (time.perf_counter() - t) * len(xs) / len(sub)

    t = time.perf_counter()
    floquet_verdict(fos, {"a_over_l": "1/10", "w0_over_w": "1/20"}, dps=30, method="mp")
    t_mp = time.perf_counter() - t

    scale = np.maximum(1.0, np.abs(loop))
    print(f"traces_along, 401 points: {t_ours:.3f} s")
    print(f"floquet_verdict per point, 401 points: {t_loop:.3f} s; ratio {t_loop / t_ours:.1f}x")
    print(f"hill_trace, 21 points extrapolated to 401: {t_hill:.2f} s; "
          f"ratio {t_hill / t_ours:.1f}x")
    print(f"mp Taylor route, 30 digits, one point: {t_mp:.2f} s")
    print(f"max |trace difference| / max(1, |trace|): ensemble vs per point "
          f"{np.max(np.abs(ours - loop) / scale):.1e}; Hill vs per point (subsample) "
          f"{np.max(np.abs(hill - loop[::20]) / scale[::20]):.1e}")


if __name__ == "__main__":
    main()
