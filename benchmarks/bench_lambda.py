"""lambda of 000 eq. 7 at 50 and 1000 digits: ours (certified) beside two expert baselines.

    python benchmarks/bench_lambda.py

Targets: lambda and the verdict at 50 digits in at most 1 ms per
point, at 1000 digits in at most 50 ms.

* ours: ``characteristic_exponent(theta0, theta1, dps=D)`` -- the default
  route "arb" with dps: band count on balls, double guess, Newton in arb and
  the sign-change proof; every printed digit proved (``certified_digits``).
* baseline 1, "mpmath CF + findroot": the source's characteristic equation
  C_0 + theta1 (b_1/b_0 + b_-1/b_0) = 0 (000 eq. 10) with both continued
  fractions, solved by mpmath.findroot (secant) from a double guess.
* baseline 2, "arb CF secant": the same equation in python-flint's arb/acb
  (midpoints, no enclosure of the tail, nothing proved), secant iteration from
  the same double guess.
* the double guess of the baselines: the trace of the monodromy matrix by
  scipy's solve_ivp (DOP853, rtol 1e-12), lam = arccos(tr/2)/pi (points of
  band 0 and gaps 0, 1, where that branch is the unfolded exponent).  Its
  time is printed separately ("guess") and the baselines are quoted with and
  without it.

The baselines live here, not in the package.  Each point is also checked
against our mpmath route (method "cf") and against the baselines: same
verdict, and lam within 10^-(D-2).
"""

import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import mpmath  # noqa: E402
import numpy as np  # noqa: E402
from flint import acb, arb, ctx  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from pendulab.analyses.floquet import characteristic_exponent  # noqa: E402

POINTS = [("-0.002", "0.2"), ("-0.04", "0.3"), ("-0.25", "1.1"), ("0.5", "0.7"), ("-1", "2.5")]


# -- baselines --------------------------------------------------------------------------

def double_guess(theta0, theta1):
    """lam in double precision from the monodromy trace (scipy), principal branch."""
    t0, t1 = float(theta0), float(theta1)

    def rhs(t, y):
        p = t0 + 2 * t1 * np.cos(2 * t)
        return [y[1], -p * y[0], y[3], -p * y[2]]
    sol = solve_ivp(rhs, (0.0, np.pi), [1.0, 0.0, 0.0, 1.0], method="DOP853",
                    rtol=1e-12, atol=1e-14)
    tr = sol.y[0, -1] + sol.y[3, -1]
    lam = np.arccos(complex(tr / 2)) / np.pi
    return complex(lam.real, abs(lam.imag))


def cf_depth(theta0, theta1, digits):
    """Levels of each continued fraction so that the neglected tail is below 10^-digits."""
    t0, t1 = float(theta0), abs(float(theta1))
    logp, n = 0.0, 0
    while logp > -digits * 2.302585 or n < 2:
        n += 1
        c = abs(t0 - (2 * n) ** 2)
        logp += 2 * np.log(t1 / c) if c > t1 else 0.0
    return n + 2


def char_fn(lam, t0, t1, depth):
    """C_0 + theta1 (b_1/b_0 + b_-1/b_0) with b_n/b_(n-1) = -theta1/(C_n + theta1 b_(n+1)/b_n)."""
    rp = 0
    for n in range(depth, 0, -1):
        rp = -t1 / (t0 - (2 * n + lam) ** 2 + t1 * rp)
    rm = 0
    for n in range(-depth, 0):
        rm = -t1 / (t0 - (2 * n + lam) ** 2 + t1 * rm)
    return t0 - lam ** 2 + t1 * (rp + rm)


def mpmath_baseline(theta0, theta1, dps, guess):
    with mpmath.workdps(dps + 10):
        t0, t1 = mpmath.mpf(theta0), mpmath.mpf(theta1)
        depth = cf_depth(theta0, theta1, dps + 10)
        g = mpmath.mpf(guess.real) if guess.imag == 0 else mpmath.mpc(guess)
        lam = mpmath.findroot(lambda x: char_fn(x, t0, t1, depth), g,
                              tol=mpmath.mpf(10) ** (-2 * dps - 10))
        return +lam


