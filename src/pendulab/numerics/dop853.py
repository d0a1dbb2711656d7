"""DOP853 for two-component systems with scalar floats: SciPy's method, without its Python overhead.

SciPy's ``solve_ivp(method="DOP853")`` runs its step loop in Python on small NumPy
arrays (a dozen array operations per stage); for the two-component states of the
pendulums that overhead, not the right-hand side, is most of the time.  This module
runs the same method - the Dormand-Prince 8(5,3) pair with Hairer's 7th-order dense
output, the coefficient tables read from ``scipy.integrate._ivp.dop853_coefficients``
(not re-typed) - with the same step-size control as SciPy's ``DOP853`` class (initial
step of ``select_initial_step``, safety 0.9, factors in [0.2, 10], the combined 5th/3rd
order error norm, no growth right after a rejection) on plain Python floats: the step
is straight-line code generated from the tables (:func:`step_source`).  The answers
agree with SciPy's to rounding (the sums run in another order), so the step sequence
is the same except where an error norm sits within rounding of 1.

Pure Python: the result does not depend on a compiler being present.

* :func:`solve` - states at monotonic output times, with optional events (sign
  changes of g(t, y) located on the dense output by Brent's method, as SciPy does).
"""

import math

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ORDER = 7  # the error estimator's order (step ~ error ** (1/8))


class TooManyEvaluations(Exception):
    """More than ``max_evaluations`` calls of the right-hand side."""


class NotFinite(Exception):
    """The right-hand side or the state stopped being finite."""


class StepTooSmall(Exception):
    """The step fell below 10 spacings of the floats at t (solve_ivp's failure)."""

    def __str__(self):
        return "Required step size is less than spacing between numbers."


_TABLES = "scipy.integrate._ivp.dop853_coefficients"


def _tables():
    """SciPy's module of DOP853 coefficients, read without importing ``scipy.integrate``.

    The module itself needs only NumPy; importing it by name would first run
    ``scipy.integrate``'s package initialisation, which imports scipy.optimize,
    scipy.special and the quadrature code (about 0.3 s that a build would pay
    in every process).  So it is loaded from its file, found through SciPy's
    own package location, under its own name; where that file is not where
    this SciPy keeps it, the ordinary import is used.
    """
    import importlib
    import importlib.util
    import os
    import sys
    loaded = sys.modules.get(_TABLES) or sys.modules.get("_pendulab_" + _TABLES)
    if loaded is not None:
        return loaded
    spec = importlib.util.find_spec("scipy")
    roots = (spec.submodule_search_locations or []) if spec is not None else []
    for root in roots:
        path = os.path.join(root, "integrate", "_ivp", "dop853_coefficients.py")
        if not os.path.isfile(path):
            continue
        try:
            mspec = importlib.util.spec_from_file_location("_pendulab_" + _TABLES, path)
            module = importlib.util.module_from_spec(mspec)
            mspec.loader.exec_module(module)
        except Exception:  # a SciPy whose file needs its package after all
            break
        sys.modules["_pendulab_" + _TABLES] = module
        return module
    return importlib.import_module(_TABLES)


def _lit(x):
    return repr(float(x))


def _combo(terms, comp):
    """'c1*k1a + c2*k2a' text of the nonzero terms (comp 'a' or 'b')."""
    return " + ".join(f"{_lit(c)}*k{j}{comp}" for j, c in terms if c != 0.0) or "0.0"


