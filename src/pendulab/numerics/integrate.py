"""The numerics stage, step 3: integrators of the generated first-order systems.

* :func:`ensemble_rk4` - the source's integrator (000 sec. 4): fixed-step
  classical Runge-Kutta of order 4 over an ensemble of trajectories, no early
  exit, with the running statistics of theta the stability criteria read;
  compiled C kernel (:mod:`pendulab.numerics.ckernel`) or the generated NumPy
  module (:func:`pendulab.numerics.codegen.numpy_module`), same call.
* :func:`rk4_trajectory` - one RK4 trajectory, every state.
* :func:`reference_trajectory` - DOP853 at rtol 1e-13 (SciPy's method and tables,
  stepped on scalar floats by :mod:`pendulab.numerics.dop853`): the reference that
  measures RK4's error (:func:`rk4_error`).

One RK4 step from time t_i = t0 + i dt (the times are computed from i, not
accumulated) with f = ``fos.rhs`` (or ``fos.linear_rhs`` with
``linear=True``):

    k1 = f(t_i, y_i),  k2 = f(t_i + dt/2, y_i + (dt/2) k1),
    k3 = f(t_i + dt/2, y_i + (dt/2) k2),  k4 = f(t_i + dt, y_i + dt k3),
    y_{i+1} = y_i + (dt/6) (k1 + 2 k2 + 2 k3 + k4).

The state is (theta, dtheta) in the system's own time (tau for the driven
pivot, t for the variable length); with ``linear=True`` it is the deviation
from ``fos.about``.
"""

import math
import os
from dataclasses import dataclass

import numpy as np

from pendulab.errors import InputError

BACKENDS = ("auto", "c", "numpy")


@dataclass(frozen=True)
class EnsembleResult:
    """What :func:`ensemble_rk4` returns for n trajectories.

    The statistics are over the ``steps + 1`` states y_0 (the initial one),
    y_1, ..., y_steps, each with weight 1:

    * ``y`` - (n, 2): the final states y_steps (theta, dtheta);
    * ``mean_theta`` - (n,): sum_i theta_i / (steps + 1), the signed time mean
      (criterion ``mean``: |mean_theta| < 0.1);
    * ``mean_abs_theta`` - (n,): sum_i |theta_i| / (steps + 1) (``mean-abs``);
    * ``max_abs_theta`` - (n,): max_i |theta_i| (``bounded``: < pi/2);
    * ``backend`` - "c" or "numpy", ``steps`` and ``dt`` as given;
    * ``exact_trajectories`` - how many trajectories met a sine argument beyond
      :data:`~pendulab.numerics.codegen.SIN_LIMIT` and were integrated again with
      the library sine (C's, or NumPy's on the NumPy path).

    Both backends do the same IEEE operations in the same order (the NumPy path
    runs :func:`pendulab.numerics.codegen.numpy_kernel_module`, the C kernel's
    arithmetic), so they give the same bits, except for trajectories integrated
    again with the library sine (C's and NumPy's sines may differ in the last bit).

    A trajectory that overflows has NaN or inf in all its statistics
    (a NaN state makes every later statistic NaN, in both backends).
    """

    y: np.ndarray
    mean_theta: np.ndarray
    mean_abs_theta: np.ndarray
    max_abs_theta: np.ndarray
    backend: str
    steps: int
    dt: float
    exact_trajectories: int = 0


# -- input checks ---------------------------------------------------------------------------

def _finite_number(value, name):
    if isinstance(value, bool):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(x):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return x


def _steps(steps):
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
        raise InputError(f"steps must be a positive integer, got {steps!r}")
    if steps <= 0:
        raise InputError(f"steps must be a positive integer, got {steps!r}")
    return int(steps)


def _array(value, name):
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers") from None
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} has a value that is not finite")
    return a


