"""The speed-versus-accuracy trade of every engine, measured; writes docs/tradeoffs.md.

    python benchmarks/tradeoffs.py                 every part, then docs/tradeoffs.md and figures
    python benchmarks/tradeoffs.py --part rk4      one part (repeatable); the others' last
                                                   results are kept (docs/tradeoffs.json)
    python benchmarks/tradeoffs.py --quick         smaller grids, under a minute; prints the
                                                   tables and writes nothing (unless --write)

Parts (each one table or more in docs/tradeoffs.md, one figure in docs/figures/):

* ``series``  - order N of the source's series theta0 = nu^2 + sum alpha_n theta1^n
  (000 eqs. 20-24) against its error, at theta1 inside and near the radius of
  convergence; the reference is the characteristic value from the Floquet code at
  50 digits (``theta0_of_exponent``, continued fractions: an independent method);
  the time to generate the exact coefficients and to evaluate them;
* ``rk4``     - RK4 steps per drive period against the error over 300 drive periods
  (the reference: DOP853 at rtol 1e-13), beside DOP853 at several tolerances;
* ``floquet`` - dps (and the depth it implies) of every route of
  ``characteristic_exponent`` against the error in lambda; the continued fraction
  truncated at depth N (000 sec. 2.2, the equation derived by
  ``phelps_hunter.lambda_equation``); the stability limits of a/l to a given accuracy
  by every method;
* ``bessel``  - dps against time for the zeros j_1,k, j_2,k and the identities,
  arb (python-flint, certified) against mpmath;
* ``kernels`` - the generated NumPy modules against the C kernel (same RK4).

Errors are measured against references from independent methods, named beside each
table.  Times are best of a few runs of wall-clock time on whatever machine runs this
(the doc records the load average); quote ratios, not absolute times.
"""

import argparse
import datetime
import json
import math
import os
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _paths():
    """src/ (this checkout's pendulab) and benchmarks/ (the shared helpers) first on sys.path;
    done by main() only, so that importing this module (the doc's test does) changes nothing."""
    for sub in ("benchmarks", "src"):
        if str(ROOT / sub) not in sys.path:
            sys.path.insert(0, str(ROOT / sub))

PARTS = ("series", "rk4", "floquet", "bessel", "kernels")
DOC = ROOT / "docs" / "tradeoffs.md"
RESULTS = ROOT / "docs" / "tradeoffs.json"
FIGURES = ROOT / "docs" / "figures"
COMMAND = "python benchmarks/tradeoffs.py"


def build_parser():
    """The command line (the doc's test parses every command the doc prints with it)."""
    ap = argparse.ArgumentParser(prog=COMMAND, description=__doc__.splitlines()[0])
    ap.add_argument("--part", action="append", choices=PARTS,
                    help="run this part only (repeatable; default: all)")
    ap.add_argument("--quick", action="store_true",
                    help="smaller grids (under a minute); prints, writes nothing unless --write")
    ap.add_argument("--write", action="store_true", help="with --quick: write the doc anyway")
    ap.add_argument("--no-write", action="store_true", help="print the tables only")
    ap.add_argument("--redraw", action="store_true",
                    help="measure nothing: rewrite the doc and figures from docs/tradeoffs.json")
    return ap


# -- small helpers --------------------------------------------------------------------------

def best_time(fn, repeat=3):
    """(result, best wall time of ``repeat`` calls)."""
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return out, best


def sci(x, digits=2):
    """1.2e-07 style text (None -> em dash)."""
    if x is None:
        return "-"
    x = float(x)
    if x == 0:
        return "0"
    return f"{x:.{digits - 1}e}"


def ms(t):
    return f"{1e3 * t:.3g} ms" if t < 1 else f"{t:.3g} s"


def pareto(points):
    """Indices of the points (cost, error) that no other point beats in both (lower is better)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def cheapest(rows, target, cost="time", error="error"):
    """The row of least cost whose error is at most ``target`` (None if none)."""
    ok = [r for r in rows if r[error] is not None and r[error] <= target and not r.get("refused")]
    return min(ok, key=lambda r: r[cost]) if ok else None


def cmd(part):
    return f"`{COMMAND} --part {part}`"


# -- part: series ---------------------------------------------------------------------------

SERIES_POINTS = [(0.5, 0.1), (0.5, 0.3), (0.5, 0.6), (0.5, 0.9), (0.5, 1.0), (0.9, 0.1),
                 (0.9, 0.18)]
SERIES_ORDERS = [2, 4, 6, 8, 12, 16, 20, 24, 32, 40]


def part_series(quick):
    """Order N of 000 eq. 20's theta0 against its error and its cost."""
    import mpmath

    from bench_series import _fresh_engine, timed  # the series benchmark's helpers
    from pendulab.analyses import series as se
    from pendulab.analyses.floquet import theta0_of_exponent
    from pendulab.errors import AccuracyWarning

    orders = [2, 4, 8, 16] if quick else SERIES_ORDERS
    points = [(0.5, 0.3), (0.5, 0.9), (0.9, 0.18)] if quick else SERIES_POINTS
    generate = {}
    for n in orders:  # the exact coefficients alpha_n, c_n from an empty engine
        _fresh_engine()
        generate[n], _ = timed(lambda: se.mathieu_series(n))
    rows = []
    for nu, th1 in points:
        with mpmath.workdps(50):
            ref = theta0_of_exponent(str(nu), str(th1), dps=50)
        for n in orders:
            for dps in (None, 30):
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", AccuracyWarning)
                    (value, est), t = best_time(
                        lambda: se.theta0_of_nu(nu if dps is None else str(nu),
                                                th1 if dps is None else str(th1), n, dps=dps,
                                                on_domain="warn"), 3 if dps is None else 1)
                with mpmath.workdps(50):
                    err = float(abs(mpmath.mpf(value) - ref))
                rows.append({"nu": nu, "theta1": th1, "order": n, "dps": dps, "error": err,
                             "estimate": float(est), "refused": bool(caught),
                             "evaluate": t, "generate": generate[n], "time": t})
    return {"rows": rows, "orders": orders, "points": points,
            "reference": "theta0_of_exponent dps 50"}


