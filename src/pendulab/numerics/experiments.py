"""The source's numerical experiments (000_8cba66c4fdf94ac6.txt sec. 4, Figs. 2-5), reproduced.

Every number comes from the derivation: the first-order system in tau
(:func:`pendulab.numerics.model.pivot_system`), its Mathieu parameters
(:func:`pendulab.numerics.model.mathieu_parameters`), the integrators of
:mod:`pendulab.numerics.integrate`, the sweeps of :mod:`pendulab.numerics.sweep`,
the limits of :func:`pendulab.analyses.stability.limits` and the series of
:mod:`pendulab.analyses.series`.

* :func:`first_experiment` - 10 x 10 initial conditions (theta(0), theta'(0))
  times a 10 x 10 (a/l, omega0/omega) grid; the number of stable pairs per
  initial condition (000 sec. 4 reports 5 to 14).
* :func:`stability_maps` - Figs. 3 and 4: the (a/l, omega0/omega) map of every
  criterion for one initial condition, with eq. 28 and the exact limits.
* :func:`fig5` - a/l = 1/5, omega0/omega = 1/20: the numerical theta(tau)
  against the series solution (000 eq. 23) at order 2 and at order N.
* :func:`fig2` - theta0 = -2e-3, theta1 = 0.2: the motion of Mathieu's
  equation (000 eq. 7), its slow part and the pivot.
"""

import math
from fractions import Fraction

from pendulab.errors import InputError
from pendulab.numerics import sweep as S

#: Initial conditions (theta(0), theta'(0)) named by the source (000 sec. 4).
INITIAL = {
    "text": (0.06, 0.01),      # Fig. 3 as the text gives it (the 14-pair initial condition)
    "caption": (0.01, 0.06),   # Fig. 3 as its caption gives it
    "fig4": (0.1, 0.1),        # Fig. 4 (text and caption agree; the 5-pair initial condition)
}
#: The source's counts of stable pairs on the 10 x 10 grid (000 sec. 4).
SOURCE_COUNTS = {"min": 5, "max": 14, (0.1, 0.1): 5, (0.06, 0.01): 14}
#: Parameter-grid conventions for "10 x 10 in [0, 1]".
CONVENTIONS = ("linspace", "right", "left")


def axis(n, convention="linspace"):
    """n values of a/l or omega0/omega in [0, 1]: ``linspace`` k/(n-1), k = 0..n-1 (both ends);
    ``right`` k/n, k = 1..n (0 left out); ``left`` k/n, k = 0..n-1 (1 left out)."""
    n = S._count(n, "grid", 1, 2000)
    if convention == "linspace":
        return S.linspace_grid(n)
    if convention == "right":
        return tuple(float(Fraction(k, n)) for k in range(1, n + 1))
    if convention == "left":
        return tuple(float(Fraction(k, n)) for k in range(n))
    raise InputError(f"grid convention must be one of {', '.join(CONVENTIONS)}, got {convention!r}")


def initial_grid(n=10, top=0.1):
    """The source's initial conditions: theta(0), theta'(0) each on top*k/n, k = 1..n.

    With n = 10 this is 0.01, 0.02, ..., 0.1, the only ten-point grid of
    [0, 0.1] that holds both (0.1, 0.1) and (0.06, 0.01), which the source
    names.  Pairs are ordered theta(0)-major.
    """
    n = S._count(n, "initial grid", 1, 100)
    vals = [float(Fraction(str(top)) * k / n) for k in range(1, n + 1)]
    return tuple((th, om) for th in vals for om in vals)