def step_source():
    """Python text of ``step(f, t, h, ya, yb, k0a, k0b)`` and ``extra(...)`` from SciPy's tables.

    ``step`` returns (yn_a, yn_b, f_new_a, f_new_b, e5_a, e5_b, e3_a, e3_b, stages) with
    e5, e3 the dot products of the stages with E5 and E3 (times 1, not h) and stages the
    13 (k_a, k_b); ``extra(f, t, h, ya, yb, stages)`` the three extra stages of the dense
    output, and ``dense_F`` the 7 interpolation coefficients of each component.
    """
    D = _tables()
    n = D.N_STAGES
    A, B, C, E3, E5, DD = D.A, D.B, D.C, D.E3, D.E5, D.D
    lines = ["def step(f, t, h, ya, yb, k0a, k0b):"]
    for s in range(1, n):
        terms = [(j, A[s, j]) for j in range(s)]
        lines.append(f"    k{s}a, k{s}b = f(t + {_lit(C[s])}*h, ya + h*({_combo(terms, 'a')}), "
                     f"yb + h*({_combo(terms, 'b')}))")
    bt = [(j, B[j]) for j in range(n)]
    lines.append(f"    yna = ya + h*({_combo(bt, 'a')})")
    lines.append(f"    ynb = yb + h*({_combo(bt, 'b')})")
    lines.append(f"    k{n}a, k{n}b = f(t + h, yna, ynb)")
    e5 = [(j, E5[j]) for j in range(n + 1)]
    e3 = [(j, E3[j]) for j in range(n + 1)]
    ks = ", ".join(f"(k{j}a, k{j}b)" for j in range(n + 1))
    lines.append(f"    return (yna, ynb, k{n}a, k{n}b, {_combo(e5, 'a')}, {_combo(e5, 'b')}, "
                 f"{_combo(e3, 'a')}, {_combo(e3, 'b')}, ({ks},))")
    lines.append("")
    lines.append("def extra(f, t, h, ya, yb, ks):")
    lines.append(f"    ({', '.join(f'(k{j}a, k{j}b)' for j in range(n + 1))},) = ks")
    for s in range(n + 1, D.N_STAGES_EXTENDED):
        terms = [(j, A[s, j]) for j in range(s)]
        lines.append(f"    k{s}a, k{s}b = f(t + {_lit(C[s])}*h, ya + h*({_combo(terms, 'a')}), "
                     f"yb + h*({_combo(terms, 'b')}))")
    lines.append("    Fa, Fb = [], []")
    for i in range(DD.shape[0]):
        terms = [(j, DD[i, j]) for j in range(D.N_STAGES_EXTENDED)]
        lines.append(f"    Fa.append(h*({_combo(terms, 'a')}))")
        lines.append(f"    Fb.append(h*({_combo(terms, 'b')}))")
    lines.append("    return Fa, Fb")
    return "\n".join(lines) + "\n"


_NS = {}


def _compiled():
    if not _NS:
        ns = {}
        exec(compile(step_source(), "<generated DOP853 step>", "exec"), ns)
        _NS.update(ns)
    return _NS["step"], _NS["extra"]


class _Step:
    """One accepted step's dense output (SciPy's Dop853DenseOutput, in scalars)."""

    __slots__ = ("t_old", "h", "ya", "yb", "Fa", "Fb")

    def __init__(self, t_old, h, ya, yb, Fa, Fb):
        self.t_old, self.h, self.ya, self.yb, self.Fa, self.Fb = t_old, h, ya, yb, Fa, Fb

    def __call__(self, t):
        x = (t - self.t_old) / self.h
        ya = yb = 0.0
        for i, (fa, fb) in enumerate(zip(reversed(self.Fa), reversed(self.Fb))):
            ya += fa
            yb += fb
            m = x if i % 2 == 0 else 1.0 - x
            ya *= m
            yb *= m
        return ya + self.ya, yb + self.yb


def _dense(f, t, h, ya, yb, yna, ynb, ks, extra):
    """The dense output of the step t -> t + h (three more evaluations)."""
    Fa3, Fb3 = extra(f, t, h, ya, yb, ks)
    k0a, k0b = ks[0]
    fna, fnb = ks[-1]
    da, db = yna - ya, ynb - yb
    Fa = [da, h*k0a - da, 2*da - h*(fna + k0a)] + Fa3
    Fb = [db, h*k0b - db, 2*db - h*(fnb + k0b)] + Fb3
    return _Step(t, h, ya, yb, Fa, Fb)


def _brent(g, a, b):
    """solve_ivp's solve_event_equation: Brent's method to 4 machine epsilons."""
    from pendulab.numerics.roots import EPS, brent_root
    return brent_root(g, a, b, xtol=4 * EPS, rtol=4 * EPS)


def solve(fun, t_eval, y0, rtol, atol, *, t_span=None, max_evaluations=None, events=()):
    """Integrate y' = fun(t, a, b) -> (a', b') over ``t_span`` with y0 = (a, b); states at t_eval.

    ``t_eval`` strictly monotonic (a list of floats) inside ``t_span`` (default
    (t_eval[0], t_eval[-1])); ``atol`` a float or a pair.  ``events``: functions g(t, a, b) with attributes ``terminal`` and ``direction``
    as in solve_ivp.  Returns (times, states_a, states_b, events, nfev, stopped) with
    ``events`` a list of (times, states) per event function; ``stopped`` True when a
    terminal event ended the run (the outputs then stop at its time).  Raises
    :class:`TooManyEvaluations` past ``max_evaluations`` calls, :class:`NotFinite`
    when a state or a derivative is not finite, :class:`StepTooSmall` when the step
    falls below 10 spacings of the floats.
    """
    try:
        return _solve(fun, t_eval, y0, rtol, atol, t_span, max_evaluations, events)
    except OverflowError:  # float ** overflows raise instead of giving inf
        raise NotFinite from None