def _check_ensemble(fos, y0, params):
    """(y0 (n, 2), params (n, k)) as C-contiguous float arrays, or one InputError."""
    k = len(fos.params)
    y0 = _array(y0, "y0")
    if y0.ndim != 2 or y0.shape[1] != 2:
        raise InputError(f"y0 must have shape (n, 2) (theta, dtheta), got {y0.shape}")
    n = y0.shape[0]
    p = _array(params, "params")
    names = ", ".join(s.name for s in fos.params) or "none"
    if p.ndim == 1:
        if p.shape[0] != k:
            raise InputError(f"params must have {k} values ({names}), got {p.shape[0]}")
        p = np.broadcast_to(p, (n, k))
    elif p.ndim == 2:
        if p.shape != (n, k):
            raise InputError(f"params must have shape ({n}, {k}) (one row of {names} per "
                             f"trajectory), got {p.shape}")
    else:
        raise InputError(f"params must have shape (n, {k}) or ({k},), got {p.shape}")
    return np.ascontiguousarray(y0), np.ascontiguousarray(p)


def _check_point(fos, y0, params):
    y0 = _array(y0, "y0")
    if y0.shape != (2,):
        raise InputError(f"y0 must have shape (2,) (theta, dtheta), got {y0.shape}")
    k = len(fos.params)
    p = _array(params, "params")
    if p.shape != (k,):
        names = ", ".join(s.name for s in fos.params) or "none"
        raise InputError(f"params must have shape ({k},) ({names}), got {p.shape}")
    return y0, p


def _backend(backend):
    if backend not in BACKENDS:
        raise InputError(f"backend must be one of {', '.join(BACKENDS)}, got {backend!r}")
    return backend


def _kernel(fos, backend):
    """The compiled kernel for ``backend`` ("c" or "auto"), or None for NumPy."""
    if backend == "numpy":
        return None
    from pendulab.numerics import ckernel
    return ckernel.load(fos, required=(backend == "c"))


def c_kernel_available(fos=None):
    """Whether :func:`ensemble_rk4` with backend "auto" runs compiled C here (for ``fos``,
    or any system when None: a probe compile with the same compiler and flags)."""
    from pendulab.numerics import ckernel
    return ckernel.available(fos)


def default_threads():
    """The cores this process may use (sched_getaffinity where available)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


# -- the NumPy path -------------------------------------------------------------------------

def _max_abs(a, b):
    x = np.abs(a)
    return np.where((x > b) | (x != x), x, b)


def _rk4_kernel_numpy(ns, tag, y0, p, t0, dt, steps, record=None):
    """The C kernel's block loop in NumPy (same operations, same order, same bits).

    y0 (n, 2), p (n, k); returns (theta, dtheta, sum theta, sum |theta|, max |theta|,
    guard), each (n,); ``record(i, theta, dtheta)`` after each step.
    """
    tt, pt = ns[f"time_terms_{tag}"], ns[f"point_{tag}"]
    th, om = y0[:, 0].copy(), y0[:, 1].copy()
    P = [p[:, q].copy() for q in range(p.shape[1])]
    s, sa, m = th.copy(), np.abs(th), np.abs(th)
    G, gt = np.zeros_like(th), 0.0
    h2, h6 = 0.5 * dt, dt / 6.0
    with np.errstate(all="ignore"):
        for i in range(steps):
            ta, tm, tb = t0 + i * dt, t0 + (i + 0.5) * dt, t0 + (i + 1) * dt
            ca, g = tt(ta)
            gt = _max_abs(g, gt)
            cm, g = tt(tm)
            gt = _max_abs(g, gt)
            cb, g = tt(tb)
            gt = _max_abs(g, gt)
            a0, a1, ga = pt(ca, ta, th, om, *P)
            b0, b1, gb = pt(cm, tm, th + h2 * a0, om + h2 * a1, *P)
            c0, c1, gc = pt(cm, tm, th + h2 * b0, om + h2 * b1, *P)
            d0, d1, gd = pt(cb, tb, th + dt * c0, om + dt * c1, *P)
            th = th + h6 * (a0 + 2.0 * b0 + 2.0 * c0 + d0)
            om = om + h6 * (a1 + 2.0 * b1 + 2.0 * c1 + d1)
            x = np.abs(th)
            s += th
            sa += x
            m = np.where((x > m) | (x != x), x, m)
            G = _max_abs(ga, _max_abs(gb, _max_abs(gc, _max_abs(gd, G))))
            if record is not None:
                record(i + 1, th, om)
    return th, om, s, sa, m, _max_abs(G, gt)


def _ensemble_numpy(fos, y0, p, t0, dt, steps, linear, stats):
    """The NumPy path: the C kernel's arithmetic (codegen.numpy_kernel_module), reruns too."""
    from pendulab.numerics.codegen import numpy_kernel_functions
    ns = numpy_kernel_functions(fos)
    kind = "linear" if linear else "nonlinear"
    th, om, s, sa, m, guard = _rk4_kernel_numpy(ns, f"{kind}_fast", y0, p, t0, dt, steps)
    rerun = np.nonzero(~(guard <= ns["SIN_LIMIT"]))[0] if ns[f"RERUN_{kind.upper()}"] else []
    if len(rerun):
        out = _rk4_kernel_numpy(ns, f"{kind}_exact", y0[rerun], p[rerun], t0, dt, steps)
        for arr, new in zip((th, om, s, sa, m), out):
            arr[rerun] = new
    y = np.column_stack([th, om])
    if not stats:
        nan = np.full(len(th), np.nan)
        return y, nan, nan.copy(), nan.copy(), 0
    return y, s / (steps + 1), sa / (steps + 1), m, len(rerun)