def series_markdown(res):
    lines = ["## 1. The series for theta0 (000 eqs. 20-24): order against error", "",
             f"Reproduce: {cmd('series')}.  Error |theta0_N - theta0| of "
             "`series.theta0_of_nu(nu, theta1, N)` against the characteristic value from "
             "`floquet.theta0_of_exponent(nu, theta1, dps=50)` (continued fractions, an "
             "independent method), in double precision and at dps 30.  *generate* is "
             "`series.mathieu_series(N)` from an empty engine (the exact alpha_n, c_n, which the "
             "products write); *evaluate* is one call of `theta0_of_nu` (it runs the recursion on "
             "numbers and does not need them).  A value the evaluator refuses (the omitted orders "
             "grow: beyond the radius of convergence, about 0.95 at nu = 0.5 and 0.2 at nu = 0.9, "
             "docs/series.md) is marked *refused* (taken with `on_domain=\"warn\"`).", ""]
    orders = res["orders"]
    lines.append("| nu | theta1 | " + " | ".join(f"N = {n}" for n in orders) + " |")
    lines.append("|---|---|" + "---|" * len(orders))
    for nu, th1 in res["points"]:
        for dps in (None, 30):
            cells = []
            for n in orders:
                r = next(r for r in res["rows"] if r["nu"] == nu and r["theta1"] == th1
                         and r["order"] == n and r["dps"] == dps)
                cells.append(sci(r["error"]) + (" refused" if r["refused"] else ""))
            lab = "double" if dps is None else "dps 30"
            lines.append(f"| {nu} | {th1} ({lab}) | " + " | ".join(cells) + " |")
    gen = {r["order"]: r["generate"] for r in res["rows"]}
    ev = {}
    ev30 = {}
    for r in res["rows"]:
        (ev if r["dps"] is None else ev30).setdefault(r["order"], []).append(r["evaluate"])
    lines += ["", "| cost | " + " | ".join(f"N = {n}" for n in orders) + " |",
              "|---|" + "---|" * len(orders),
              "| generate (exact coefficients) | " + " | ".join(ms(gen[n]) for n in orders) + " |",
              "| evaluate, double (median) | " + " | ".join(ms(sorted(ev[n])[len(ev[n]) // 2])
                                                          for n in orders) + " |",
              "| evaluate, dps 30 (median) | " + " | ".join(ms(sorted(ev30[n])[len(ev30[n]) // 2])
                                                           for n in orders) + " |", ""]
    refused = [r for r in res["rows"] if r["refused"]]
    key = lambda r: (r["nu"], r["theta1"], r["order"])  # noqa: E731
    at30 = {key(r): r["error"] for r in res["rows"] if r["dps"] == 30}
    floor = [r for r in res["rows"] if r["dps"] is None and r["error"] > 10 * at30[key(r)]]
    lines += ["Reading: inside the radius the error falls geometrically with N, the faster the "
              "smaller theta1; near the radius (theta1 = 0.9 at nu = 0.5, 0.18 at nu = 0.9) it "
              "falls slowly, and beyond it it stops falling"
              + (f" (the evaluator refuses from N = {min(r['order'] for r in refused)} on at "
                 f"theta1 = {refused[0]['theta1']})" if refused else "")
              + "."
              + (f"  Double precision floors at {sci(min(r['error'] for r in floor))} to "
                 f"{sci(max(r['error'] for r in floor))} (where it parts from dps 30); below "
                 "that the evaluation needs dps." if floor else "")
              + "  The "
              f"exact coefficients cost {ms(gen[orders[-1]])} at N = {orders[-1]} against "
              f"{ms(gen[orders[0]])} at N = {orders[0]}; a number needs none of them.", ""]
    return "\n".join(lines)


# -- part: rk4 ------------------------------------------------------------------------------

RK4_STEPS = [25, 50, 100, 200, 400, 800, 1600]
DOP_RTOLS = [1e-6, 1e-8, 1e-10, 1e-12]
RK4_POINT = {"a_over_l": 0.2, "w0_over_w": 0.05, "y0": (0.06, 0.01)}  # 000 Fig. 5's point


def _rod():
    from pendulab.canonical import periodic_form
    from pendulab.equations import derive
    from pendulab.numerics.model import pivot_system
    from pendulab.systems import DrivenPivot
    eqs = derive(DrivenPivot(body="rod"))
    return pivot_system(eqs, periodic_form(eqs))


def part_rk4(quick):
    """RK4 steps per period and DOP853's rtol against the error over 300 drive periods."""
    import numpy as np

    from pendulab.numerics import integrate

    fos = _rod()
    periods = 30 if quick else 300
    steps_list = [25, 100, 400] if quick else RK4_STEPS
    rtols = [1e-8, 1e-12] if quick else DOP_RTOLS
    T = float(fos.period)
    base = 25  # every RK4 grid contains the times of 25 steps per period: errors measured there
    times = T / base * np.arange(periods * base + 1)
    y0 = list(RK4_POINT["y0"])
    p = [RK4_POINT["a_over_l"], RK4_POINT["w0_over_w"]]
    ref, t_ref = best_time(lambda: integrate.reference_trajectory(fos, y0, p, times), 1)
    ref12 = integrate.reference_trajectory(fos, y0, p, times, rtol=1e-12, atol=1e-14)
    ref_spread = float(np.max(np.abs(ref12 - ref)))
    integrate.rk4_trajectory(fos, y0, p, 0.0, T / 10, 10)  # kernel compiled or loaded, warm
    ens_n = 256
    rows = []
    for spp in steps_list:
        (tt, st), t1 = best_time(lambda: integrate.rk4_trajectory(fos, y0, p, 0.0, T / spp,
                                                                  periods * spp), 3)
        err = float(np.max(np.abs(st[::spp // base] - ref)))
        _, te = best_time(lambda: integrate.ensemble_rk4(fos, np.tile(y0, (ens_n, 1)),
                                                         np.tile(p, (ens_n, 1)), 0.0, T / spp,
                                                         periods * spp), 2 if quick else 3)
        rows.append({"method": "rk4", "setting": spp, "error": err, "time": t1,
                     "per_trajectory": te / ens_n})
    for rtol in rtols:
        out, t = best_time(lambda: integrate.reference_trajectory(fos, y0, p, times, rtol=rtol,
                                                                  atol=rtol * 1e-2), 1)
        rows.append({"method": "dop853", "setting": rtol, "error": float(np.max(np.abs(out - ref))),
                     "time": t, "per_trajectory": t})
    return {"rows": rows, "periods": periods, "reference_time": t_ref,
            "reference_spread": ref_spread,
            "ensemble": ens_n, "backend": "c" if integrate.c_kernel_available(fos) else "numpy"}


def rk4_markdown(res):
    P = res["periods"]
    lines = ["## 2. RK4 steps per period against DOP853 tolerances", "",
             f"Reproduce: {cmd('rk4')}.  The rod at the source's Fig. 5 point (000 sec. 4: "
             "a/l = 0.2, omega0/omega = 0.05, theta(0) = 0.06, theta'(0) = 0.01), full nonlinear "
             f"equation, {P} drive periods.  Error: max over both components and the times of 25 "
             "steps per period (every grid below contains them) of |state - reference|, the "
             "reference being `integrate.reference_trajectory` (DOP853, rtol 1e-13, atol 1e-15; "
             f"it differs from the same at rtol 1e-12 by {sci(res['reference_spread'])}, which "
             f"bounds what the table can resolve; {ms(res['reference_time'])} for its "
             f"{25 * P + 1} output times).  *one trajectory*: `integrate.rk4_trajectory` (every "
             f"state returned; {res['backend']} kernel) or `reference_trajectory` at that rtol "
             "(atol = rtol/100; dense output at the same times); *per trajectory in an ensemble*: "
             f"`ensemble_rk4` over {res['ensemble']} copies (statistics only), divided by "
             f"{res['ensemble']}.", "",
             "| method | setting | error | one trajectory | per trajectory in an ensemble |",
             "|---|---|---|---|---|"]
    for r in res["rows"]:
        setting = (f"{r['setting']} steps per period" if r["method"] == "rk4"
                   else f"rtol {r['setting']:g}")
        ens = ms(r["per_trajectory"]) if r["method"] == "rk4" else "(one at a time)"
        lines.append(f"| {r['method'].upper()} | {setting} | {sci(r['error'])} | {ms(r['time'])} "
                     f"| {ens} |")
    rk = [r for r in res["rows"] if r["method"] == "rk4"]
    if len(rk) >= 2:
        a, b = rk[-2], rk[-1]
        if a["error"] > 0 and b["error"] > 0:
            lines += ["", f"Doubling the steps from {a['setting']} to {b['setting']} divides the "
                      f"error by {a['error'] / b['error']:.1f} (RK4: 16 until the reference's "
                      "resolution is reached)."]
    lines.append("")
    return "\n".join(lines)


# -- part: floquet --------------------------------------------------------------------------

FLOQUET_POINTS = [("-0.002", "0.2"), ("-0.25", "1.1"), ("0.5", "0.7"), ("-1", "2.5")]
FLOQUET_DPS = {"arb": [15, 17, 30, 50, 100, 300, 1000], "hill": [15, 30, 50], "cf": [15, 30, 50],
               "monodromy": [15, 30]}
CF_DEPTHS = [1, 2, 3, 4, 5, 6, 8, 10]
LIMIT_RATIOS = [0.05, 0.1, 0.3]
LIMIT_METHODS = (["exact", "eq12", "eq19", "eq19-corrected", "eq28"]
                 + [f"series:{n}" for n in (4, 8, 14)]
                 + [f"integer-series:{n}" for n in (2, 4, 6, 8, 10, 14, 20)])
ROD = "4/3"


def _rel(a, b):
    """log10 of |a - b| / max(1, |b|) (-inf when equal): errors down to 1e-1000 stay exact."""
    import mpmath
    with mpmath.workdps(1100):
        e = abs(mpmath.mpmathify(a) - b) / max(abs(b), 1)
        return float(mpmath.log10(e)) if e else -math.inf


def sci_log(lg):
    """1.2e-1003 style text of 10^lg."""
    if lg == -math.inf:
        return "0"
    e = math.floor(lg)
    return f"{10 ** (lg - e):.1f}e{e:+03d}"


def part_floquet(quick):
    import mpmath
    import numpy as np
    import sympy as sp

    from pendulab.analyses import phelps_hunter as ph
    from pendulab.analyses import stability
    from pendulab.analyses.floquet import characteristic_exponent, exponent, stability_limits
    from pendulab.symbols import theta0, theta1

    points = FLOQUET_POINTS[:2] if quick else FLOQUET_POINTS
    dps_of = ({"arb": [15, 17, 50, 300], "hill": [15], "cf": [15]} if quick else FLOQUET_DPS)
    top = max(d for ds in dps_of.values() for d in ds) + 20
    refs = {p: characteristic_exponent(*p, dps=top).lam for p in points}

    routes = []
    for method, dps_list in dps_of.items():
        for dps in dps_list:
            errs, ts, depths = [], [], []
            for p in points:
                r, t = best_time(lambda: characteristic_exponent(*p, dps=dps, method=method),
                                 1 if method == "monodromy" else 3)
                errs.append(_rel(r.lam, refs[p]))
                ts.append(t)
                depths.append(r.depth)
            routes.append({"method": method, "dps": dps, "log_error": max(errs),
                           "time": sum(ts) / len(ts), "depth": [min(depths), max(depths)]})
    # double precision: the default route (dps=None) and the vectorised exponent
    errs, ts = [], []
    for p in points:
        r, t = best_time(lambda: characteristic_exponent(*p), 3)
        errs.append(_rel(complex(r.lam), refs[p]))
        ts.append(t)
        method = r.method
    routes.append({"method": f"{method} (dps=None, the default)", "dps": None,
                   "log_error": max(errs),
                   "time": sum(ts) / len(ts), "depth": None})
    # double precision off the four points: the default against arb at 17 digits, rounded
    rng = np.random.default_rng(11)
    doubles = []
    for _ in range(10 if quick else 40):
        p = (repr(float(rng.uniform(-5, 20))), repr(float(rng.uniform(0, 10))))
        h, th = best_time(lambda: characteristic_exponent(*p), 1)
        a, ta = best_time(lambda: characteristic_exponent(*p, dps=17), 1)
        ref = characteristic_exponent(*p, dps=40).lam
        doubles.append({"hill": th, "arb17": ta, "same": complex(h.lam) == complex(a.lam),
                       "hill_error": _rel(complex(h.lam), ref),
                       "arb17_error": _rel(complex(a.lam), ref)})
    rng = np.random.default_rng(7)
    n = 2000 if quick else 20000
    t0s = rng.uniform(-1.0, 0.5, n)
    t1s = rng.uniform(0.2, 2.5, n)
    lam_v, t_v = best_time(lambda: exponent(t0s, t1s), 3)
    sample = range(0, n, n // 20)
    err_v = max(_rel(complex(lam_v[i]), characteristic_exponent(repr(float(t0s[i])),
                                                                repr(float(t1s[i])), dps=30).lam)
                for i in sample)
    routes.append({"method": "vectorised `exponent` (arrays)", "dps": None, "log_error": err_v,
                   "time": t_v / n, "depth": None})

    # the source's continued fraction truncated at depth N, solved for lambda
    depths = [1, 2, 3, 4] if quick else CF_DEPTHS
    cf_rows = []
    for N in depths:
        eq, t_gen = best_time(lambda: ph.lambda_equation(N), 1)
        f = sp.lambdify((ph.lam, theta0, theta1), eq, "mpmath")
        errs, ts = [], []
        for p in points:
            def solve():
                with mpmath.workdps(40):
                    x0, x1 = mpmath.mpf(p[0]), mpmath.mpf(p[1])
                    return mpmath.findroot(lambda L: f(L, x0, x1), mpmath.mpmathify(refs[p]))
            x, t = best_time(solve, 3)
            errs.append(_rel(x, refs[p]))
            ts.append(t)
        cf_rows.append({"depth": N, "log_error": max(errs), "time": sum(ts) / len(ts),
                        "generate": t_gen, "degree": 2 * (2 * N + 1)})

    # the stability limits of a/l (rod) by every method, against the proved 30-digit limits
    ratios = LIMIT_RATIOS[1:2] if quick else LIMIT_RATIOS
    methods = [m for m in LIMIT_METHODS if not quick or m in
               ("exact", "eq12", "eq28", "integer-series:4", "integer-series:8")]
    lim_rows = []
    for m in methods:  # one call at another ratio first: derivations and lambdify done once
        stability.limits(0.07, 4 / 3, m)
    for ratio in ratios:
        timed_rows = []
        for m in methods:  # first calls (the module caches results per ratio): the least of
            # three at ratios 1e-12 apart, then the answer at the ratio itself
            t = min(best_time(lambda: stability.limits(ratio + k * 1e-12, 4 / 3, m), 1)[1]
                    for k in (1, 2, 3))
            timed_rows.append((m, stability.limits(ratio, 4 / 3, m), t))
        exact = stability_limits(ratio, ROD, dps=30)
        with mpmath.workdps(40):
            lo, hi = mpmath.mpf(exact[0]), mpmath.mpf(exact[1])
            for m, out, t in timed_rows:
                e_lo = float(abs(out[0] - lo) / lo) if out[0] is not None else None
                e_hi = float(abs(out[1] - hi) / hi) if out[1] is not None else None
                lim_rows.append({"ratio": ratio, "method": m, "lower_error": e_lo,
                                 "upper_error": e_hi, "time": t,
                                 "error": (None if e_hi is None or e_lo is None
                                           else max(e_lo, e_hi))})
    return {"routes": routes, "cf": cf_rows, "limits": lim_rows, "double_sample": doubles,
            "points": [list(p) for p in points],
            "reference_dps": top, "vector_points": n}


def floquet_markdown(res):
    pts = ", ".join(f"({a}, {b})" for a, b in res["points"])
    lines = ["## 3. lambda (000 eq. 7): dps, depth and route against error", "",
             f"Reproduce: {cmd('floquet')}.  Points (theta0, theta1): {pts} (band 0 and gaps "
             "0, 1).  Error: the worst over the points of |lam - lam_ref| / max(1, |lam_ref|), "
             f"lam_ref from `characteristic_exponent(..., dps={res['reference_dps']})` (arb, every "
             "digit proved); time: the mean per point (best of 3).  *depth* is "
             "`FloquetResult.depth`, which each route chooses from dps (cf: continued-fraction "
             "levels; hill: truncated determinants; monodromy: Taylor order; arb: levels).", "",
             "| route | dps | error | time per point | depth |", "|---|---|---|---|---|"]
    for r in res["routes"]:
        d = "-" if r["depth"] is None else f"{r['depth'][0]}-{r['depth'][1]}"
        lines.append(f"| {r['method']} | {r['dps'] if r['dps'] is not None else 'double'} | "
                     f"{sci_log(r['log_error'])} | {ms(r['time'])} | {d} |")
    arb = {r["dps"]: r for r in res["routes"] if r["method"] == "arb"}
    others = [r for r in res["routes"] if r["method"] in ("hill", "cf", "monodromy")
              and r["dps"] in arb]
    ratio = [r["time"] / arb[r["dps"]]["time"] for r in others]
    lines += ["", f"The vectorised row is one call on {res['vector_points']} seeded random "
              "points in [-1, 0.5] x [0.2, 2.5], its error checked on 20 of them against "
              "30-digit arb values."]
    ds = res.get("double_sample")
    if ds:
        n = len(ds)
        lines += ["", f"Double precision on {n} seeded random points (theta0, theta1) in "
                  "[-5, 20] x [0, 10] (bands and gaps up to the fourth): the default "
                  "`characteristic_exponent(theta0, theta1)` (the default route) took "
                  f"{ms(sum(x['hill'] for x in ds) / n)} a point, "
                  "`characteristic_exponent(theta0, theta1, dps=17)` (arb) "
                  f"{ms(sum(x['arb17'] for x in ds) / n)}; rounded to a double, the two agree "
                  f"bit for bit at {sum(x['same'] for x in ds)} of the {n} points, and their "
                  "worst relative errors against 40 digits are "
                  f"{sci_log(max(x['hill_error'] for x in ds))} (default) and "
                  f"{sci_log(max(x['arb17_error'] for x in ds))} (arb)."]
    if ratio:
        lines += ["", f"Reading: at every dps measured the arb route (the default with dps) is "
                  f"the cheapest scalar route, {min(ratio):.0f}x to {max(ratio):.0f}x cheaper "
                  "than the mpmath routes at the same dps, and the only one that proves its "
                  f"digits; from dps {min(arb)} to {max(arb)} its time grows "
                  f"{arb[max(arb)]['time'] / arb[min(arb)]['time']:.0f}x and its depth from "
                  f"{arb[min(arb)]['depth'][1]} to {arb[max(arb)]['depth'][1]} levels.  "
                  "Without dps the scalar call takes the "
                  + next(r["method"].split()[0] for r in res["routes"] if "default" in r["method"])
                  + " route at double precision (see the defaults above); for many points the "
                  "vectorised `exponent` costs "
                  + ms(next(r["time"] for r in res["routes"] if r["method"].startswith("vector")))
                  + " a point."]
    lines += ["",
              "### The source's continued fraction at a fixed depth", "",
              f"Reproduce: {cmd('floquet')}.  The equation for lambda with both continued "
              "fractions truncated at depth N (000 sec. 2.2; `phelps_hunter.lambda_equation(N)`, "
              "derived by SymPy, a polynomial of degree 2(2N + 1) once cleared), lambdified for "
              "mpmath and solved by `mpmath.findroot` at 40 digits from lam_ref itself (so the "
              "error is the truncation's, not the root finder's).  *derive* is the symbolic "
              "equation's first construction.", "",
              "| depth N | degree | error (worst point) | solve per point | derive |",
              "|---|---|---|---|---|"]
    for r in res["cf"]:
        lines.append(f"| {r['depth']} | {r['degree']} | {sci_log(r['log_error'])} | "
                     f"{ms(r['time'])} | "
                     f"{ms(r['generate'])} |")
    cf = res["cf"]
    arb = {r["dps"]: r for r in res["routes"] if r["method"] == "arb"}
    if len(cf) >= 2 and arb:
        a0, a1 = cf[0], cf[-1]
        per = (a0["log_error"] - a1["log_error"]) / (a1["depth"] - a0["depth"])
        first = min(arb)
        lines += ["", f"Reading: each level of the fraction gains about {per:.1f} digits at these "
                  f"points (the tail ratio theta1^2/(C_m C_(m+2)) of 000 eq. 10), but solving the "
                  f"truncated equation at depth {a1['depth']} ({ms(a1['time'])}) costs "
                  f"{'more' if a1['time'] > arb[min(arb)]['time'] else 'less'} than "
                  f"the proved arb answer at dps {first} ({ms(arb[first]['time'])}), which picks "
                  "its depth from the digits asked.  The source's first approximation (depth 1, "
                  f"degree 6) is good to {sci_log(a0['log_error'])} only."]
    lines += ["", "### Stability limits of a/l (rod, I/(m l^2) = 4/3)", "",
              f"Reproduce: {cmd('floquet')}.  `stability.limits(ratio, 4/3, method)` against "
              "`floquet.stability_limits(ratio, \"4/3\", dps=30)` (every digit proved); relative "
              "errors of the lower and the upper limit; time: the least of three first calls at "
              "ratios 1e-12 apart (the module keeps what it computed per ratio; each method ran "
              "once before at omega0/omega = 0.07, so the one-time derivations and lambdify are "
              "not counted).  eq19 and eq19-corrected give no upper limit; the "
              "nu-series (series:N, eq28 = series:2) has none at N = 4, 8, ... and converges to "
              "a wrong one otherwise (docs/series.md, sec. 4).", ""]
    ratios = sorted({r["ratio"] for r in res["limits"]})
    lines.append("| method | " + " | ".join(f"omega0/omega = {x}: lower, upper" for x in ratios)
                 + " | time (worst) |")
    lines.append("|---|" + "---|" * len(ratios) + "---|")
    methods = list(dict.fromkeys(r["method"] for r in res["limits"]))
    for m in methods:
        rs = [r for r in res["limits"] if r["method"] == m]
        cells = [f"{sci(r['lower_error'])}, {sci(r['upper_error'])}" for r in rs]
        lines.append(f"| {m} | " + " | ".join(cells) + f" | {ms(max(r['time'] for r in rs))} |")
    lines.append("")
    return "\n".join(lines)


# -- part: bessel ---------------------------------------------------------------------------

BESSEL_DPS = [15, 30, 50, 100, 200]


def part_bessel(quick):
    import mpmath

    from bench_bessel import mpmath_loop  # the Bessel benchmark's mpmath.besseljzero loop
    from pendulab.analyses.bessel_identities import check_identities, default_grid
    from pendulab.analyses.bessel_zeros import bessel_zeros

    count = 20 if quick else 100
    dps_list = [15, 30, 50] if quick else BESSEL_DPS
    bessel_zeros(1, 3, 30)  # the derived expansions, once per process (as a session has them)
    rows = []
    grid = default_grid(20, near_zeros=False)
    for dps in dps_list:
        (z1, z2), t_arb = best_time(lambda: (bessel_zeros(1, count, dps),
                                             bessel_zeros(2, count, dps)), 2)
        mp_strings, t_mp = best_time(lambda: mpmath_loop(count, dps), 1)
        with mpmath.workdps(dps + 20):  # the reference: mpmath's root finder, 20 more digits
            ref = [[mpmath.nstr(mpmath.besseljzero(n, k), dps, strip_zeros=False)
                    for k in range(1, count + 1)] for n in (1, 2)]
        wrong_arb = sum(a != b for r, o in zip(ref, (z1.strings, z2.strings)) for a, b in zip(r, o))
        wrong_mp = sum(a != b for r, o in zip(ref, mp_strings) for a, b in zip(r, o))
        rep_a, t_ia = best_time(lambda: check_identities(2, dps, grid, engines=("arb",)), 2)
        rep_m, t_im = best_time(lambda: check_identities(2, dps, grid, engines=("mpmath",)), 1)
        rows.append({"dps": dps, "arb": t_arb, "mpmath": t_mp, "wrong_arb": wrong_arb,
                     "wrong_mpmath": wrong_mp, "id_arb": t_ia, "id_mpmath": t_im,
                     "id_arb_worst": float(rep_a.worst[0]),
                     "id_mpmath_worst": float(rep_m.worst[0]),
                     "id_certified": bool(rep_a.arb_certified)})
    return {"rows": rows, "count": count, "grid": len(grid)}


def bessel_markdown(res):
    c = res["count"]
    lines = ["## 4. Bessel zeros and identities (002): dps against time, arb against mpmath", "",
             f"Reproduce: {cmd('bessel')}.  Zeros: j_1,k and j_2,k for k = 1..{c} "
             f"(2 x {c} zeros); arb: `bessel_zeros(n, {c}, dps)` (interval Newton, every digit "
             "proved); mpmath: a plain `mpmath.besseljzero` loop at `workdps(dps)` (the loop of "
             "benchmarks/bench_bessel.py).  *wrong* counts the zeros whose dps-digit string "
             "differs from mpmath.besseljzero at dps + 20 digits, rounded to dps.  Identities: "
             f"`check_identities(2, dps, {res['grid']} log-spaced points in [1e-30, 1e6])` (cross "
             "product, both derivative rules, z W = 2/pi; n = 0..2) with one engine each; "
             "*worst* is the largest relative defect found.", "",
             "| dps | zeros, arb | zeros, mpmath | ratio | wrong: arb, mpmath | identities, arb | "
             "identities, mpmath | ratio | worst defect: arb, mpmath |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        lines.append(f"| {r['dps']} | {ms(r['arb'])} | {ms(r['mpmath'])} | "
                     f"{r['mpmath'] / r['arb']:.1f}x | {r['wrong_arb']}, {r['wrong_mpmath']} | "
                     f"{ms(r['id_arb'])} | {ms(r['id_mpmath'])} | "
                     f"{r['id_mpmath'] / r['id_arb']:.1f}x "
                     f"| {sci(r['id_arb_worst'])}, {sci(r['id_mpmath_worst'])} |")
    rows = res["rows"]
    rz = [r["mpmath"] / r["arb"] for r in rows]
    ri = [r["id_mpmath"] / r["id_arb"] for r in rows]
    lines += ["", f"Reading: arb is {min(rz):.1f}x to {max(rz):.1f}x faster for the zeros and "
              f"{min(ri):.0f}x to {max(ri):.0f}x for the identities, and proves what it prints; "
              f"the plain mpmath loop printed {sum(r['wrong_mpmath'] for r in rows)} wrong last "
              f"digits over the rows (arb {sum(r['wrong_arb'] for r in rows)}).  Both engines "
              "find the identities' defects far below 10^-dps.", ""]
    return "\n".join(lines)


# -- part: kernels --------------------------------------------------------------------------

KERNEL_SIZES = [1, 16, 256, 4096]


def part_kernels(quick):
    import tempfile
    import types

    import numpy as np

    from bench_rk4 import numpy_baseline  # plain NumPy RK4 over an ensemble
    from pendulab.numerics import ckernel, codegen, integrate

    fos = _rod()
    steps = 3000  # 30 drive periods at the source's 100 steps per period
    dt = float(fos.period) / 100
    sizes = [1, 256] if quick else KERNEL_SIZES
    compile_s = cache_s = None
    if not quick:  # the first use compiles; later ones load the library from the cache
        saved = os.environ.get("PENDULAB_CACHE_DIR")
        with tempfile.TemporaryDirectory() as tmp:
            os.environ["PENDULAB_CACHE_DIR"] = tmp
            try:
                ckernel.clear_loaded()
                _, compile_s = best_time(lambda: ckernel.load(fos, required=True), 1)
                ckernel.clear_loaded()
                _, cache_s = best_time(lambda: ckernel.load(fos, required=True), 1)
            finally:
                if saved is None:
                    del os.environ["PENDULAB_CACHE_DIR"]
                else:
                    os.environ["PENDULAB_CACHE_DIR"] = saved
                ckernel.clear_loaded()
    ckernel.load(fos)
    readable = codegen.numpy_functions(fos)["rhs"]  # the module written to generated/
    shim = types.SimpleNamespace(lambdified=lambda: readable)
    rng = np.random.default_rng(5)
    rows = []
    for n in sizes:
        params = np.column_stack([rng.uniform(0, 1, n), rng.uniform(0, 1, n)])
        y0 = np.tile([0.06, 0.01], (n, 1))
        c, t_c = best_time(lambda: integrate.ensemble_rk4(fos, y0, params, 0.0, dt, steps,
                                                          backend="c"), 3)
        q, t_q = best_time(lambda: integrate.ensemble_rk4(fos, y0, params, 0.0, dt, steps,
                                                          backend="numpy"), 1 if quick else 2)
        k_steps = steps if n * steps <= 256 * 3000 * 16 else steps // 10
        t_r, _, mean_r = numpy_baseline(shim, y0, params, dt, k_steps)
        t_r *= steps / k_steps
        same = bool(np.array_equal(c.y, q.y) and np.array_equal(c.mean_theta, q.mean_theta))
        d = np.abs(mean_r - c.mean_theta)
        dev = (float(np.median(d)), float(np.max(d))) if k_steps == steps else (None, None)
        rows.append({"n": n, "c": t_c, "numpy": t_q, "readable": t_r, "same_bits": same,
                     "readable_mean_dev": dev, "scaled": k_steps != steps})
    return {"rows": rows, "steps": steps, "compile": compile_s, "cache": cache_s,
            "threads": integrate.default_threads()}


def kernels_markdown(res):
    lines = ["## 5. The generated NumPy modules against the C kernel", "",
             f"Reproduce: {cmd('kernels')}.  RK4 over n trajectories of the rod (seeded random "
             f"a/l, omega0/omega in [0, 1]), {res['steps']} steps of pi/100, statistics kept.  "
             f"*C*: `ensemble_rk4(..., backend=\"c\")` ({res['threads']} threads); *NumPy kernel*: "
             "`backend=\"numpy\"`, the generated NumPy twin of the kernel (same operations, same "
             "sine: the same bits, checked in every row); *readable module*: the generated "
             "`rhs_numpy.py` (NumPy's sin) in a plain NumPy RK4 loop (benchmarks/bench_rk4.py's "
             "baseline A); its signed means differ from the kernel's by the rounding of the sine "
             "(*deviation*: median and largest over the n trajectories; the largest is that of "
             "a chaotic cell, which amplifies a last-bit difference, docs/numerics.md).  "
             "Error against the reference: the same for all three (section 2).", "",
             "| n | C | NumPy kernel | readable module | NumPy kernel / C | readable / C "
             "| same bits | deviation of the mean: median, max |",
             "|---|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        note = " (scaled from a tenth of the steps)" if r["scaled"] else ""
        lines.append(f"| {r['n']} | {ms(r['c'])} | {ms(r['numpy'])} | {ms(r['readable'])}{note} | "
                     f"{r['numpy'] / r['c']:.1f}x | {r['readable'] / r['c']:.1f}x | "
                     f"{r['same_bits']} | {sci(r['readable_mean_dev'][0])}, "
                     f"{sci(r['readable_mean_dev'][1])} |")
    rows = res["rows"]
    lines += ["", f"Reading: the C kernel's lead is largest for few trajectories "
              f"({rows[0]['numpy'] / rows[0]['c']:.0f}x at n = {rows[0]['n']}: the NumPy paths pay "
              "Python's cost per operation and step whatever n is) and smallest for large "
              f"ensembles ({rows[-1]['numpy'] / rows[-1]['c']:.0f}x at n = {rows[-1]['n']}); the "
              "NumPy twin buys the same bits as C without a compiler, at "
              f"{min(r['numpy'] / r['readable'] for r in rows):.1f}x to "
              f"{max(r['numpy'] / r['readable'] for r in rows):.1f}x the cost of the readable "
              "module."]
    if res["compile"] is not None:
        lines += ["", f"The first use compiles the kernel: {ms(res['compile'])} (into an empty "
                  f"cache directory); a later process loads it from the cache in "
                  f"{ms(res['cache'])}."]
    lines.append("")
    return "\n".join(lines)


# -- the tasks, the defaults, the figures, the doc ------------------------------------------

def tasks(results):
    """[(task, cheapest setting, measured, command)] from whichever parts have results."""
    out = []
    s = results.get("series")
    if s:
        for (nu, th1), target in (((0.5, 0.3), 1e-10), ((0.5, 0.6), 1e-10), ((0.5, 0.1), 1e-14),
                                  ((0.5, 0.9), 1e-6)):
            rows = [r for r in s["data"]["rows"] if r["nu"] == nu and r["theta1"] == th1
                    and r["dps"] is None]
            if not rows:
                continue
            best = cheapest(rows, target, cost="order")
            got = (f"order {best['order']} (double): error {sci(best['error'])}, "
                   f"evaluate {ms(best['evaluate'])}, generate {ms(best['generate'])}"
                   if best else f"no order up to {max(s['data']['orders'])} reaches it")
            out.append((f"theta0 of the series to {target:g} at nu = {nu}, theta1 = {th1}",
                        got, "series"))
    r = results.get("rk4")
    if r:
        for target in (1e-6, 1e-8, 1e-10):
            rows = r["data"]["rows"]
            rk = cheapest([x for x in rows if x["method"] == "rk4"], target)
            dp = cheapest([x for x in rows if x["method"] == "dop853"], target)
            parts = []
            if rk:
                parts.append(f"RK4 {rk['setting']} steps per period ({sci(rk['error'])}, "
                             f"{ms(rk['time'])}; {ms(rk['per_trajectory'])} per trajectory in an "
                             "ensemble)")
            if dp:
                parts.append(f"DOP853 rtol {dp['setting']:g} ({sci(dp['error'])}, "
                             f"{ms(dp['time'])})")
            out.append((f"{r['data']['periods']} drive periods of motion to {target:g}",
                        "; ".join(parts) or "none measured", "rk4"))
    f = results.get("floquet")
    if f:
        d = f["data"]
        for target in (1e-6, 1e-12):
            for ratio in sorted({x["ratio"] for x in d["limits"]}):
                rows = [x for x in d["limits"] if x["ratio"] == ratio]
                best = cheapest(rows, target)
                exact = next(x for x in rows if x["method"] == "exact")
                got = (f"`{best['method']}` ({sci(best['error'])}, {ms(best['time'])})"
                       if best else "none")
                if best and best is not exact:
                    got += (f"; `exact`, every digit proved: {sci(exact['error'])}, "
                            f"{ms(exact['time'])}")
                out.append((f"stability limits of a/l to {target:g} (rod, omega0/omega = {ratio})",
                            got, "floquet"))
        for digits in (15, 50, 1000):  # D significant digits: relative error <= 5 10^-D
            rows = [x for x in d["routes"] if x["dps"] is not None
                    and x["log_error"] <= math.log10(5) - digits]
            best = min(rows, key=lambda x: x["time"]) if rows else None
            if best:
                out.append((f"lambda to {digits} significant digits (relative error <= "
                            f"5e-{digits})", f"`{best['method']}` at dps {best['dps']} "
                            f"({sci_log(best['log_error'])}, {ms(best['time'])} per point)",
                            "floquet"))
        dbl = [x for x in d["routes"] if x["dps"] is None]
        if dbl:
            v = min(dbl, key=lambda x: x["time"])
            out.append(("lambda in double precision, many points",
                        f"{v['method']} ({sci_log(v['log_error'])}, {ms(v['time'])} per point)",
                        "floquet"))
    b = results.get("bessel")
    if b:
        for digits in (30, 100):
            row = next((x for x in b["data"]["rows"] if x["dps"] == digits), None)
            if row:
                out.append((f"Bessel zeros to {digits} digits",
                            f"arb at dps {digits} ({row['wrong_arb']} wrong, "
                            f"{ms(row['arb'])} for {2 * b['data']['count']}; mpmath "
                            f"{ms(row['mpmath'])}, {row['wrong_mpmath']} wrong)", "bessel"))
    k = results.get("kernels")
    if k:
        big = max(k["data"]["rows"], key=lambda x: x["n"])
        one = min(k["data"]["rows"], key=lambda x: x["n"])
        out.append((f"RK4 ensembles (n = {one['n']} .. {big['n']})",
                    f"the C kernel: {one['numpy'] / one['c']:.0f}x to "
                    f"{big['numpy'] / big['c']:.0f}x "
                    "faster than its NumPy twin, same bits", "kernels"))
    return out


#: the defaults this page checks: (where, what it is for); where is "limits:NAME" (the
#: default of pendulab.limits.LIMITS[NAME]), "module:function(parameter)" (a signature's
#: default), "module:OPTIONS[key]" (a product option's default) or "module:NAME" (a module
#: attribute).  tests/test_tradeoffs_doc.py compares the
#: values the doc prints with the code's.
DEFAULTS = [
    ("limits:experiments.steps_per_period", "RK4 steps per drive period of sweeps, experiments, "
     "`pendulab simulate`"),
    ("limits:experiments.periods", "drive periods of a trajectory"),
    ("pendulab.numerics.integrate:reference_trajectory(rtol)", "the DOP853 reference"),
    ("limits:series.order", "order of the series product"),
    ("limits:notes.series_order", "order of the notes' series section"),
    ("pendulab.analyses.floquet:characteristic_exponent(dps)",
     "lambda without dps: arb rounded to a double within its size limit, hill beyond"),
    ("limits:floquet.dps", "digits of the floquet product"),
    ("pendulab.analyses.floquet:stability_limits(dps)", "limits without dps: proved doubles"),
    ("limits:bessel.dps", "digits of the bessel product"),
    ("limits:quarter_periods.dps", "digits of the quarter_periods product"),
    ("limits:stability.methods", "methods the stability product compares"),
    ("pendulab.analyses.variable_length_motion:RTOL", "DOP853 rtol of the string's motion "
     "(product motion)"),
    ("pendulab.products.floquet:OPTIONS[method]", "route of the floquet product"),
]


def default_value(where):
    """The code's current value of a DEFAULTS entry (see DEFAULTS)."""
    import importlib
    import inspect
    if where.startswith("limits:"):
        from pendulab.limits import LIMITS
        return LIMITS[where[len("limits:"):]][3]
    module, name = where.split(":")
    mod = importlib.import_module(module)
    if "(" in name:
        fn, param = name[:-1].split("(")
        return inspect.signature(getattr(mod, fn)).parameters[param].default
    if name.startswith("OPTIONS["):
        return mod.OPTIONS[name[len("OPTIONS["):-1]][1]
    return getattr(mod, name)


def verdicts(results):
    """{where: verdict text} from the measured tables (None: the part has not run)."""
    out = {}
    r = results.get("rk4")
    if r:
        rows = r["data"]["rows"]
        at = next((x for x in rows if x["method"] == "rk4" and x["setting"] == 100), None)
        need = cheapest([x for x in rows if x["method"] == "rk4"], 1e-8)
        if at:
            out["limits:experiments.steps_per_period"] = (
                f"error {sci(at['error'])} over {r['data']['periods']} periods: enough for the "
                "criteria it serves (abs(mean theta) < 0.1, max abs(theta) < pi/2: errors far "
                "below 0.01) and the source's own setting (000 sec. 4); motion to 1e-8 needs "
                + (f"{need['setting']}" if need else "more") + " steps per period. Follows, "
                "for its use.")
        dp = [x for x in rows if x["method"] == "dop853"]
        if dp:
            out["pendulab.numerics.integrate:reference_trajectory(rtol)"] = (
                f"rtol 1e-12 already gives {sci(min(x['error'] for x in dp))} against it; as the "
                "reference that measures RK4 it must be the most accurate setting: follows.")
        out["limits:experiments.periods"] = ("the source's 300 periods (000 sec. 4); not an "
                                             "accuracy setting.")
        out["pendulab.analyses.variable_length_motion:RTOL"] = (
            "the motion product compares the integration with 002's closed form, so it needs "
            "the reference's accuracy; on the pivot above rtol 1e-12 is within "
            f"{sci(min(x['error'] for x in dp))} of 1e-13 (the string was not measured here): "
            "follows." if dp else None)
    s = results.get("series")
    if s:
        rows = [x for x in s["data"]["rows"] if x["dps"] is None and x["order"] == 8]
        txt = ", ".join(f"{sci(x['error'])} at theta1 = {x['theta1']} (nu = {x['nu']})"
                        for x in rows[:3])
        ok = [x["theta1"] for x in rows if x["nu"] == 0.5 and x["error"] <= 1e-6]
        reach = (f"1e-6 up to theta1 = {max(ok)} at nu = 0.5 among those measured" if ok
                 else "1e-6 at none of the points measured")
        out["limits:series.order"] = (
            f"order 8 gives {txt}: {reach}.  The product writes exact "
            "coefficients, whose cost grows fast with N, and whoever evaluates them picks "
            "the order; a product default, not an accuracy promise: follows.")
        out["limits:notes.series_order"] = "as series.order (the notes show the series): follows."
    f = results.get("floquet")
    if f:
        lim = f["data"]["limits"]
        s4 = [x for x in lim if x["method"] == "series:4"]
        i4 = [x for x in lim if x["method"] == "integer-series:4"]
        if s4 and i4:
            out["limits:stability.methods"] = (
                "a comparison of the source's methods, not a route to a number: series:4 has no "
                "upper limit at all (docs/series.md, sec. 4), integer-series:4 is within "
                f"{sci(max(x['error'] for x in i4))}; 'exact' is in the list.  "
                "Follows for its purpose (the lower limit of series:4 is within "
                f"{sci(max(x['lower_error'] for x in s4))}).")
    f = results.get("floquet")
    if f:
        routes = f["data"]["routes"]
        dflt = next((x for x in routes if "default" in x["method"]), None)
        a17 = next((x for x in routes if x["method"] == "arb" and x["dps"] == 17), None)
        ds = f["data"].get("double_sample")
        if dflt and a17 and ds:
            th = sum(x["hill"] for x in ds) / len(ds)
            ta = sum(x["arb17"] for x in ds) / len(ds)
            follows = dflt["time"] <= 2 * a17["time"] and th <= 2 * ta
            out["pendulab.analyses.floquet:characteristic_exponent(dps)"] = (
                ("follows" if follows else "**does not follow**")
                + f": without dps the route is {dflt['method'].split()[0]} ({ms(dflt['time'])} "
                f"per point, error {sci_log(dflt['log_error'])}); arb at dps 17 takes "
                f"{ms(a17['time'])} (the default's time / arb's: {dflt['time'] / a17['time']:.1f}), every digit "
                f"proved (error {sci_log(a17['log_error'])}); on {len(ds)} random points up to "
                f"the fourth band {ms(th)} against {ms(ta)} ({th / ta:.1f}x), the same worst "
                "error (section 3)."
                + ("" if follows else "  Without dps, the arb route at 17 digits (within its "
                   "size limit abs(theta0) + 2 abs(theta1) <= 3e4), rounded to a double, would "
                   "be as accurate and that much cheaper."))
        arbs = {x["dps"]: x for x in routes if x["method"] == "arb"}
        mps = [x for x in routes if x["method"] in ("hill", "cf", "monodromy")
               and x["dps"] in arbs]
        if mps:
            ratios = [x["time"] / arbs[x["dps"]]["time"] for x in mps]
            out["pendulab.products.floquet:OPTIONS[method]"] = (
                "auto is arb with the product's dps (within arb's size limit), the cheapest "
                f"route measured: {min(ratios):.0f}x to {max(ratios):.0f}x cheaper than the "
                "mpmath routes at the same dps, and proved: follows.")
        a30 = next((x for x in routes if x["method"] == "arb" and x["dps"] == 30), None)
        a15 = next((x for x in routes if x["method"] == "arb" and x["dps"] == 15), None)
        if a30 and a15:
            out["limits:floquet.dps"] = (f"30 proved digits cost {ms(a30['time'])} per point "
                                         f"against {ms(a15['time'])} for 15: follows.")
        lim = f["data"]["limits"]
        exact = [x for x in lim if x["method"] == "exact"]
        if exact:
            worst = max(x["time"] for x in exact)
            cheaper = sorted({x["method"] for x in lim if x["method"] != "exact"
                              and x["error"] is not None and x["error"] <= 1e-6
                              and x["time"] < min(e["time"] for e in exact
                                                  if e["ratio"] == x["ratio"])})
            out["pendulab.analyses.floquet:stability_limits(dps)"] = (
                f"the proved doubles: error {sci(max(x['error'] for x in exact))}, at most "
                f"{ms(worst)} per ratio; the only route to 1e-12 in the table"
                + (f"; to 1e-6 {', '.join(cheaper)} can be cheaper at some ratios but prove "
                   "nothing and need their order chosen per ratio" if cheaper else "")
                + ": follows.")
    b = results.get("bessel")
    if b:
        row = next((x for x in b["data"]["rows"] if x["dps"] == 30), None)
        if row:
            txt = (f"arb at dps 30: {ms(row['arb'])} for {2 * b['data']['count']} proved zeros, "
                   f"{row['mpmath'] / row['arb']:.0f}x less than mpmath: follows.")
            out["limits:bessel.dps"] = txt
            out["limits:quarter_periods.dps"] = txt
    return out


def figure(part, curves, xlabel, ylabel, title, higher_better=False, front=True):
    """An SVG (text) of ``curves`` [(label, [(x, y, tag)])], log-log, the Pareto front of each
    curve ringed; fixed hash salt and no date, so the same numbers give the same bytes."""
    import io

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rc = {"svg.hashsalt": "pendulab", "svg.fonttype": "path", "figure.figsize": (6.4, 4.4),
          "font.size": 8}
    with matplotlib.rc_context(rc):
        fig, ax = plt.subplots()
        try:
            for k, (label, pts) in enumerate(curves):
                pts = [p for p in pts if p[0] > 0 and p[1] is not None and 0 < p[1] < math.inf]
                if not pts:
                    continue
                xs, ys = [p[0] for p in pts], [p[1] for p in pts]
                colour = f"C{k % 10}"
                ax.plot(xs, ys, "o-", color=colour, ms=3, lw=1, label=label)
                for p in pts:
                    ax.annotate(str(p[2]), (p[0], p[1]), fontsize=6, color=colour,
                                textcoords="offset points", xytext=(3, 3))
                if front:
                    best = pareto([(p[0], -p[1] if higher_better else p[1]) for p in pts])
                    ax.plot([xs[i] for i in best], [ys[i] for i in best], "o", mfc="none",
                            mec=colour, ms=8, mew=1.2)
            if front:
                ax.plot([], [], "o", mfc="none", mec="k", ms=8, label="Pareto front (ringed)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            ax.set_title(title)
            ax.legend(fontsize=6, frameon=False)
            ax.grid(True, which="major", lw=0.3)
            buf = io.StringIO()
            fig.savefig(buf, format="svg", metadata={"Date": None})
        finally:
            plt.close(fig)
    return buf.getvalue()


def figures(results):
    """{file name: SVG text} of the parts that have results."""
    out = {}
    s = results.get("series")
    if s:
        curves = []
        for nu, th1 in s["data"]["points"]:
            rows = [r for r in s["data"]["rows"] if r["nu"] == nu and r["theta1"] == th1
                    and r["dps"] == 30]
            curves.append((f"nu = {nu}, theta1 = {th1}",
                           [(r["generate"] + r["evaluate"], max(r["error"], 1e-32), r["order"])
                            for r in rows]))
        out["tradeoffs_series.svg"] = figure(
            "series", curves, "seconds: generate the exact coefficients + evaluate at dps 30",
            "|theta0_N - theta0|", "The series (000 eq. 20): order N (labels) against error")
    r = results.get("rk4")
    if r:
        rows = r["data"]["rows"]
        out["tradeoffs_rk4.svg"] = figure("rk4", [
            ("RK4, one trajectory", [(x["time"], x["error"], x["setting"]) for x in rows
                                     if x["method"] == "rk4"]),
            ("RK4, per trajectory of an ensemble", [(x["per_trajectory"], x["error"], x["setting"])
                                                    for x in rows if x["method"] == "rk4"]),
            ("DOP853 (labels: rtol)", [(x["time"], x["error"], f"{x['setting']:g}") for x in rows
                                       if x["method"] == "dop853"])],
            "seconds", "max error over the trajectory",
            f"{r['data']['periods']} drive periods: RK4 steps per period / DOP853 rtol")
    f = results.get("floquet")
    if f:
        d = f["data"]
        curves = []
        for m in dict.fromkeys(x["method"] for x in d["routes"] if x["dps"] is not None):
            curves.append((f"characteristic_exponent, {m} (labels: dps)",
                           [(x["time"], -x["log_error"], x["dps"]) for x in d["routes"]
                            if x["method"] == m]))
        curves.append(("truncated continued fraction (labels: depth)",
                       [(x["time"], -x["log_error"], x["depth"]) for x in d["cf"]]))
        out["tradeoffs_floquet.svg"] = figure("floquet", curves, "seconds per point",
                                              "correct digits, -log10 (relative error in lambda)",
                                              "lambda: route and dps or depth against digits",
                                              higher_better=True)
    b = results.get("bessel")
    if b:
        rows = b["data"]["rows"]
        out["tradeoffs_bessel.svg"] = figure("bessel", [
            ("zeros, arb", [(x["arb"], 10.0 ** -x["dps"], x["dps"]) for x in rows]),
            ("zeros, mpmath", [(x["mpmath"], 10.0 ** -x["dps"], x["dps"]) for x in rows]),
            ("identities, arb", [(x["id_arb"], 10.0 ** -x["dps"], x["dps"]) for x in rows]),
            ("identities, mpmath", [(x["id_mpmath"], 10.0 ** -x["dps"], x["dps"]) for x in rows])],
            "seconds", "10^-dps (digits asked; labels: dps)",
            f"Bessel: {2 * b['data']['count']} zeros and the identities, by dps")
    k = results.get("kernels")
    if k:
        rows = k["data"]["rows"]
        out["tradeoffs_kernels.svg"] = figure("kernels", [
            ("C kernel", [(x["n"], x["c"] / x["n"], x["n"]) for x in rows]),
            ("NumPy kernel", [(x["n"], x["numpy"] / x["n"], x["n"]) for x in rows]),
            ("readable NumPy module", [(x["n"], x["readable"] / x["n"], x["n"]) for x in rows])],
            "trajectories n in the ensemble", "seconds per trajectory (the same error for all)",
            f"RK4, {k['data']['steps']} steps: time per trajectory by ensemble size", front=False)
    return out


MARKDOWN = {"series": series_markdown, "rk4": rk4_markdown, "floquet": floquet_markdown,
            "bessel": bessel_markdown, "kernels": kernels_markdown}
RUN = {"series": part_series, "rk4": part_rk4, "floquet": part_floquet, "bessel": part_bessel,
       "kernels": part_kernels}


def document(results):
    """docs/tradeoffs.md from the results of every part that has run."""
    head = ["# Speed against accuracy, measured", "",
            f"Written by `{COMMAND}` (every part; `--part NAME` reruns one and keeps the others' "
            "last results, which docs/tradeoffs.json holds).  Each table names the command that "
            "reproduces it.  Times are wall-clock seconds on a shared 2-core machine, best of a "
            "few runs; they move with the load, so compare within a table (the ratios), not "
            "across runs.  Errors are against independent references named with each table.", "",
            "| part | run (UTC) | mode | load average | seconds |", "|---|---|---|---|---|"]
    for part in PARTS:
        if part in results:
            r = results[part]
            mode = "quick" if r["quick"] else "full"
            head.append(f"| {part} | {r['date']} | {mode} | {r['load']:.1f} | "
                        f"{r['seconds']:.0f} |")
    head += ["", "## The cheapest setting for each task", "",
             "| task | cheapest setting measured (error, time) | command |", "|---|---|---|"]
    for task, got, part in tasks(results):
        head.append(f"| {task} | {got} | {cmd(part)} |")
    head += ["", "## The project's defaults against these tables", "",
             "Each default as the code has it now (tests/test_tradeoffs_doc.py compares this "
             "column with the code).", "",
             "| default | value | for | verdict |", "|---|---|---|---|"]
    verdict = verdicts(results)
    for where, what in DEFAULTS:
        head.append(f"| `{where}` | `{default_value(where)!r}` | {what} | "
                    f"{verdict.get(where) or 'not measured in this run'} |")
    head.append("")
    body = [MARKDOWN[p](results[p]["data"]) for p in PARTS if p in results]
    figs = [f"![{p}](figures/tradeoffs_{p}.svg)" for p in PARTS if p in results]
    tail = ["## Figures", "",
            "Error against cost, log-log, each curve's Pareto front ringed (no other setting of "
            "that curve is both faster and more accurate).  The lambda figure plots the correct "
            "digits (higher is better) instead of the error, which spans 1e-1 to 1e-1000; the "
            "Bessel figure the digits asked (every engine reached them, up to the last digit "
            "counted as *wrong* in section 4); the kernels' figure the time per trajectory "
            "by ensemble size (no front: the error is the same for all three).", ""] + figs + [""]
    return "\n".join(head + body + tail)


def main(argv=None):
    args = build_parser().parse_args(argv)
    _paths()
    parts = args.part or list(PARTS)
    write = not args.no_write and (not args.quick or args.write)
    results = {}
    if write and RESULTS.exists():
        results = json.loads(RESULTS.read_text())
    for part in [] if args.redraw else parts:
        t = time.perf_counter()
        print(f"== {part} ==", flush=True)
        data = RUN[part](args.quick)
        results[part] = {"data": data, "seconds": time.perf_counter() - t,
                         "date": datetime.datetime.now(datetime.timezone.utc)
                                                  .strftime("%Y-%m-%d %H:%M"),
                         "load": os.getloadavg()[0], "quick": args.quick}
        print(MARKDOWN[part](data), flush=True)
    text = document(results)
    if not write:
        print(text.split("## 1.")[0])
        return 0
    FIGURES.mkdir(parents=True, exist_ok=True)
    files = {FIGURES / name: svg for name, svg in figures(results).items()}
    files[RESULTS] = json.dumps(results, indent=1, sort_keys=True) + "\n"
    files[DOC] = text
    for path, content in files.items():  # each file whole or not at all (temp file + rename)
        tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
        tmp.write_text(content)
        os.replace(tmp, path)
    print(f"wrote {DOC.relative_to(ROOT)}, {RESULTS.relative_to(ROOT)} and figures in "
          f"{FIGURES.relative_to(ROOT)}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