def _solve(fun, t_eval, y0, rtol, atol, t_span, max_evaluations, events):
    step, extra = _compiled()
    t0, t_end = (float(t_eval[0]), float(t_eval[-1])) if t_span is None else map(float, t_span)
    direction = 1.0 if t_end > t0 else -1.0
    ata, atb = (atol, atol) if not hasattr(atol, "__len__") else (float(atol[0]), float(atol[1]))
    count = [0]
    limit = math.inf if max_evaluations is None else max_evaluations
    isfinite = math.isfinite

    def f(t, a, b):
        count[0] += 1
        if count[0] > limit:
            raise TooManyEvaluations
        try:
            da, db = fun(t, a, b)
        except (OverflowError, ValueError, ZeroDivisionError):
            raise NotFinite from None
        return da, db

    ya, yb = float(y0[0]), float(y0[1])
    fa, fb = f(t0, ya, yb)
    # SciPy's select_initial_step (RMS norms)
    sa, sb = ata + abs(ya) * rtol, atb + abs(yb) * rtol
    d0 = math.sqrt(((ya / sa) ** 2 + (yb / sb) ** 2) / 2)
    d1 = math.sqrt(((fa / sa) ** 2 + (fb / sb) ** 2) / 2)
    interval = abs(t_end - t0)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    f1a, f1b = f(t0 + h0 * direction, ya + h0 * direction * fa, yb + h0 * direction * fb)
    d2 = math.sqrt((((f1a - fa) / sa) ** 2 + ((f1b - fb) / sb) ** 2) / 2) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1 / (ORDER + 1))
    h_abs = min(100 * h0, h1, interval)

    out_t, out_a, out_b = [], [], []
    n_out = len(t_eval)
    j = 0
    while j < n_out and direction * (t_eval[j] - t0) <= 0:  # solve_ivp: t0 itself, not before
        if t_eval[j] == t0:
            out_t.append(t0)
            out_a.append(ya)
            out_b.append(yb)
        j += 1
    g_old = [g(t0, ya, yb) for g in events]
    found = [([], []) for _ in events]
    t = t0
    exponent = -1.0 / (ORDER + 1)
    stopped = False
    while direction * (t - t_end) < 0:
        min_step = 10 * abs(math.nextafter(t, direction * math.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                raise StepTooSmall
            h = h_abs * direction
            t_new = t + h
            if direction * (t_new - t_end) > 0:
                t_new = t_end
            h = t_new - t
            h_abs = abs(h)
            yna, ynb, fna, fnb, e5a, e5b, e3a, e3b, ks = step(f, t, h, ya, yb, fa, fb)
            sa = ata + max(abs(ya), abs(yna)) * rtol
            sb = atb + max(abs(yb), abs(ynb)) * rtol
            e5 = (e5a / sa) ** 2 + (e5b / sb) ** 2
            e3 = (e3a / sa) ** 2 + (e3b / sb) ** 2
            if e5 == 0 and e3 == 0:
                err = 0.0
            else:
                err = h_abs * e5 / math.sqrt((e5 + 0.01 * e3) * 2)
            if not isfinite(err):
                raise NotFinite
            if err < 1:
                factor = MAX_FACTOR if err == 0 else min(MAX_FACTOR, SAFETY * err ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(MIN_FACTOR, SAFETY * err ** exponent)
            rejected = True
        if not (isfinite(yna) and isfinite(ynb)):
            raise NotFinite
        dense = None
        t_stop = t_new
        if events:
            g_new = [g(t_new, yna, ynb) for g in events]
            hits = []
            for i, g in enumerate(events):
                up = g_old[i] <= 0 and g_new[i] >= 0  # solve_ivp's find_active_events
                dn = g_old[i] >= 0 and g_new[i] <= 0
                d = getattr(g, "direction", 0)
                if (up and d >= 0) or (dn and d <= 0):
                    hits.append(i)
            if hits:
                dense = _dense(f, t, h, ya, yb, yna, ynb, ks, extra)
                roots = []
                for i in hits:
                    g = events[i]
                    te = _brent(lambda s, g=g: g(s, *dense(s)), t, t_new)
                    roots.append((te, i))
                roots.sort(key=lambda r: direction * r[0])
                for te, i in roots:
                    found[i][0].append(te)
                    found[i][1].append(dense(te))
                    if getattr(events[i], "terminal", False):
                        stopped = True
                        t_stop = te
                        break
            g_old = g_new
        # outputs in (t, t_stop]
        while j < n_out and direction * (t_eval[j] - t_stop) <= 0:
            if dense is None:
                dense = _dense(f, t, h, ya, yb, yna, ynb, ks, extra)
            te = t_eval[j]
            if te == t_new:
                out_a.append(yna)
                out_b.append(ynb)
            else:
                a, b = dense(te)
                out_a.append(a)
                out_b.append(b)
            out_t.append(te)
            j += 1
        if stopped:
            break
        t, ya, yb, fa, fb = t_new, yna, ynb, fna, fnb
    return out_t, out_a, out_b, found, count[0], stopped