def arb_baseline(theta0, theta1, dps, guess):
    saved = ctx.prec
    ctx.prec = int((dps + 10) * 3.33)
    try:
        depth = cf_depth(theta0, theta1, dps + 10)
        real = guess.imag == 0
        num = arb if real else acb
        t0, t1 = num(arb(theta0)), num(arb(theta1))
        x0 = arb(guess.real) if real else acb(guess.real, guess.imag)
        x1 = x0 * (1 + num(2) ** -30)
        f0, f1 = char_fn(x0, t0, t1, depth), char_fn(x1, t0, t1, depth)
        tol = arb(10) ** (-dps - 5)
        for _ in range(100):
            x2 = (x1 - f1 * (x1 - x0) / (f1 - f0)).mid()
            if abs(x2 - x1).mid() < tol * abs(x2).mid():
                return x2
            x0, f0, x1 = x1, f1, x2
            f1 = char_fn(x1, t0, t1, depth)
        raise RuntimeError("arb secant did not converge")
    finally:
        ctx.prec = saved


# -- the run ----------------------------------------------------------------------------

def per_call(fn, n):
    fn()
    t = time.perf_counter()
    for _ in range(n):
        out = fn()
    return (time.perf_counter() - t) / n, out


def to_mp(z):
    """arb/acb or mpmath number as an mpmath number at the current precision."""
    if isinstance(z, arb):
        return mpmath.mpf(z.mid().str(int(mpmath.mp.dps) + 5, radius=False))
    if isinstance(z, acb):
        return mpmath.mpc(to_mp(z.real), to_mp(z.imag))
    return z


def main():
    print(f"mpmath backend: {mpmath.libmp.BACKEND}")
    for dps, reps, target in ((50, 40, 1e-3), (1000, 3, 50e-3)):
        print(f"\n== {dps} digits (target: ours <= {1e3 * target:g} ms per point) ==")
        totals = {"ours": 0.0, "guess": 0.0, "mp": 0.0, "arb": 0.0}
        ok_all = True
        for t0, t1 in POINTS:
            t_ours, ours = per_call(lambda: characteristic_exponent(t0, t1, dps=dps), reps)
            t_guess, g = per_call(lambda: double_guess(t0, t1), max(3, reps // 4))
            t_mp, lam_mp = per_call(lambda: mpmath_baseline(t0, t1, dps, g), max(1, reps // 4))
            t_arb, lam_arb = per_call(lambda: arb_baseline(t0, t1, dps, g), reps)
            ref = characteristic_exponent(t0, t1, dps=dps, method="cf")
            with mpmath.workdps(dps + 10):
                tol = mpmath.mpf(10) ** (2 - dps) * max(1, abs(ref.lam))
                agree = (ours.stable == ref.stable and abs(ours.lam - ref.lam) < tol
                         and abs(lam_mp - ref.lam) < tol and abs(to_mp(lam_arb) - ref.lam) < tol)
            ok_all &= agree
            for k, v in (("ours", t_ours), ("guess", t_guess), ("mp", t_mp), ("arb", t_arb)):
                totals[k] += v
            print(f"({t0:>6}, {t1:>4}) ours {1e3 * t_ours:7.2f} ms [{ours.certified_digits} digits "
                  f"certified, {'stable' if ours.stable else 'unstable'}] | guess "
                  f"{1e3 * t_guess:5.2f} ms | mpmath CF+findroot {1e3 * (t_guess + t_mp):7.2f} ms "
                  f"({1e3 * t_mp:7.2f} after the guess) | arb CF secant "
                  f"{1e3 * (t_guess + t_arb):7.2f} ms ({1e3 * t_arb:6.2f} after) | "
                  f"agree with cf route and baselines: {agree}")
        n = len(POINTS)
        o, gu, mp_, ar = (totals[k] / n for k in ("ours", "guess", "mp", "arb"))
        print(f"mean per point: ours {1e3 * o:.2f} ms (target {1e3 * target:g} ms: "
              f"{'met' if o <= target else 'NOT met'}); mpmath baseline {1e3 * (gu + mp_):.2f} ms "
              f"({1e3 * mp_:.2f} after the guess); arb baseline {1e3 * (gu + ar):.2f} ms "
              f"({1e3 * ar:.2f} after the guess)")
        print(f"ratios ours/baseline: mpmath {o / (gu + mp_):.2f} (after-guess {o / mp_:.2f}); "
              f"arb {o / (gu + ar):.2f} (after-guess {o / ar:.2f}); verdicts and values agree: "
              f"{ok_all}")


if __name__ == "__main__":
    main()
