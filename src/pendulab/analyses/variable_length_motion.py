"""The variable-length pendulum in motion: integration against the closed form (002).

Everything numeric here is read from the derivation: the right-hand side is
the numerics stage's first-order system (:func:`pendulab.numerics.model.length_system`,
002 eq. 3 nonlinear and 002 eq. 4 linear, in the time t with the scene's
L(t) written out), the reference is the pipeline's ``closed_form`` stage
(:class:`pendulab.analyses.bessel.BesselSolution`: theta = A z^-1 J1(z) + B z^-1 Y1(z),
z = (2/v0) sqrt(g L), A and B from theta(0) = theta_0, theta'(0) = 0), and the
amplitude law's exponent is derived from the system's potential energy and the
linear equation (:func:`amplitude_exponent`).  No equation of the source is
typed here.

Public API (all arguments are SymPy objects of the stages plus plain numbers):

* :func:`integrate` - theta(t) by SciPy's DOP853 (rtol 1e-13 by default),
  linear or nonlinear; refuses (:class:`LengthReachesZeroError`) a t_end at
  or beyond the first zero of L(t).
* :func:`length_zero_time` - that first zero, from the length expression.
* :func:`closed_form_theta` - the closed form at given times (mpmath).
* :func:`relative_agreement` - max |numeric - reference| / max |reference|.
* :func:`b_zero_length` - the L0 that puts z0 at a zero of J2 (then B = 0).
* :func:`amplitude_exponent` - d log(amplitude) / d log L from E/omega = const.
* :func:`turning_points`, :func:`fit_exponent` - the fitted exponent of the
  successive peak amplitudes against L.
* :func:`quarter_periods` - the measured swings between theta = 0 and theta' = 0,
  :func:`zero_quarter_periods` - the same from the zeros of J1 and J2.
* :func:`substitute`, :func:`length_function` - numbers into an expression / L(t).
* :func:`periodic_verdict` - the Floquet verdict of a periodic L(t) from the
  monodromy matrix of the linear equation (:mod:`pendulab.numerics.monodromy`),
  :func:`verdict_word` - "stable", "unstable" or "boundary" for it.

The integrators call the scalar right-hand side printed by the code
generation stage (:func:`pendulab.numerics.codegen.scalar_function`, from
``fos.rhs`` / ``fos.linear_rhs``; :func:`_rhs`); the Floquet verdict is
:func:`pendulab.numerics.monodromy.floquet_verdict`; the zeros of J1 and J2
are the certified ones of :mod:`pendulab.analyses.bessel_zeros`.
"""

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from sympy.core.evalf import PrecisionExhausted

from pendulab import symbols as S
from pendulab.errors import ConvergenceError, InputError

#: default tolerances of the adaptive integrator (DOP853)
RTOL = 1e-13


class LengthReachesZeroError(InputError):
    """The string's length reaches 0 inside the requested time span.

    ``time`` is the first t > 0 with L(t) = 0 (or where L fell below the
    floor of the integrator's event), in the scene's time unit.
    """

    def __init__(self, message, time):
        self.time = float(time)
        super().__init__(message)


@dataclass(frozen=True)
class Trajectory:
    """theta(t) on a time grid, from :func:`integrate`.

    ``t``, ``theta``, ``dtheta`` are 1-d arrays of equal length (dtheta = d theta/dt);
    ``values`` maps parameter names to the floats used; ``linear`` says which
    right-hand side (002 eq. 4 or eq. 3) ran; ``turning`` holds the
    (t, theta) of every dtheta = 0 event (two 1-d arrays), ``crossings`` the
    t of every theta = 0 event; ``nfev`` counts right-hand-side calls.
    """

    t: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    values: dict
    linear: bool
    turning: tuple = field(default=(np.empty(0), np.empty(0)))
    crossings: np.ndarray = field(default_factory=lambda: np.empty(0))
    nfev: int = 0


# ---------------------------------------------------------------------------
# numbers for the parameters
# ---------------------------------------------------------------------------

def _finite(name, value):
    if isinstance(value, bool):
        raise InputError(f"{name}: must be a number, got {value!r}")
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number, got {value!r}") from None
    if not math.isfinite(out):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    return out


def _param_values(symbols, values, what):
    """Floats for ``symbols`` (in their order) from ``values`` {name: number}; all needed."""
    missing = [s.name for s in symbols if s.name not in values]
    if missing:
        raise InputError(f"{what} needs numbers for {', '.join(missing)}")
    return tuple(_finite(s.name, values[s.name]) for s in symbols)