def first_experiment(system=None, grid=10, convention="linspace", periods=300, steps_per_period=100,
                     n_initial=10, **sweep_kw):
    """Stable pairs per initial condition, for every nonlinear criterion from one run.

    Returns {"initial": [(theta(0), theta'(0)), ...], "counts": {criterion:
    [count per initial condition]}, "floquet": count of the Floquet map,
    "a_over_l", "w0_over_w", "simulated", "backends"}.
    """
    system = system or S.SystemSpec()
    values = axis(grid, convention)
    spec = S.make_spec(system, a_over_l=values, w0_over_w=values, initial=initial_grid(n_initial),
                       periods=periods, steps_per_period=steps_per_period, criterion="mean")
    res = S.sweep(spec, **sweep_kw)
    counts = {}
    for crit in ("mean", "mean-abs", "bounded"):
        v = S.verdict(crit, res.stats).reshape(len(spec.initial), -1).sum(axis=1)
        counts[crit] = [int(x) for x in v]
    floquet = int(S.floquet_verdict(S.replace(spec, initial=spec.initial[:1])).sum())
    return {"initial": list(spec.initial), "counts": counts, "floquet": floquet,
            "a_over_l": list(values), "w0_over_w": list(values), "convention": convention,
            "simulated": res.simulated, "backends": list(res.backends), "seconds": res.seconds}


def stability_maps(system=None, grid=100, initial=INITIAL["text"], periods=300, steps_per_period=100,
                   criteria=S.CRITERIA, prune=False, **sweep_kw):
    """Figs. 3-4: {criterion: bool map (n_w, n_a)}, counts, the grid and how many trajectories ran.

    One run gives the statistics of every nonlinear criterion; ``floquet``
    integrates nothing.  With ``prune`` each nonlinear criterion runs
    :func:`pendulab.numerics.sweep.pruned_sweep` instead (one run each).
    """
    system = system or S.SystemSpec()
    bad = [c for c in criteria if c not in S.CRITERIA]
    if bad:
        raise InputError(f"criteria must be among {', '.join(S.CRITERIA)}, got {', '.join(map(str, bad))}")
    values = S.linspace_grid(grid)
    spec = S.make_spec(system, a_over_l=values, w0_over_w=values, initial=[initial], periods=periods,
                       steps_per_period=steps_per_period, criterion="mean")
    maps, simulated = {}, {}
    nonlinear = [c for c in criteria if c != "floquet"]
    if nonlinear and not prune:
        res = S.sweep(spec, **sweep_kw)
        for c in nonlinear:
            maps[c] = S.verdict(c, res.stats)[0]
            simulated[c] = res.simulated
    for c in nonlinear if prune else ():
        res = S.pruned_sweep(S.replace(spec, criterion=c), **sweep_kw)
        maps[c] = res.stable[0]
        simulated[c] = res.simulated
    if "floquet" in criteria:
        maps["floquet"] = S.floquet_verdict(spec).reshape(spec.shape)[0]
        simulated["floquet"] = 0
    return {"a_over_l": values, "w0_over_w": values, "initial": tuple(initial),
            "maps": {c: maps[c] for c in criteria}, "counts": {c: int(maps[c].sum()) for c in criteria},
            "simulated": simulated, "cells": spec.cells}


def inertia_ratio(system):
    """I/(m l^2) of ``system`` (a SystemSpec) as an exact SymPy number, from the system's own inertia."""
    import sympy as sp
    if system.inertia_ratio is not None:
        return sp.nsimplify(system.inertia_ratio)
    eqs, _ = S._stages(system)
    value = sp.simplify(eqs.system.inertia_ratio)
    if not value.is_number:
        raise InputError(f"the limits need a numeric I/(m l^2); this body gives {value}")
    return value


def limit_curves(system, w_values, methods=("eq28", "exact")):
    """{method: (lower (n,), upper (n,))} of a/l over ``w_values`` by
    :func:`pendulab.analyses.stability.limits` (None where a method gives no limit -> NaN)."""
    import numpy as np

    from pendulab.analyses.stability import limits
    r = float(inertia_ratio(system))
    out = {}
    for m in methods:
        lo, up = [], []
        for w in w_values:
            a, b = limits(w, r, m)
            lo.append(np.nan if a is None else a)
            up.append(np.nan if b is None else b)
        out[m] = (np.array(lo), np.array(up))
    return out


def floquet_region(system, values):
    """Bool map (len(values), len(values)) of Floquet stability on values x values (rows omega0/omega)."""
    spec = S.make_spec(system, a_over_l=values, w0_over_w=values, criterion="floquet")
    return S.floquet_verdict(spec).reshape(len(values), len(values))


# ---------------------------------------------------------------------------
# Fig. 5: numerics against the series solution (000 eq. 23)
# ---------------------------------------------------------------------------