# -- the public calls -----------------------------------------------------------------------

def ensemble_rk4(fos, y0, params, t0, dt, steps, *, linear=False, stats=True, backend="auto",
                 threads=None):
    """Integrate n trajectories of ``fos`` with fixed-step RK4 from t0 over ``steps`` steps.

    ``y0``: (n, 2) initial states (theta, dtheta); ``params``: (n, len(fos.params))
    values in ``fos.params`` order, or one row (len(fos.params),) for all.  No early
    exit: every trajectory takes every step.  ``backend``: "c" (the compiled kernel;
    an :class:`~pendulab.errors.InputError` if it cannot be built), "numpy" (the
    generated NumPy module), "auto" (C, else a one-line notice on stderr and NumPy).
    ``threads``: worker threads of the C kernel (default: the cores this process may
    use).  ``stats=False`` skips the statistics (they are then NaN).

    Returns an :class:`EnsembleResult` (statistics over the steps + 1 states,
    the initial one included).

    >>> from pendulab.equations import derive
    >>> from pendulab.systems import DrivenPivot
    >>> from pendulab.canonical import periodic_form
    >>> from pendulab.numerics.model import pivot_system
    >>> eqs = derive(DrivenPivot(body="rod"))
    >>> fos = pivot_system(eqs, periodic_form(eqs))      # params (a_over_l, w0_over_w)
    >>> r = ensemble_rk4(fos, [[0.06, 0.01], [0.06, 0.01]], [[0.2, 0.05], [0.0, 0.05]],
    ...                  0.0, math.pi / 100, 3000, backend="numpy")
    >>> bool(r.max_abs_theta[0] < math.pi / 2), bool(r.max_abs_theta[1] < math.pi / 2)
    (True, False)
    """
    _backend(backend)
    y0, p = _check_ensemble(fos, y0, params)
    t0 = _finite_number(t0, "t0")
    dt = _finite_number(dt, "dt")
    if dt == 0:
        raise InputError("dt must be a finite nonzero number, got 0")
    steps = _steps(steps)
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, (int, np.integer))
                                or threads < 1):
        raise InputError(f"threads must be a positive integer, got {threads!r}")
    n = y0.shape[0]
    kernel = _kernel(fos, backend)
    if n == 0:
        empty = np.empty(0)
        return EnsembleResult(np.empty((0, 2)), empty, empty.copy(), empty.copy(),
                              backend="numpy" if kernel is None else "c", steps=steps, dt=dt)
    if kernel is not None:
        *out, reruns = kernel.ensemble(y0, p, t0, dt, steps, linear=linear, stats=stats,
                                       threads=threads or default_threads())
        return EnsembleResult(*out, backend="c", steps=steps, dt=dt, exact_trajectories=reruns)
    *out, reruns = _ensemble_numpy(fos, y0, p, t0, dt, steps, linear, stats)
    return EnsembleResult(*out, backend="numpy", steps=steps, dt=dt, exact_trajectories=reruns)