def substitute(expr, values):
    """``expr`` with every free symbol named in ``values`` {name: number} replaced by its float.

    Symbols are matched by name, so a scene's ``eps`` (a real symbol from
    :func:`pendulab.exprs.parse`) and a positive ``eps`` are both replaced.
    """
    expr = sp.sympify(expr)
    sub = {s: sp.Float(_finite(s.name, values[s.name]), 17) for s in expr.free_symbols
           if s.name in values}
    return expr.subs(sub)


#: length_function's results by (L(t), the numbers of its symbols): a product asks for the
#: same L(t) about ten times (each integration, its zero, the fits), each lambdify costs ms
_LENGTH_FUNCTIONS = {}


def length_function(length, values):
    """(L(t) as a float function of t, the numeric SymPy expression) with ``values`` substituted."""
    length = sp.sympify(length)
    key = (length, repr(sorted((s.name, values[s.name]) for s in length.free_symbols
                               if s.name in values)))
    if key not in _LENGTH_FUNCTIONS:
        expr = substitute(length, values)
        rest = expr.free_symbols - {S.t}
        if rest:
            raise InputError(f"L(t) = {length} needs numbers for {', '.join(sorted(s.name for s in rest))}")
        if len(_LENGTH_FUNCTIONS) >= 64:
            _LENGTH_FUNCTIONS.pop(next(iter(_LENGTH_FUNCTIONS)))
        _LENGTH_FUNCTIONS[key] = (sp.lambdify(S.t, expr, "math"), expr)
    return _LENGTH_FUNCTIONS[key]


def _safe(fn):
    """``fn`` returning NaN where L is not a real number (math's domain errors: sqrt(1 - t)
    past t = 1) or overflows."""
    def value(x):
        try:
            return float(fn(x))
        except (ValueError, OverflowError, ZeroDivisionError, TypeError):
            return math.nan
    return value


def _positive(expr, x, v):
    """Whether L(x) > 0, from its float ``v``; a float 0.0 (or one below the smallest normal
    double) is decided again from the expression at 30 digits, where exp(-745.4) is not 0:
    underflow is not a zero.

    Strict: only a real number that evalf computes to its 30 digits (``strict=True``) and
    that is > 0 counts as positive.  An exact zero (1 - t at t = 1, which plain evalf
    returns as a digitless 0.e-165 that compares > 0), a value evalf cannot tell from 0, a
    pole, a complex value or an expression left with a symbol is refused (False)."""
    if v > 2.3e-308 or v < 0 or v != v:
        return v > 0
    try:
        exact = sp.sympify(expr).evalf(30, subs={S.t: sp.Float(repr(float(x)), 30)}, strict=True)
    except (PrecisionExhausted, ValueError, TypeError, ZeroDivisionError, ArithmeticError):
        return False
    if not (exact.is_Number and exact.is_extended_real and exact.is_finite):
        return False
    return bool(exact > 0)


#: samples of (0, horizon] scanned by :func:`length_zero_time` and :func:`length_floor_time`
SCAN_POINTS = 4096


def _scan(length, values, horizon):
    """The first sample of (0, ``horizon``] where L is not positive: (t_prev, t, value at t)
    with L(t_prev) > 0, or None; L at t = 0 must be positive."""
    fn, expr = length_function(length, values)
    fn = _safe(fn)
    grid = np.linspace(0.0, float(horizon), SCAN_POINTS + 1)
    for j in range(1, grid.size):
        v = fn(grid[j])
        if not _positive(expr, grid[j], v):
            return fn, expr, grid[j - 1], grid[j], v
    return None


def _first_positive_root(poly):
    """The least real root t > 0 of the polynomial ``poly`` in t (a float), or None.

    Decided exactly where the coefficients are numbers: each Float is its exact binary
    value, and SymPy's real_roots (isolating intervals, Sturm/Vincent) finds every real root
    with its multiplicity, so a double root (a length that touches 0: 5 (t - 7/3)^2) is not
    lost as a pair of complex roots with an imaginary part of 1e-8.  Other coefficients
    (irrational constants such as pi) go to numpy.roots, on the square-free part of the
    polynomial (its roots are simple, so their imaginary parts are a rounding away from 0),
    with a 1e-12 test on the imaginary parts.
    """
    coeffs = poly.all_coeffs()
    if all(c.is_Rational or c.is_Float for c in coeffs):
        exact = sp.Poly([sp.Rational(c) for c in coeffs], S.t)
        positive = [r for r in exact.real_roots() if r.is_positive]
        return float(positive[0].evalf(30)) if positive else None
    coeffs = sp.Poly(sp.sqf_part(poly.as_expr()), S.t).all_coeffs()
    roots = [complex(r) for r in np.roots([complex(c) for c in coeffs])]
    positive = sorted(r.real for r in roots if abs(r.imag) <= 1e-12 * max(1, abs(r)) and r.real > 0)
    return positive[0] if positive else None