def series_nu(theta0, theta1, order):
    """nu of the source's branch (oscillation about the inverted position) at ``order``:
    the smallest nu in (0, 1) with theta0_of_nu(nu, theta1, order) = theta0 (000 eq. 20;
    at order 2 the root of 000 eq. 27 with the minus sign)."""
    import warnings

    import numpy as np

    from pendulab.analyses.series import theta0_of_nu
    from pendulab.errors import AccuracyWarning
    from pendulab.numerics.roots import brent_root

    grid = np.linspace(1e-4, 0.999, 2000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        vals, _ = theta0_of_nu(grid, theta1, order, on_domain="warn")
    f = np.asarray(vals) - theta0
    ok = np.isfinite(f)
    sign = np.flatnonzero(ok[:-1] & ok[1:] & (np.sign(f[:-1]) != np.sign(f[1:])))
    if not sign.size:
        raise InputError(f"the order-{order} series has no nu in (0, 1) with theta0 = {theta0!r} at "
                         f"theta1 = {theta1!r} (outside its stability interval)")
    k = sign[0]
    return brent_root(lambda x: theta0_of_nu(x, theta1, order)[0] - theta0, grid[k], grid[k + 1],
                  xtol=1e-15, rtol=1e-15)


def series_solution(tau, theta_init, omega_init, theta0, theta1, order):
    """theta(tau) = A theta_c + B theta_s (000 eq. 23) at ``order`` with A, B from the initial conditions.

    theta_c(0) and theta_s'(0) come from the series' own functions
    (theta_c'(0) = theta_s(0) = 0 since theta_c has only cosines and theta_s only sines):
    A = theta(0)/theta_c(0), B = theta'(0)/theta_s'(0).  Returns (theta (len(tau),), nu, estimate).
    """
    import mpmath
    import numpy as np

    from pendulab.analyses.series import theta_c, theta_s

    nu = series_nu(theta0, theta1, order)
    c0 = float(theta_c(0.0, nu, theta1, order)[0])
    with mpmath.workdps(30):
        ds0 = float(mpmath.diff(lambda t: theta_s(t, mpmath.mpf(nu), mpmath.mpf(theta1), order, dps=30)[0], 0))
    A, B = theta_init / c0, omega_init / ds0
    tc, ec = theta_c(np.asarray(tau, float), nu, theta1, order)
    ts, es = theta_s(np.asarray(tau, float), nu, theta1, order)
    return A * np.asarray(tc) + B * np.asarray(ts), nu, float(np.max(abs(A) * ec + abs(B) * es))


def fig5(system=None, a_over_l=0.2, w0_over_w=0.05, theta_init=0.06, omega_init=0.01, periods=40,
         steps_per_period=100, orders=(2, 8), backend="auto"):
    """Fig. 5: RK4 theta(tau) (full equation and linearised) against the series at each order.

    Returns {"tau", "theta" (nonlinear RK4), "theta_linear", "series": {order:
    theta}, "nu": {order: nu, "floquet": exact exponent}, "error": {order:
    max |series - RK4 nonlinear|}, "error_linear": {order: max |series - RK4
    linear|}, "theta0", "theta1", "rk4_error", "rk4_error_linear" (max |RK4 -
    DOP853 at rtol 1e-13| of theta, the integrator's own error)}.
    """
    import numpy as np

    from pendulab.analyses.floquet import exponent

    system = system or S.SystemSpec()
    spec = S.make_spec(system, a_over_l=[a_over_l], w0_over_w=[w0_over_w], theta_init=theta_init,
                       omega_init=omega_init, periods=periods, steps_per_period=steps_per_period)
    run = S.trajectory(spec, reference=True, backend=backend)
    lin = S.trajectory(S.replace(spec, linear=True), reference=True, backend=backend)
    t0, t1 = (float(v) for v in S.mathieu_pair(system)(a_over_l, w0_over_w))
    tau = run["tau"]
    out = {"tau": tau, "theta": run["states"][:, 0], "theta_linear": lin["states"][:, 0],
           "series": {}, "nu": {"floquet": float(exponent(t0, t1).real)}, "error": {},
           "error_linear": {}, "estimate": {}, "theta0": t0, "theta1": t1,
           "rk4_error": run["max_error_theta"], "rk4_error_linear": lin["max_error_theta"]}
    for n in orders:
        th, nu, est = series_solution(tau, theta_init, omega_init, t0, t1, n)
        out["series"][n] = th
        out["nu"][n] = nu
        out["estimate"][n] = est
        out["error"][n] = float(np.max(np.abs(th - out["theta"])))
        out["error_linear"][n] = float(np.max(np.abs(th - out["theta_linear"])))
    return out


# ---------------------------------------------------------------------------
# Fig. 2: fast and slow motion of Mathieu's equation
# ---------------------------------------------------------------------------

def groups_of(system, theta0, theta1):
    """(a/l, omega0/omega) with the given (theta0, theta1), solving the derived 000 eqs. 5-6."""
    import sympy as sp

    from pendulab import symbols as Sym
    from pendulab.numerics.model import mathieu_parameters

    eqs, form = S._stages(system)
    p0, p1 = mathieu_parameters(eqs, form)
    if system.inertia_ratio is not None:
        p0, p1 = (v.subs(Sym.inertia_ratio, sp.nsimplify(system.inertia_ratio)) for v in (p0, p1))
    sols = sp.solve([p0 - sp.nsimplify(theta0), p1 - sp.nsimplify(theta1)],
                    [Sym.a_over_l, Sym.w0_over_w], dict=True)
    for s in sols:
        a, w = s.get(Sym.a_over_l), s.get(Sym.w0_over_w)
        if a is not None and w is not None and a.is_real and w.is_real and a >= 0 and w >= 0:
            return float(a), float(w)
    raise InputError(f"no a/l >= 0, omega0/omega >= 0 gives theta0 = {theta0}, theta1 = {theta1}")


def pivot_height(system):
    """f(tau) = y0(t)/a at t = 2 tau/Omega, from the scene's drive (000 eq. 1)."""
    import sympy as sp

    from pendulab import symbols as Sym

    eqs, form = S._stages(system)
    freq = form.frequency if form.frequency is not None else Sym.omega
    expr = sp.simplify((eqs.system.drive / Sym.a).subs(Sym.t, 2 * Sym.tau / freq))
    if expr.free_symbols - {Sym.tau}:
        raise InputError(f"the pivot height y0/a = {expr} depends on more than tau")
    return sp.lambdify(Sym.tau, expr, "numpy")


def fig2(system=None, theta0=-2e-3, theta1=0.2, theta_init=0.1, omega_init=0.0, periods=40,
         steps_per_period=100, backend="auto"):
    """Fig. 2: RK4 on Mathieu's equation (000 eq. 7), the slow part and the pivot.

    The slow part is the running mean of theta over one drive period (the
    average that separates the slow motion from the fast one, 000 sec. 2.3);
    ``pivot`` is y0/a from the drive.  Returns {"tau", "theta", "slow",
    "pivot", "a_over_l", "w0_over_w", "nu" (exact exponent: slow angular
    frequency in tau), "rk4_error" (max |RK4 - DOP853| of theta)}.
    """
    import numpy as np

    from pendulab.analyses.floquet import exponent

    system = system or S.SystemSpec()
    a, w = groups_of(system, theta0, theta1)
    spec = S.make_spec(system, a_over_l=[a], w0_over_w=[w], theta_init=theta_init,
                       omega_init=omega_init, periods=periods, steps_per_period=steps_per_period,
                       linear=True)
    run = S.trajectory(spec, reference=True, backend=backend)
    theta = run["states"][:, 0]
    k = steps_per_period
    kernel = np.ones(k + 1)
    kernel[0] = kernel[-1] = 0.5  # trapezoid over exactly one period
    slow = np.convolve(theta, kernel / k, mode="same")
    half = k // 2
    slow[:half] = np.nan
    slow[len(slow) - half:] = np.nan
    return {"tau": run["tau"], "theta": theta, "slow": slow, "pivot": pivot_height(system)(run["tau"]),
            "a_over_l": a, "w0_over_w": w, "theta0": theta0, "theta1": theta1,
            "nu": float(exponent(theta0, theta1).real), "rk4_error": run["max_error_theta"]}