def rk4_trajectory(fos, y0, params, t0, dt, steps, *, linear=False, backend="auto"):
    """One RK4 trajectory: (times (steps + 1,), states (steps + 1, 2)), y0 first.

    ``y0`` (2,), ``params`` (len(fos.params),); times t0 + i dt; the step, the sine
    and the bits are those of :func:`ensemble_rk4`.
    """
    _backend(backend)
    y0, p = _check_point(fos, y0, params)
    t0 = _finite_number(t0, "t0")
    dt = _finite_number(dt, "dt")
    if dt == 0:
        raise InputError("dt must be a finite nonzero number, got 0")
    steps = _steps(steps)
    times = t0 + dt * np.arange(steps + 1, dtype=float)
    kernel = _kernel(fos, backend)
    if kernel is not None:
        return times, kernel.path(y0, p, t0, dt, steps, linear=linear)
    from pendulab.numerics.codegen import numpy_kernel_functions
    ns = numpy_kernel_functions(fos)
    kind = "linear" if linear else "nonlinear"
    states = np.empty((steps + 1, 2))
    states[0] = y0

    def record(i, th, om):
        states[i, 0], states[i, 1] = th[0], om[0]
    *_, guard = _rk4_kernel_numpy(ns, f"{kind}_fast", y0.reshape(1, 2), p.reshape(1, -1), t0, dt,
                                  steps, record=record)
    if ns[f"RERUN_{kind.upper()}"] and not guard[0] <= ns["SIN_LIMIT"]:
        _rk4_kernel_numpy(ns, f"{kind}_exact", y0.reshape(1, 2), p.reshape(1, -1), t0, dt, steps,
                          record=record)
    return times, states


def reference_trajectory(fos, y0, params, t_eval, *, linear=False, rtol=1e-13, atol=1e-15,
                         max_evaluations=None):
    """DOP853 on the generated right-hand side: states (len(t_eval), 2) at ``t_eval``.

    Starts from ``y0`` (2,) at t_eval[0]; ``t_eval`` must be monotonic.  The reference that
    measures RK4's error (:func:`rk4_error`); raises InputError if the solver fails, if a
    state stops being finite, or after ``max_evaluations`` evaluations of the right-hand side
    (None: no bound; DOP853 takes 12 per step, 3 more for the dense output of a step with
    output times).  The method is SciPy's DOP853 (same tables, same step-size control) run
    on scalar floats by :mod:`pendulab.numerics.dop853`, with the code generation stage's
    scalar right-hand side (:func:`pendulab.numerics.codegen.scalar_function`).
    """
    from pendulab.numerics import dop853
    from pendulab.numerics.codegen import scalar_function
    y0, p = _check_point(fos, y0, params)
    t_eval = _array(t_eval, "t_eval")
    if t_eval.ndim != 1 or t_eval.size < 2:
        raise InputError("t_eval must be a 1-d array of at least two times")
    d = np.diff(t_eval)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise InputError("t_eval must be strictly monotonic")
    rtol = _finite_number(rtol, "rtol")
    atol = _finite_number(atol, "atol")
    f = scalar_function(fos, linear)
    pl = tuple(float(x) for x in p)

    def fun(t, a, b):
        return f(t, (a, b), pl)
    try:
        _, ya, yb, *_ = dop853.solve(fun, t_eval.tolist(), y0, rtol, atol,
                                     max_evaluations=max_evaluations)
    except dop853.TooManyEvaluations:
        raise InputError(f"the reference (DOP853 at rtol {rtol:g}) passed {max_evaluations} "
                         "evaluations of the right-hand side before reaching the end (a fast "
                         "oscillation or rotation); ask for fewer periods or smaller values") from None
    except dop853.NotFinite:
        raise InputError("reference integration (DOP853) overflowed (a state is no longer finite)") from None
    except dop853.StepTooSmall as e:
        raise InputError(f"reference integration (DOP853) failed: {e}") from None
    out = np.column_stack([np.array(ya, float), np.array(yb, float)])
    if not np.all(np.isfinite(out)):
        raise InputError("reference integration (DOP853) overflowed (a state is no longer finite)")
    return out


def rk4_error(fos, y0, params, t0, dt, steps, linear=False, backend="auto"):
    """max over i = 0..steps and both components of |RK4 state_i - DOP853 reference_i|.

    The reference is :func:`reference_trajectory` at rtol 1e-13, atol 1e-15 on the
    same times t0 + i dt.
    """
    times, states = rk4_trajectory(fos, y0, params, t0, dt, steps, linear=linear, backend=backend)
    ref = reference_trajectory(fos, y0, params, times, linear=linear)
    return float(np.max(np.abs(states - ref)))