def _length_event(length, values, horizon):
    """(kind, t) of the first t in (0, ``horizon``] where L(t) stops being a positive real:
    kind "zero" (a sign change through 0, or a zero of the expression), "singular" (a sign
    change through a pole, 1 + tan(t) at pi/2, or L not real past t) - or None.
    Exact (real roots) for a polynomial L(t), whatever the horizon."""
    fn, expr = length_function(length, values)
    if expr.is_polynomial(S.t):
        poly = sp.Poly(expr, S.t)
        if poly.degree() < 1:
            return None
        first = _first_positive_root(poly)
        return ("zero", first) if first is not None else None
    if horizon is None:
        return None
    from pendulab.numerics.roots import brent_root
    found = _scan(length, values, horizon)
    if found is None:
        return None
    fn, expr, lo, hi, v = found
    scale = abs(fn(0.0))
    if v == v and v <= 0:  # a change of sign (or an exact zero): a zero, or a pole between
        root = hi if v == 0 else brent_root(fn, lo, hi, xtol=1e-14, rtol=1e-15)
        near = fn(root)
        if abs(near) <= 1e-6 * scale or min(abs(fn(lo)), abs(fn(hi))) <= 1e-3 * scale:
            return "zero", root
        return "singular", root
    # L is not a real number at hi (a domain error, a complex value): bisect for the edge
    for _ in range(200):
        mid = (lo + hi) / 2
        if not lo < mid < hi:
            break
        if _positive(expr, mid, fn(mid)):
            lo = mid
        else:
            hi = mid
    return ("zero" if abs(fn(lo)) <= 1e-6 * scale else "singular"), hi


def length_zero_time(length, values, horizon=None):
    """The first t > 0 with L(t) = 0 (a float), or None if L stays positive.

    Exact for a polynomial L(t) (real roots of the polynomial); for any other
    length the interval (0, ``horizon``] is scanned on 4096 points and the
    first sign change refined by Brent's method (pendulab.numerics.roots), so a
    zero the scan steps over is left to the integrator's event.  A sample is
    "not positive" only by the sign of L: a float that underflowed to 0
    (exp(-k t) past k t = 745) is evaluated again at 30 digits, where it is
    positive; and a sign change through a pole (1 + tan(t) at pi/2) is not a
    zero (:func:`length_check` names it).
    """
    found = _length_event(length, values, horizon)
    return found[1] if found is not None and found[0] == "zero" else None


def length_floor_time(length, values, horizon, floor=None):
    """The first t in (0, ``horizon``] with L(t) <= ``floor`` L(0) (default
    :data:`LENGTH_FLOOR`), a float, or None.

    The interval is scanned on 4096 points; besides the first sample below
    the floor, the dips of L between samples (a strict local minimum of the
    samples below 1e-3 L(0): 1 + sin(t) touching 0) are refined by Brent's
    minimiser, so a length that only touches the floor between samples is found.
    """
    from pendulab.numerics.roots import brent_minimum, brent_root
    floor = LENGTH_FLOOR if floor is None else floor
    fn, _ = length_function(length, values)
    fn = _safe(fn)
    l0 = fn(0.0)
    level = floor * l0
    grid = np.linspace(0.0, float(horizon), SCAN_POINTS + 1)
    vals = np.array([fn(x) for x in grid])
    low = ~(vals > level)
    low[0] = False
    first = int(np.argmax(low)) if low.any() else None
    dips = np.nonzero((vals[1:-1] < vals[:-2]) & (vals[1:-1] <= vals[2:])
                      & (vals[1:-1] < 1e-3 * l0))[0] + 1
    for j in dips[:64]:
        if first is not None and j >= first:
            break
        x, fx = brent_minimum(fn, grid[j - 1], grid[j + 1], xatol=1e-12 * max(1.0, grid[j]))
        if fx <= level:
            return brent_root(lambda u: fn(u) - level, grid[j - 1], x, xtol=1e-14, rtol=1e-15)
    if first is None:
        return None
    g = lambda u: fn(u) - level if fn(u) == fn(u) else -1.0  # noqa: E731 (NaN: below)
    return brent_root(g, grid[first - 1], grid[first], xtol=1e-14, rtol=1e-15)


def length_check(length, values, horizon, *, t_end, why=""):
    """Refuse, before anything is integrated, a length that reaches 0, passes a pole or
    falls to :data:`LENGTH_FLOOR` L(0) in (0, ``horizon``] (``horizon`` >= ``t_end``:
    the Floquet verdict of a periodic L(t) integrates one whole period).

    Raises :class:`LengthReachesZeroError` (one line, with the time) or returns
    the first zero of L(t) (a float, possibly beyond ``horizon`` for a
    polynomial) or None.  ``why`` is added to the message when the time lies
    beyond ``t_end`` (what integrates up to ``horizon``).
    """
    used = {k: values[k] for k in sorted(values)}
    found = _length_event(length, values, horizon)

    def tail(when, where=", where the equation divides by L"):
        if when <= t_end:
            return (f"t_end = {t_end:.12g} lies at or beyond it{where}: "
                    f"integrate to t_end < {when:.12g}")
        return f"t_end = {t_end:.12g} is before it, but {why}"

    if found is not None and found[1] <= horizon:
        kind, when = found
        if kind == "zero":
            text = f"L(t) = {length} reaches 0 at t = {when:.12g} (values {used}); " + tail(when)
        else:
            text = (f"L(t) = {length} is not a finite positive length at t = {when:.12g} (a pole, "
                    f"or the end of its real values; values {used}); "
                    + tail(when, ", where L is not finite"))
        raise LengthReachesZeroError(text, when)
    short = length_floor_time(length, values, horizon)
    if short is not None:
        raise LengthReachesZeroError(
            f"L(t) = {length} falls to {LENGTH_FLOOR:g} L(0) at t = {short:.12g} (values {used}): "
            f"too short, relative to L(0), for the integration to go "
            f"on; " + tail(short, ""), short)
    return None if found is None else found[1]


# ---------------------------------------------------------------------------
# the right-hand side (switch here to the generated kernels)
# ---------------------------------------------------------------------------

def _rhs(fos, linear):
    """f(t, y, p) -> [dtheta, theta''] of the derivation, scalar floats.

    The code generation stage's scalar function
    (:func:`pendulab.numerics.codegen.scalar_function`: ``fos.rhs`` /
    ``fos.linear_rhs`` lowered by cse and printed with ``math`` functions), not
    the vectorised NumPy module, which costs about 40 times more per call of
    ``solve_ivp`` (measured: 7.5 us against 0.2 us per call).
    """
    from pendulab.numerics.codegen import scalar_function
    return scalar_function(fos, linear)


# ---------------------------------------------------------------------------
# integration
# ---------------------------------------------------------------------------

#: the event of :func:`integrate` fires when L(t) falls below this fraction of L(0)
LENGTH_FLOOR = 1e-6


def integrate(fos, length, values, t_end, theta_0, *, dtheta_0=0.0, linear=False,
              rtol=RTOL, atol=None, points=2001, t_eval=None):
    """Integrate the variable-length pendulum from t = 0 to ``t_end`` (DOP853).

    ``fos`` is the numerics stage's system (:func:`pendulab.numerics.model.length_system`;
    state (theta, dtheta), rhs 002 eq. 3, linear_rhs 002 eq. 4), ``length``
    the scene's L(t) (a SymPy expression in t), ``values`` {name: number}
    for every parameter of ``fos.params`` and of ``length`` (e.g. ``{"g": 9.81,
    "L0": 1, "v0": 0.01}``).  Initial state theta(0) = ``theta_0``,
    theta'(0) = ``dtheta_0`` (002 takes 0).  Output on ``points`` equally
    spaced times (or on ``t_eval``), plus every turning point (dtheta = 0).

    Raises :class:`LengthReachesZeroError` when L(t) reaches 0 at or before
    ``t_end``: found from the length expression before integrating, and by a
    terminal event L(t) = LENGTH_FLOOR L(0) for lengths whose zero is not
    found in advance.  Never returns NaN (a non-finite state raises
    :class:`~pendulab.errors.ConvergenceError`).
    """
    from pendulab.numerics import dop853

    t_end = _finite("t_end", t_end)
    if t_end <= 0:
        raise InputError(f"t_end: must be positive, got {t_end!r}")
    theta_0 = _finite("theta_0", theta_0)
    dtheta_0 = _finite("dtheta_0", dtheta_0)
    if not 0 < rtol < 1:
        raise InputError(f"rtol: must lie in (0, 1), got {rtol!r}")
    p = _param_values(fos.params, values, "the equation of motion")
    used = {s.name: v for s, v in zip(fos.params, p)}
    lfun, lexpr = length_function(length, values)
    l0 = lfun(0.0)
    if not l0 > 0:
        raise InputError(f"L(0) = {l0!r} with these values: the length must be positive at t = 0")
    t_zero = length_zero_time(length, values, horizon=t_end)
    if t_zero is not None and t_zero <= t_end:
        raise LengthReachesZeroError(
            f"L(t) = {length} reaches 0 at t = {t_zero:.12g} (values {used}); t_end = {t_end:.12g} "
            f"lies at or beyond it, where the equation divides by L: integrate to t_end < {t_zero:.12g}",
            t_zero)
    f = _rhs(fos, linear)

    def rhs(t, a, b):
        return f(t, (a, b), p)

    floor = LENGTH_FLOOR * l0

    def short(t, a, b):
        return lfun(t) - floor
    short.terminal = True
    short.direction = -1

    def turning(t, a, b):
        return b
    turning.direction = 0

    def crossing(t, a, b):
        return a
    crossing.direction = 0

    if atol is None:
        atol = rtol * 1e-3 * max(abs(theta_0), abs(dtheta_0), 1e-300)
    if t_eval is None:
        t_eval = np.linspace(0.0, t_end, int(points))
    t_eval = np.asarray(t_eval, dtype=float)
    if (t_eval.ndim != 1 or not np.all(np.isfinite(t_eval)) or np.any(np.diff(t_eval) <= 0)
            or (t_eval.size and (t_eval[0] < 0 or t_eval[-1] > t_end))):
        raise InputError(f"t_eval: must be increasing times in [0, t_end = {t_end:.12g}]")
    try:
        tt_, ya, yb, found, nfev, stopped = dop853.solve(
            rhs, t_eval.tolist(), (theta_0, dtheta_0), rtol, atol, t_span=(0.0, t_end),
            events=(short, turning, crossing))
    except (dop853.NotFinite, ZeroDivisionError):
        raise ConvergenceError(f"DOP853 did not reach t_end = {t_end:.12g}: a state or its "
                               "derivative is no longer finite") from None
    except dop853.StepTooSmall as e:
        raise ConvergenceError(f"DOP853 did not reach t_end = {t_end:.12g}: {e}") from None
    if found[0][0]:
        te = float(found[0][0][0])
        raise LengthReachesZeroError(
            f"L(t) = {length} falls to {LENGTH_FLOOR:g} L(0) at t = {te:.12g} (values {used}): too "
            f"short, relative to L(0), for the integration to go on before t_end = {t_end:.12g}; "
            f"integrate to t_end < {te:.12g}", te)
    y = np.array([ya, yb], dtype=float).reshape(2, -1)
    if not np.all(np.isfinite(y)):
        raise ConvergenceError(f"DOP853 did not reach t_end = {t_end:.12g}: a state is no longer finite")
    tt = np.array(found[1][0], dtype=float)
    th = np.array([s[0] for s in found[1][1]], dtype=float)
    # the start (dtheta(0) = 0, or theta(0) = 0) is not an event of the motion
    start = 1e-12 * t_end
    keep = tt > start
    tc = np.array(found[2][0], dtype=float)
    return Trajectory(np.array(tt_, dtype=float), y[0], y[1], dict(values), bool(linear),
                      (tt[keep], th[keep]), np.asarray(tc[tc > start]), int(nfev))


# ---------------------------------------------------------------------------
# the closed form (pipeline stage closed_form) at the same times
# ---------------------------------------------------------------------------

def _closed_expr(solution, length, keep_B=True):
    """theta as an expression in (t, theta_0, parameters) from the closed form stage."""
    z_t = solution.z_of_L.subs(S.Lvar, length)
    z0 = solution.z_of_L.subs(S.Lvar, length.subs(S.t, 0))
    constants = dict(solution.constants)
    if not keep_B:
        constants[S.B] = sp.Integer(0)
    expr = solution.general_z.subs(constants).subs(solution.z0_symbol, z0)
    return expr.subs(S.z, z_t)


def closed_form_theta(solution, length, values, theta_0, times, *, engine="scipy", dps=30,
                      keep_B=True):
    """The closed form theta(t) at ``times`` (a float array).

    ``solution`` is the pipeline's closed_form stage (a solved
    :class:`~pendulab.analyses.bessel.BesselSolution`): theta = A z^-1 J1(z) + B z^-1 Y1(z)
    with A, B fixed by theta(0) = ``theta_0``, theta'(0) = 0 (002, "Pela regra
    de Cramer") and z = (2/v0) sqrt(g L(t)).  ``engine="scipy"`` evaluates
    the expression with scipy.special.jv/yv on the whole array (double
    precision; fast), ``engine="mpmath"`` point by point at ``dps`` digits.
    ``keep_B=False`` drops the Y1 term (the z0 = j_{2,k} case, where B = 0).
    """
    expr = substitute(_closed_expr(solution, length, keep_B), values)
    rest = expr.free_symbols - {S.t, S.theta_0}
    if rest:
        raise InputError(f"the closed form needs numbers for {', '.join(sorted(s.name for s in rest))}")
    th0 = _finite("theta_0", theta_0)
    times = np.asarray(times, dtype=float)
    if engine == "scipy":
        fn = sp.lambdify((S.t, S.theta_0), expr, ["scipy", "numpy"])
        # extreme scene values (L0 = g = 1e-300) overflow or give NaN here: the callers see
        # the values and refuse them in one line; NumPy's warnings would be lines more
        with np.errstate(all="ignore"):
            values = fn(times, th0)
        return np.broadcast_to(np.asarray(values, dtype=float), times.shape).copy()
    if engine != "mpmath":
        raise InputError(f"engine: must be 'scipy' or 'mpmath', got {engine!r}")
    import mpmath
    fn = sp.lambdify((S.t, S.theta_0), expr, "mpmath")
    with mpmath.workdps(dps):
        m0 = mpmath.mpf(th0)
        return np.array([float(mpmath.re(fn(mpmath.mpf(float(x)), m0))) for x in times])


def closed_form_constants(solution, length, values, theta_0, *, dps=30, z0=None):
    """(z0, A, B) of the closed form as mpmath numbers at ``dps`` digits.

    ``z0`` (an mpmath number) overrides the z0 of ``values`` (used to
    evaluate A, B exactly at a zero of J2).
    """
    import mpmath
    z0_expr = substitute(solution.z_of_L.subs(S.Lvar, length.subs(S.t, 0)), values)
    th0 = sp.Float(_finite("theta_0", theta_0), 17)
    with mpmath.workdps(dps + 10):
        z0v = sp.lambdify((), z0_expr, "mpmath")() if z0 is None else mpmath.mpf(z0)
        both = [substitute(solution.constants[key].subs(S.theta_0, th0), values) for key in (S.A, S.B)]
        out = [z0v] + list(sp.lambdify(solution.z0_symbol, both, "mpmath")(z0v))
    return tuple(+x for x in out)


def relative_agreement(numeric, reference):
    """max |numeric - reference| / max |reference| (floats; the scale is the motion's size)."""
    numeric, reference = np.asarray(numeric, float), np.asarray(reference, float)
    scale = np.max(np.abs(reference))
    if not scale > 0:
        raise InputError("the reference motion is identically zero: no relative agreement")
    return float(np.max(np.abs(numeric - reference)) / scale)


# ---------------------------------------------------------------------------
# z0 at a zero of J2: B = 0 (002, "Conseqüência")
# ---------------------------------------------------------------------------

def _l0_roots(z0_of_l0, jsym):
    """The solutions L0 of z0(L0) = j (z0 with numbers in, a Float coefficient) as
    ``sp.solve(sp.Eq(z0_of_l0, jsym), L0)`` gives them.

    sp.solve recasts the Floats as rationals (``nsimplify(..., rational=True)``), solves
    exactly and makes the solution's numbers Floats again (``nfloat``).  For z0 = c sqrt(L0),
    the z of the closed form at L(0) = L0, the exact solution is L0 = j^2/c^2 (none for
    c < 0, as j > 0): formed here the same way, without the solver (tests compare the
    two); any other z0 goes to sp.solve.
    """
    coeff, rest = z0_of_l0.as_coeff_Mul()
    if not (coeff.is_Float and rest == sp.sqrt(S.L0)):
        return sp.solve(sp.Eq(z0_of_l0, jsym), S.L0)
    if not coeff > 0:
        return []
    c = sp.nsimplify(coeff, rational=True)
    return [sp.nfloat(jsym**2 / c**2, exponent=False)]


def b_zero_length(solution, length, values, k=None, *, dps=30):
    """The initial length L0 that puts z0 at the k-th zero of J2, so that B = 0.

    ``solution.constants[B]`` is proportional to J2(z0) (derived: B = (pi/2) theta_0 z0^2 J2(z0);
    002 prints the opposite sign); the closed form's z0 expression is solved for L0 with
    z0 = j_{2,k} (certified, :func:`pendulab.analyses.bessel_zeros.bessel_zeros`).  ``k=None`` takes the zero nearest to
    the z0 of ``values``.  Returns (L0, k, j_{2,k}) with L0 a float and
    j_{2,k} an mpmath number at ``dps`` digits.
    """
    import mpmath
    from pendulab.analyses.bessel_zeros import bessel_zeros
    z0 = solution.z_of_L.subs(S.Lvar, length.subs(S.t, 0))
    if S.L0 not in z0.free_symbols:
        raise InputError(f"z0 = {z0} does not depend on L0: cannot adjust L0")
    others = {n: v for n, v in values.items() if n != "L0"}
    z0_of_L0 = substitute(z0, others)
    jsym = sp.Symbol("j", positive=True)
    roots = _l0_roots(z0_of_L0, jsym)
    if len(roots) != 1:
        raise InputError(f"cannot solve z0 = {z0} for L0 uniquely (solutions: {roots})")
    known = []  # j_{2,1} .. j_{2,n} computed so far (each zero is the same whatever n is)
    with mpmath.workdps(dps + 10):
        def zeros(n):  # j_{2,1} .. j_{2,n}, certified, at the working precision dps + 10
            if len(known) < n:
                known[:] = [mpmath.mpf(x) for x in bessel_zeros(2, n, dps + 10).strings]
            return known[:n]
        if k is None:
            current = float(sp.lambdify((), substitute(z0, values), "mpmath")())
            # McMahon's leading term j_{2,k} ~ (k + 1/2 + 1/4) pi brackets the index; pick the nearest.
            guess = max(1, int(round(current / math.pi - 0.75)))
            cands = [c for c in (guess - 1, guess, guess + 1) if c >= 1]
            js = zeros(cands[-1])
            k = min(cands, key=lambda c: abs(js[c - 1] - current))
        if isinstance(k, bool) or not isinstance(k, int) or k < 1:
            raise InputError(f"k: must be a positive integer, got {k!r}")
        j = zeros(k)[-1]
        l0 = roots[0].subs(jsym, sp.Float(mpmath.nstr(j, dps + 5), dps + 5))
        return float(l0), k, +j


# ---------------------------------------------------------------------------
# the amplitude law (adiabatic invariant E/omega)
# ---------------------------------------------------------------------------

def amplitude_exponent(system, equations):
    """The exponent q of amplitude ~ L^q for slow lengthening, derived from E/omega = const.

    With the length frozen at L (L' = L'' = 0), the linear equation
    (equations stage, 002 eq. 4) reads lead * theta'' + restoring * theta = 0,
    so omega^2 = restoring/lead; the small-oscillation energy of amplitude a
    is V(a) - V(0) of the system's potential energy to second order in a
    (Taylor: the first two a-derivatives at a = 0).  E/omega = C fixes a as a
    function of L; by implicit differentiation of I(a, L) = E/omega,
    da/dL = -I_L/I_a, and the exponent is L (da/dL)/a = -L I_L/(a I_a),
    simplified (no equation is solved for a).  Returns a SymPy Rational (for
    the string: -3/4); an InputError when it depends on a (not a power law).
    """
    amp = sp.Symbol("a_theta", positive=True)
    th = system.coordinate
    ell = S.L(S.t)
    frozen = {ell.diff(S.t, 2): 0, ell.diff(S.t): 0}
    lin = sp.expand(equations.linear.subs(frozen).subs(ell, S.Lvar))
    lead = lin.coeff(th.diff(S.t, 2))
    restoring = sp.expand(lin - lead * th.diff(S.t, 2)).coeff(th)
    omega = sp.sqrt(sp.simplify(restoring / lead))
    v = sp.sympify(system.potential_energy).subs(ell, S.Lvar)
    v_amp = v.subs(th, amp)
    first = sp.diff(v_amp, amp)
    energy = first.subs(amp, 0) * amp + sp.diff(first, amp).subs(amp, 0) * amp**2 / 2
    invariant = energy / omega
    by_amp = sp.diff(invariant, amp)
    if by_amp == 0:
        raise InputError(f"E/omega = {invariant} does not depend on the amplitude")
    exponent = sp.simplify(-S.Lvar * sp.diff(invariant, S.Lvar) / (amp * by_amp))
    if exponent.free_symbols:
        raise InputError(f"the amplitude is not a power of L (d log a / d log L = {exponent})")
    return exponent


def turning_points(traj):
    """(t, |theta|) at the turning points (dtheta = 0) of a :class:`Trajectory`."""
    tt, th = traj.turning
    return np.asarray(tt), np.abs(np.asarray(th))


def quarter_periods(traj):
    """The swings of a :class:`Trajectory` between its events, in time order.

    A list of (kind, t_from, t_to): kind "toward" runs from a turning point
    (dtheta = 0) to the next theta = 0, "outward" from theta = 0 to the next
    turning point (002's "quarto-periodo").  The start (a turning point, as
    theta'(0) = 0) counts as the first event.
    """
    events = sorted([(0.0, "turn")] + [(float(t), "turn") for t in traj.turning[0]]
                    + [(float(t), "zero") for t in traj.crossings])
    out = []
    for (t1, k1), (t2, k2) in zip(events, events[1:]):
        if k1 == k2:
            raise ConvergenceError(f"two {k1} events in a row at t = {t1:.12g}, {t2:.12g}: the "
                                   "event detection missed one (integrate with more points)")
        out.append(("toward" if k1 == "turn" else "outward", t1, t2))
    return out


def zero_quarter_periods(k, count, growing=True, *, dps=20):
    """The quarter periods of the z0 = j_{2,k} motion from the zeros of J1 and J2.

    With B = 0, theta = A z^-1 J1(z): theta' = 0 at the zeros of J2, theta = 0
    at those of J1 (d/dz[z^-1 J1] = -z^-1 J2).  z runs up from j_{2,k}
    (growing string: j_{2,k}, j_{1,k+1}, j_{2,k+1}, ...) or down (shortening:
    j_{2,k}, j_{1,k}, j_{2,k-1}, ..., j_{1,1}).  A swing lasts |z_b^2 - z_a^2|
    in the unit |v0|/(4 g) (002).  Returns up to ``count`` pairs
    (kind, duration) in time order, kind "toward" or "outward", durations as
    mpmath numbers of the certified quarter periods
    (:func:`pendulab.analyses.bessel_periods.quarter_periods`, every one of
    their ``dps`` digits correct).
    """
    import mpmath
    from pendulab.analyses import bessel_periods as bp
    if isinstance(count, bool) or not isinstance(count, int) or count < 0:
        raise InputError(f"count: must be a non-negative integer, got {count!r}")
    if count == 0:
        return []
    if growing:
        qp = bp.quarter_periods((count + 1) // 2, dps, bp.GROWING, start=k)
        pairs = [(kind, text) for i, o in zip(qp.inward, qp.outward)
                 for kind, text in (("toward", i), ("outward", o))]
    else:
        qp = bp.quarter_periods(min(count, 2 * k - 1), dps, bp.SHORTENING, start=k)
        pairs = []
        for i, text in enumerate(qp.inward):
            pairs.append(("toward", text))
            if i < len(qp.outward):
                pairs.append(("outward", qp.outward[i]))
    with mpmath.workdps(dps + 5):
        return [(kind, mpmath.mpf(text)) for kind, text in pairs[:count]]


def fit_exponent(traj, length, skip=0):
    """Least-squares slope of log|theta| at the turning points against log L(t).

    Returns (slope, points used, the max deviation of log|theta| from the
    fitted line).  ``skip`` leaves out the first turning points.
    """
    tt, amp = turning_points(traj)
    tt, amp = tt[skip:], amp[skip:]
    if tt.size < 3:
        raise InputError(f"only {tt.size} turning points: integrate longer to fit an exponent")
    lfun, _ = length_function(length, traj.values)
    x = np.log([lfun(t) for t in tt])
    y = np.log(amp)
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), int(tt.size), float(np.max(np.abs(y - (slope * x + intercept))))


# ---------------------------------------------------------------------------
# periodic L(t): Floquet verdict from the monodromy matrix
# ---------------------------------------------------------------------------

def periodic_verdict(fos, values, *, method="dop853", dps=None):
    """The Floquet verdict of a periodic L(t) (``fos.period`` not None).

    ``values`` {name: number} must hold every parameter of ``fos.params``
    (others are ignored).  Returns the
    :class:`pendulab.numerics.monodromy.FloquetVerdict` of
    :func:`pendulab.numerics.monodromy.floquet_verdict` (the monodromy matrix
    of 002 eq. 4 over one period; ``method``, ``dps`` as there).
    """
    from pendulab.numerics.monodromy import floquet_verdict
    if fos.period is None:
        raise InputError(f"L(t) is not periodic ({fos.note}): no Floquet verdict")
    p = _param_values(fos.params, values, "the Floquet verdict")
    return floquet_verdict(fos, p, method=method, dps=dps)


def verdict_word(fv):
    """"boundary" if the verdict could not decide the side of a band edge, else
    "stable" or "unstable" (a :class:`~pendulab.numerics.monodromy.FloquetVerdict`)."""
    if fv.on_boundary:
        return "boundary"
    return "stable" if fv.stable else "unstable"


def growth_factor(traj, period):
    """max |theta| over the last period of ``traj`` divided by max |theta| over its first."""
    t = traj.t
    first = np.abs(traj.theta[t <= t[0] + period]).max()
    last = np.abs(traj.theta[t >= t[-1] - period]).max()
    return float(last / first)
