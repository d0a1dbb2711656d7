"""Parameter sweeps of the driven pivot: grids, stability criteria, chunks, executors.

A sweep integrates the full nonlinear equation of motion in the source's time
tau (the first-order system of :func:`pendulab.numerics.model.pivot_system`,
000 sec. 4) for every cell of a grid and classifies each trajectory by a
stability criterion of the inverted position.

Cells.  The parameters are a/l (``a_over_l``, columns) and omega0/omega
(``w0_over_w``, rows); with several initial conditions (theta(0), theta'(0))
(tau-derivative) the cell index is

    k = c * (n_w * n_a) + i * n_a + j

for initial condition c, omega0/omega index i and a/l index j.  Maps are
arrays of shape (n_init, n_w, n_a) (or (n_w, n_a) for one initial condition).

Criteria (:data:`CRITERIA`), over the whole run of ``periods`` drive periods
with ``steps_per_period`` fixed RK4 steps each (no early exit):

* ``mean``     - |time mean of theta| < 0.1 (the signed mean; 000 sec. 4);
* ``mean-abs`` - time mean of |theta| < 0.1 (000 sec. 4 read with |theta|);
* ``bounded``  - |theta| < pi/2 throughout;
* ``floquet``  - the linear verdict: the inverted position is stable
  for Mathieu's equation with (theta0, theta1) of the canonical stage
  (:func:`pendulab.numerics.model.mathieu_parameters`, lambdified;
  :func:`pendulab.analyses.floquet.is_stable`, double precision: a cell within
  a few ulps of a characteristic curve takes is_stable's count, which may fall
  on either side; :func:`pendulab.analyses.stability_map.map_stability` decides
  such cells exactly); for any other periodic drive (Hill's equation)
  |tr M| < 2 of the monodromy matrix
  (:func:`pendulab.numerics.monodromy.traces_along`, DOP853, no margin
  check).  No trajectory is integrated.

Chunks and executors.  The cells are cut into chunks of ``chunk_size``
consecutive cells (a function of the sweep only, never of the executor).
Each chunk is an independent task that carries its cell indices; the
results are put back in index order and :func:`assemble` checks that every
index came back exactly once.  A chunk runs in this process
(``executor="serial"``), on local processes (``"processes"``, spawn start
method, both cores by default) or on a dask.distributed cluster
(``dask=ADDRESS`` or a ``distributed.Client``); the output bytes are the same
whatever the executor.

Progress is shown on stderr with tqdm for sweeps that last more than about
2 s (``tqdm(delay=2)``), never when stderr is not a terminal or with
``quiet=True``.
"""

import math
import os
import sys
import time
from dataclasses import dataclass, field, replace

from pendulab.errors import InputError, PendulabError

#: The stability criteria a sweep understands.
CRITERIA = ("mean", "mean-abs", "bounded", "floquet")
#: Threshold of the ``mean`` and ``mean-abs`` criteria (000 sec. 4: "theta medio menor que 0.1").
THRESHOLD = 0.1
#: Bound of the ``bounded`` criterion: the pendulum never falls below the horizontal.
BOUND = math.pi / 2
#: Cells per chunk unless the caller says otherwise.
CHUNK_SIZE = 250
#: Largest number of cells of one sweep (memory of the stats arrays stays ~ 100 MB).
MAX_CELLS = 4_000_000
#: Largest number of RK4 steps of all trajectories of one sweep together: 3e9
#: is ten Fig. 3 sweeps (10^4 cells x 3e4 steps), about 12 s with the C kernel
#: (4 ns per step per trajectory, benchmarks/bench_rk4.py) and five minutes on
#: the NumPy fallback.
MAX_STEPS = 3_000_000_000
#: Largest |a/l|, |omega0/omega|, |theta(0)|, |dtheta/dtau(0)| a sweep or a simulation takes
#: (the command line's ranges: pendulab.limits.LIMITS["sweep.theta_init"] ...).
from pendulab.limits import MAX_MAGNITUDE  # noqa: E402
#: Seconds to wait for a Dask scheduler before giving up.
CONNECT_TIMEOUT = 3.0
#: Progress bars appear only after this many seconds.
PROGRESS_DELAY = 2.0
EXECUTORS = ("auto", "serial", "processes", "dask")


# ---------------------------------------------------------------------------
# the system: rebuilt from a small picklable description in every worker
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SystemSpec:
    """How to build the driven-pivot system of a sweep (picklable, hashable).

    ``body`` is "rod", "point" or "explicit"; ``inertia_ratio`` is I/(m l^2)
    for an explicit body whose inertia is left as the symbol I (it becomes the
    parameter ``inertia_ratio`` of the first-order system); ``drive``,
    ``angle`` and ``inertia`` are the scene's texts (None: the defaults of
    :class:`pendulab.systems.DrivenPivot`).
    """

    body: str = "rod"
    inertia_ratio: float = None
    drive: str = None
    angle: str = "up"
    inertia: str = None

    def describe(self):
        if self.body == "explicit" and self.inertia is None:
            return f"I/(m l^2) = {self.inertia_ratio!r}"
        return self.body


_STAGES = {}


def use_stages(spec, equations, form):
    """Let this process reuse a pipeline's equations and canonical stages for ``spec``
    (a product already has them; deriving again costs seconds).  Workers derive their own."""
    _STAGES[spec] = (equations, form)


def stages(spec):
    """(equations, canonical form) of the system ``spec``, derived once per process."""
    return _stages(spec)


def _stages(spec):
    if spec not in _STAGES:
        _STAGES[spec] = _derive(spec)
    return _STAGES[spec]


#: The symbols a drive of a sweep, simulation or animation may use: the time, the amplitude and
#: the frequency (the runs set a/l and omega0/omega, nothing else).
DRIVE_SYMBOLS = ("t", "a", "omega")


def _derive(spec):
    from pendulab.equations import derive
    from pendulab.exprs import parse
    from pendulab.pipeline import canonical_form
    from pendulab.systems import DrivenPivot

    kwargs = {"body": spec.body, "angle": spec.angle}
    if spec.drive is not None:
        kwargs["drive"] = parse(spec.drive)
        # a symbol a run cannot set is refused even where it drops out of the equation (in a
        # constant term, or in cos(omega*x), constant in t): it is what the user wrote
        other = sorted({s.name for s in kwargs["drive"].free_symbols} - set(DRIVE_SYMBOLS))
        if other:
            raise InputError(f"the drive {spec.drive} uses {', '.join(other)}: a drive may use "
                             "only t, a and omega (write the drive's amplitude with a and its "
                             "frequency with omega, and a number for any other factor, as in "
                             "a*cos(omega*t) + a/2*cos(2*omega*t))")
        if "omega" not in {s.name for s in kwargs["drive"].free_symbols}:
            raise InputError(f"the drive {spec.drive} has no omega: write its frequency with "
                             "omega, as in a*cos(omega*t) (the runs set omega0/omega, and tau = "
                             "omega t/2 needs the drive's omega)")
    if spec.inertia is not None:
        kwargs["inertia_value"] = parse(spec.inertia)
    eqs = derive(DrivenPivot(**kwargs))
    return eqs, canonical_form(eqs)


_SYSTEMS = {}


def first_order_system(spec):
    """The first-order system in tau of ``spec`` (cached per process).

    Worker processes receive it with their first task (a pickled SymPy
    system of a few kB), so they never derive it again.
    """
    if spec not in _SYSTEMS:
        from pendulab.numerics.model import pivot_system
        eqs, form = _stages(spec)
        _SYSTEMS[spec] = pivot_system(eqs, form)
    return _SYSTEMS[spec]


def _param_columns(spec, fos):
    """The parameter names of ``fos`` in order, checked against what a sweep can set."""
    names = [s.name for s in fos.params]
    known = {"a_over_l", "w0_over_w"} | ({"inertia_ratio"} if spec.inertia_ratio is not None else set())
    extra = [n for n in names if n not in known]
    if extra and spec.drive:
        # name what the user wrote (b), not the symbols the groups bring in with it (l)
        from pendulab.exprs import parse
        written = {str(x) for x in parse(spec.drive).free_symbols}
        # a symbol of the drive beyond t, a, omega is the cause, even where the groups turn it
        # into another (g*cos(2*omega*t) leaves omega, not g, among the parameters)
        extra = (sorted(written - {"t", "a", "omega"}) or [n for n in extra if n in written]
                 or extra)
    if extra:
        # said for sweep, simulate and animate alike: the symbols, and how to write instead
        sets = ("a/l, omega0/omega and I/(m l^2)" if spec.inertia_ratio is not None
                else "a/l and omega0/omega")
        raise InputError(f"the drive leaves {', '.join(extra)} without a value: a drive may use "
                         "only t, a and omega (write the drive's amplitude with a and its "
                         "frequency with omega, and a number for any other factor, as in "
                         f"a*cos(omega*t) + a/2*cos(2*omega*t)); a run sets only {sets}")
    if spec.inertia_ratio is None and spec.body == "explicit" and "inertia_ratio" in names:
        raise InputError("an explicit body with the symbol I needs inertia_ratio")
    return names


#: spec -> (its stages, the function of mathieu_pair): lambdified once per system and process
_PAIRS = {}


def mathieu_pair(spec):
    """f(a_over_l, w0_over_w) -> (theta0, theta1) as NumPy arrays, from the canonical stage.

    The pair is :func:`pendulab.numerics.model.mathieu_parameters` lambdified
    (000 eqs. 5-6 as derived, never typed); a drive whose canonical form is
    not Mathieu's is refused in one line.  Made once per ``spec`` (and its
    stages) in a process: a build's sweeps, pruning plans and Floquet
    verdicts ask for it a score of times.
    """
    stages = _stages(spec)
    made = _PAIRS.get(spec)
    if made is None or made[0] is not stages:
        if len(_PAIRS) >= 64:
            _PAIRS.clear()
        made = _PAIRS[spec] = (stages, _make_mathieu_pair(spec, *stages))
    return made[1]


def _make_mathieu_pair(spec, eqs, form):
    import numpy as np
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.numerics.model import mathieu_parameters

    if form.kind != "mathieu":
        raise InputError(f"the drive gives a {form.kind} equation, not Mathieu's: no (theta0, theta1) "
                         "pair (the floquet criterion uses the monodromy matrix; pruning and the "
                         "series comparison need Mathieu's equation)")
    pair = mathieu_parameters(eqs, form)
    if spec.inertia_ratio is not None:
        pair = tuple(v.subs(S.inertia_ratio, sp.nsimplify(spec.inertia_ratio)) for v in pair)
    fn = sp.lambdify((S.a_over_l, S.w0_over_w), list(pair), "numpy")

    def f(a, w):
        a, w = np.broadcast_arrays(np.asarray(a, float), np.asarray(w, float))
        t0, t1 = fn(a, w)
        return (np.broadcast_to(np.asarray(t0, float), a.shape).copy(),
                np.broadcast_to(np.asarray(t1, float), a.shape).copy())
    return f


# ---------------------------------------------------------------------------
# the sweep
# ---------------------------------------------------------------------------

def _finite(value, name):
    if isinstance(value, bool):
        raise InputError(f"{name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    if abs(v) > MAX_MAGNITUDE:
        # beyond it RK4 at the source's 100 steps per period only measures its own overflow
        raise InputError(f"{name} must be at most {MAX_MAGNITUDE:g} in size, got {value!r}")
    return v


def _count(value, name, minimum=1, maximum=None):
    if isinstance(value, bool) or not isinstance(value, int):
        try:
            ok = float(value).is_integer()
        except (TypeError, ValueError, OverflowError):
            ok = False
        if not ok or isinstance(value, bool):
            raise InputError(f"{name} must be a whole number, got {value!r}")
        value = int(float(value))
    if value < minimum:
        raise InputError(f"{name} must be at least {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise InputError(f"{name} must be at most {maximum}, got {value}")
    return value


def _range(name):
    """(min, max) of ``pendulab.limits.LIMITS[name]``."""
    from pendulab.limits import LIMITS
    return LIMITS[name][1:3]


def linspace_grid(n):
    """n values on [0, 1], both ends included (n = 1 gives [0.0]), as a tuple of floats."""
    import numpy as np
    n = _count(n, "grid", *_range("experiments.grid"))
    return tuple(float(v) for v in np.linspace(0.0, 1.0, n))


@dataclass(frozen=True)
class SweepSpec:
    """One sweep: system, grid, initial conditions, run length, criterion.

    ``a_over_l``, ``w0_over_w`` - tuples of grid values; ``initial`` - tuple
    of (theta(0), theta'(0)) pairs in tau; ``periods`` drive periods of
    ``steps_per_period`` RK4 steps (dt = period / steps_per_period, period pi
    for the source's drive); ``linear`` integrates the linearised equation
    (000 eq. 7) instead of the full one (000 sec. 4).
    """

    system: SystemSpec
    a_over_l: tuple
    w0_over_w: tuple
    initial: tuple = ((0.06, 0.01),)
    periods: int = 300
    steps_per_period: int = 100
    criterion: str = "mean"
    linear: bool = False
    chunk_size: int = CHUNK_SIZE

    @property
    def shape(self):
        return (len(self.initial), len(self.w0_over_w), len(self.a_over_l))

    @property
    def cells(self):
        c, i, j = self.shape
        return c * i * j


def make_spec(system=None, grid=None, *, a_over_l=None, w0_over_w=None, theta_init=0.06,
              omega_init=0.01, initial=None, periods=300, steps_per_period=100, criterion="mean",
              linear=False, chunk_size=CHUNK_SIZE):
    """A checked :class:`SweepSpec`; every problem is collected into one InputError.

    ``grid=N`` gives a/l and omega0/omega on linspace(0, 1, N); explicit
    ``a_over_l``/``w0_over_w`` sequences override it.  ``initial`` (a list
    of pairs) overrides ``theta_init``/``omega_init``.
    """
    problems = []

    def collect(fn, *args, **kw):
        try:
            return fn(*args, **kw)
        except InputError as exc:
            problems.append(str(exc))
            return None

    system = system or SystemSpec()
    if not isinstance(system, SystemSpec):
        problems.append(f"system must be a SystemSpec, got {system!r}")
    if criterion not in CRITERIA:
        problems.append(f"criterion must be one of {', '.join(CRITERIA)}, got {criterion!r}")
    axes = {}
    grid_values = None
    if grid is not None and (a_over_l is None or w0_over_w is None):
        grid_values = collect(linspace_grid, grid)  # once: one message for both axes
    for name, values in (("a_over_l", a_over_l), ("w0_over_w", w0_over_w)):
        if values is None:
            if grid is None:
                problems.append(f"give grid or {name}")
                continue
            values = grid_values
        else:
            values = tuple(collect(_finite, v, f"{name}[{k}]") for k, v in enumerate(values))
            if not values:
                problems.append(f"{name} has no values")
        if values is not None:
            if any(v is not None and v < 0 for v in values):
                problems.append(f"{name} values must be >= 0")
            axes[name] = values
    if initial is None:
        initial = [(theta_init, omega_init)]
    pairs = []
    for k, pair in enumerate(initial):
        try:
            th, om = pair
        except (TypeError, ValueError):
            problems.append(f"initial[{k}] must be a (theta, dtheta) pair, got {pair!r}")
            continue
        label = ("theta-init", "omega-init") if len(initial) == 1 else (f"initial[{k}][0]", f"initial[{k}][1]")
        pairs.append((collect(_finite, th, label[0]), collect(_finite, om, label[1])))
    if not pairs:
        problems.append("no initial conditions")
    periods = collect(_count, periods, "periods", *_range("experiments.periods"))
    steps = collect(_count, steps_per_period, "steps-per-period",
                    *_range("experiments.steps_per_period"))
    chunk = collect(_count, chunk_size, "chunk_size", 1)
    if problems:
        raise InputError("; ".join(problems))
    spec = SweepSpec(system, axes["a_over_l"], axes["w0_over_w"], tuple(pairs), periods, steps,
                     criterion, bool(linear), chunk)
    if spec.cells > MAX_CELLS:
        raise InputError(f"the sweep has {spec.cells} cells; at most {MAX_CELLS} are allowed")
    work = spec.cells * periods * steps
    if work > MAX_STEPS and criterion != "floquet":  # the floquet criterion integrates nothing
        raise InputError(f"the sweep asks for {spec.cells} trajectories x {periods * steps} RK4 "
                         f"steps = {work:.3g} steps; at most {MAX_STEPS:.0e} (about 12 s with "
                         "the C kernel): fewer cells, periods or steps per period")
    return spec


def chunks(n, size):
    """[(start, stop), ...] covering range(n) in order, ``size`` cells each (the last may be shorter)."""
    return [(s, min(s + size, n)) for s in range(0, n, size)]


def cell_arrays(spec, index):
    """(y0 (m, 2), params (m, k)) of the cells ``index`` (an int array), columns in fos.params order."""
    import numpy as np

    fos = first_order_system(spec.system)
    names = _param_columns(spec.system, fos)
    n_c, n_w, n_a = spec.shape
    index = np.asarray(index, dtype=np.int64)
    c, rest = np.divmod(index, n_w * n_a)
    i, j = np.divmod(rest, n_a)
    a = np.asarray(spec.a_over_l, float)[j]
    w = np.asarray(spec.w0_over_w, float)[i]
    init = np.asarray(spec.initial, float)[c]
    cols = {"a_over_l": a, "w0_over_w": w,
            "inertia_ratio": np.full(index.shape, float(spec.system.inertia_ratio or 0.0))}
    params = np.stack([cols[n] for n in names], axis=1) if names else np.zeros((len(index), 0))
    return init, params


def _time_step(spec):
    fos = first_order_system(spec.system)
    if fos.period is None:
        raise InputError("the drive is not periodic: a sweep needs a drive period")
    return float(fos.period) / spec.steps_per_period


def run_chunk(spec, index, backend="auto", threads=None):
    """Integrate the cells ``index`` of ``spec``; returns a dict of arrays keyed by statistic.

    Keys: ``index`` (the cell indices, as given), ``y`` (m, 2) final state,
    ``mean_theta``, ``mean_abs_theta``, ``max_abs_theta`` (m,), ``backend``.
    This is the task every executor runs; it rebuilds the system from
    ``spec.system`` (cached per process).
    """
    import numpy as np

    from pendulab.numerics.integrate import ensemble_rk4

    index = np.asarray(index, dtype=np.int64)
    fos = first_order_system(spec.system)
    y0, params = cell_arrays(spec, index)
    res = ensemble_rk4(fos, y0, params, 0.0, _time_step(spec), spec.periods * spec.steps_per_period,
                       linear=spec.linear, stats=True, backend=backend, threads=threads)
    return {"index": index, "y": np.asarray(res.y, float), "mean_theta": np.asarray(res.mean_theta, float),
            "mean_abs_theta": np.asarray(res.mean_abs_theta, float),
            "max_abs_theta": np.asarray(res.max_abs_theta, float), "backend": str(res.backend)}


def _chunk_task(args):
    """Top-level (picklable) wrapper for process pools and Dask: (spec, index, backend, threads, fos)."""
    spec, index, backend, threads, fos = args
    _SYSTEMS.setdefault(spec.system, fos)
    return run_chunk(spec, index, backend=backend, threads=threads)


STATS = ("mean_theta", "mean_abs_theta", "max_abs_theta")


def assemble(n, results):
    """Put chunk results back in index order; every index 0..n-1 must appear exactly once.

    Returns {stat: (n,) array, "y": (n, 2), "backends": sorted set}.  Raises
    PendulabError naming missing or duplicated cells.
    """
    import numpy as np

    seen = np.zeros(n, dtype=np.int64)
    out = {k: np.full(n, np.nan) for k in STATS}
    out["y"] = np.full((n, 2), np.nan)
    backends = set()
    for r in results:
        idx = np.asarray(r["index"], dtype=np.int64)
        if idx.size and (idx.min() < 0 or idx.max() >= n):
            raise PendulabError(f"a chunk returned cell indices outside 0..{n - 1}")
        np.add.at(seen, idx, 1)
        for k in STATS:
            out[k][idx] = r[k]
        out["y"][idx] = r["y"]
        backends.add(r["backend"])
    missing, dup = np.flatnonzero(seen == 0), np.flatnonzero(seen > 1)
    if missing.size or dup.size:
        raise PendulabError(f"sweep assembly: {missing.size} cell(s) missing, {dup.size} duplicated"
                            + (f" (first missing {missing[0]})" if missing.size else "")
                            + (f" (first duplicated {dup[0]})" if dup.size else ""))
    out["backends"] = sorted(backends)
    return out


def verdict(criterion, stats):
    """Boolean array: stable by ``criterion`` ("mean", "mean-abs" or "bounded") from the run's statistics.

    ``stats`` maps ``mean_theta``, ``mean_abs_theta``, ``max_abs_theta`` to
    arrays; a NaN statistic (a trajectory that overflowed) is unstable.
    """
    import numpy as np
    if criterion == "mean":
        v = np.abs(np.asarray(stats["mean_theta"], float)) < THRESHOLD
    elif criterion == "mean-abs":
        v = np.asarray(stats["mean_abs_theta"], float) < THRESHOLD
    elif criterion == "bounded":
        v = np.asarray(stats["max_abs_theta"], float) < BOUND
    else:
        raise InputError(f"criterion must be one of mean, mean-abs, bounded here, got {criterion!r}")
    return v


def floquet_verdict(spec, index=None):
    """The exact linear verdict (bool array over the cells ``index``, default all).

    Mathieu's equation (canonical kind "mathieu"): :func:`pendulab.analyses.floquet.is_stable`
    of (theta0, theta1) from :func:`mathieu_pair`.  Any other periodic drive
    (Hill's equation): |tr M| < 2 for the monodromy matrix M of the linear
    first-order system over one period (:func:`pendulab.numerics.monodromy.traces_along`,
    DOP853 at rtol 1e-13, one integration per omega0/omega row along a/l);
    det M = 1 since the linear system has zero trace.
    """
    import numpy as np
    import warnings

    from pendulab.analyses.floquet import is_stable
    from pendulab.errors import AccuracyWarning

    n_c, n_w, n_a = spec.shape
    if index is None:
        index = np.arange(spec.cells)
    rest = np.asarray(index) % (n_w * n_a)
    i, j = np.divmod(rest, n_a)
    _eqs, form = _stages(spec.system)
    if form.kind != "mathieu":
        return _monodromy_map(spec)[i, j]
    # a build asks for the verdict of one grid a dozen times (each map, each pruned criterion)
    key = (spec.system, spec.a_over_l, spec.w0_over_w, rest.tobytes())
    stages = _stages(spec.system)
    if key not in _VERDICTS or _VERDICTS[key][0] is not stages:
        pair = mathieu_pair(spec.system)
        t0, t1 = pair(np.asarray(spec.a_over_l)[j], np.asarray(spec.w0_over_w)[i])
        with warnings.catch_warnings():
            # on the source's grids some cells sit exactly on a curve (a/l = 0, omega0/omega = 0);
            # their verdict is that of is_stable's count, reported as such
            warnings.simplefilter("ignore", AccuracyWarning)
            verdict = is_stable(t0, t1)
        if len(_VERDICTS) >= 32:
            _VERDICTS.clear()
        _VERDICTS[key] = (stages, verdict)
    return _VERDICTS[key][1].copy()


#: (system, grid, cells) -> (its stages, Floquet verdict of those cells), kept per process
_VERDICTS = {}
#: (system, grid) -> (its stages, characteristic exponents on the grid: prune_plan), kept per process
_EXPONENTS = {}


_MONODROMY_MAPS = {}


def _monodromy_map(spec):
    """Bool (n_w, n_a): |tr M| < 2 on the grid of ``spec`` for a periodic non-Mathieu drive."""
    import numpy as np

    from pendulab.numerics.monodromy import traces_along

    key = (spec.system, spec.a_over_l, spec.w0_over_w)
    if key not in _MONODROMY_MAPS:
        _eqs, form = _stages(spec.system)
        fos = first_order_system(spec.system)
        if fos.period is None:
            raise InputError(f"criterion floquet: the drive gives a {form.kind} equation, which is "
                             "not periodic: there is no Floquet verdict")
        names = _param_columns(spec.system, fos)
        fixed = {"inertia_ratio": spec.system.inertia_ratio} if "inertia_ratio" in names else {}
        rows = []
        for w in spec.w0_over_w:
            tr = traces_along(fos, dict(fixed, w0_over_w=w), "a_over_l", spec.a_over_l)
            rows.append(np.abs(tr) < 2)
        _MONODROMY_MAPS[key] = np.array(rows, dtype=bool).reshape(len(spec.w0_over_w),
                                                                 len(spec.a_over_l))
    return _MONODROMY_MAPS[key]


# ---------------------------------------------------------------------------
# executors
# ---------------------------------------------------------------------------

def connect(address, timeout=CONNECT_TIMEOUT):
    """A distributed.Client for ``address``; one-line InputError if it cannot be reached."""
    try:
        from distributed import Client
    except ImportError:
        raise InputError("--dask needs dask.distributed: pip install 'pendulab[distributed]'") from None
    if not isinstance(address, str) or not address.strip():
        raise InputError(f"dask scheduler address must be text such as tcp://host:8786, got {address!r}")
    import logging
    quiet = [logging.getLogger(n) for n in ("distributed", "distributed.client", "distributed.comm")]
    levels = [lg.level for lg in quiet]
    for lg in quiet:
        lg.setLevel(logging.CRITICAL)
    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s "
                         f"({type(exc).__name__}: {reason[:120]})") from None
    finally:
        for lg, lv in zip(quiet, levels):
            lg.setLevel(lv)


def _progress(total, quiet, desc):
    if quiet or not getattr(sys.stderr, "isatty", lambda: False)() or not sys.stderr.isatty():
        return None
    from tqdm import tqdm
    return tqdm(total=total, unit="cell", desc=desc, file=sys.stderr, delay=PROGRESS_DELAY,
                leave=False, dynamic_ncols=True)


def run_tasks(spec, tasks, executor="serial", *, workers=None, client=None, backend="auto",
              quiet=False, callback=None):
    """Run chunk index arrays ``tasks`` of ``spec``; returns the list of chunk results (any order).

    ``callback(done_chunks, total_chunks, result)`` is called after each
    chunk (the tests use it to kill a Dask worker mid-sweep).
    """
    total_cells = int(sum(len(t) for t in tasks))
    bar = _progress(total_cells, quiet, f"sweep ({executor})")
    results = []

    def done(r):
        results.append(r)
        if bar is not None:
            bar.update(len(r["index"]))
        if callback is not None:
            callback(len(results), len(tasks), r)

    try:
        if executor == "serial":
            for t in tasks:
                done(run_chunk(spec, t, backend=backend))
        elif executor == "processes":
            import concurrent.futures as cf
            import multiprocessing as mp
            from pendulab.procs import die_with_parent
            n = workers or min(len(tasks), os.cpu_count() or 1)
            # one thread per process: the processes already use the cores; each worker dies
            # with this process, however it dies (pendulab.procs)
            with cf.ProcessPoolExecutor(max_workers=max(1, n), mp_context=mp.get_context("spawn"),
                                        initializer=die_with_parent,
                                        initargs=(os.getpid(),)) as pool:
                fos = first_order_system(spec.system)
                futures = [pool.submit(_chunk_task, (spec, t, backend, 1, fos)) for t in tasks]
                try:
                    for fut in cf.as_completed(futures):
                        done(fut.result())
                except cf.process.BrokenProcessPool as exc:
                    raise PendulabError(f"a sweep worker process died ({exc})") from None
        elif executor == "dask":
            from distributed import as_completed
            token = _token(spec, backend)
            keys = [f"pendulab-sweep-{token}-{k}" for k in range(len(tasks))]
            fos = first_order_system(spec.system)
            futures = client.map(_chunk_task, [(spec, t, backend, 1, fos) for t in tasks], key=keys,
                                 pure=False)
            try:
                for fut in as_completed(futures):
                    done(fut.result())
            finally:
                client.cancel(futures)
        else:
            raise InputError(f"executor must be one of {', '.join(EXECUTORS)}, got {executor!r}")
    finally:
        if bar is not None:
            bar.close()
    return results


def _token(spec, backend):
    import hashlib
    return hashlib.sha256(repr((spec, backend)).encode()).hexdigest()[:16]


def _auto_executor(spec, n_tasks, backend):
    """The executor of ``executor="auto"``: in this process for small sweeps (starting processes
    costs seconds: each one derives the system again) and whenever the C kernel runs (its threads
    already use every core); local processes for a large sweep on the NumPy path."""
    work = spec.cells * spec.periods * spec.steps_per_period
    if n_tasks < 2 or work < 2e7:
        return "serial"
    if backend != "numpy":
        from pendulab.numerics.integrate import c_kernel_available
        if c_kernel_available(first_order_system(spec.system)):
            return "serial"
    return "processes"


@dataclass
class SweepResult:
    """The outcome of :func:`sweep`.

    ``stable`` - bool array of ``spec.shape`` (initial condition, omega0/omega,
    a/l); ``stats`` - {statistic: array of that shape} (NaN where no
    trajectory ran); ``simulated`` - number of trajectories integrated;
    ``executor``, ``backends``, ``seconds`` - how it ran.
    """

    spec: SweepSpec
    stable: object
    stats: dict = field(default_factory=dict)
    simulated: int = 0
    executor: str = "serial"
    backends: tuple = ()
    seconds: float = 0.0
    note: str = ""

    @property
    def count(self):
        """Number of stable cells (per initial condition: ``counts``)."""
        return int(self.stable.sum())

    @property
    def counts(self):
        return [int(v) for v in self.stable.reshape(self.stable.shape[0], -1).sum(axis=1)]

    def stable_points(self, c=0):
        """[[a_over_l, w0_over_w], ...] of the stable cells of initial condition c, in index order."""
        import numpy as np
        ii, jj = np.nonzero(self.stable[c])
        return [[self.spec.a_over_l[j], self.spec.w0_over_w[i]] for i, j in zip(ii, jj)]

    def record(self, c=0):
        """A JSON-ready record of initial condition c (no timing, no executor: identical bytes)."""
        spec = self.spec
        th, om = spec.initial[c]
        return {
            "body": spec.system.describe(),
            "criterion": spec.criterion,
            "theta_init": th, "omega_init": om,
            "grid": [len(spec.a_over_l), len(spec.w0_over_w)],
            "periods": spec.periods, "steps_per_period": spec.steps_per_period,
            "linear": spec.linear,
            "count": int(self.stable[c].sum()),
            "stable": [[_round(a), _round(w)] for a, w in self.stable_points(c)],
            "simulated": self.simulated,
        }


def _round(v):
    return float(f"{v:.12g}")


def sweep(spec, *, executor="auto", workers=None, dask=None, backend="auto", quiet=False,
          callback=None, index=None):
    """Run ``spec`` and classify every cell (see the module docstring).

    ``dask`` - a scheduler address or a ``distributed.Client`` (forces the
    Dask executor); ``index`` - only these cells are integrated (the others
    stay NaN / unstable; :func:`pruned_sweep` uses it).
    """
    import numpy as np

    if executor not in EXECUTORS:
        raise InputError(f"executor must be one of {', '.join(EXECUTORS)}, got {executor!r}")
    start = time.perf_counter()
    shape = spec.shape
    if spec.criterion == "floquet":
        stable = floquet_verdict(spec).reshape(shape)
        return SweepResult(spec, stable, {}, 0, "none", (), time.perf_counter() - start,
                           "Floquet verdict of the linearised equation; no trajectory integrated")
    cells = np.arange(spec.cells) if index is None else np.unique(np.asarray(index, dtype=np.int64))
    if cells.size and (cells[0] < 0 or cells[-1] >= spec.cells):
        raise InputError(f"cell indices must lie in 0..{spec.cells - 1}")
    tasks = [cells[a:b] for a, b in chunks(len(cells), spec.chunk_size)]
    own_client = None
    if dask is not None:
        executor = "dask"
        client = dask
        if isinstance(dask, str):
            client = own_client = connect(dask)
    else:
        client = None
        if executor == "dask":
            raise InputError("executor 'dask' needs a scheduler address (dask=...)")
        if executor == "auto":
            executor = _auto_executor(spec, len(tasks), backend)
    # build the system here first: a bad scene fails once, in this process, before any worker starts
    first_order_system(spec.system)
    _param_columns(spec.system, first_order_system(spec.system))
    _time_step(spec)
    try:
        results = run_tasks(spec, tasks, executor, workers=workers, client=client, backend=backend,
                            quiet=quiet, callback=callback)
    finally:
        if own_client is not None:
            own_client.close()
    if index is None:
        out = assemble(spec.cells, results)
    else:
        part = assemble(len(cells), [dict(r, index=np.searchsorted(cells, r["index"])) for r in results])
        out = {k: np.full(spec.cells, np.nan) for k in STATS}
        for k in STATS:
            out[k][cells] = part[k]
        out["backends"] = part["backends"]
    stats = {k: out[k].reshape(shape) for k in STATS}
    with np.errstate(invalid="ignore"):
        stable = verdict(spec.criterion, stats)
    return SweepResult(spec, stable, stats, len(cells), executor, tuple(out["backends"]),
                       time.perf_counter() - start)


# ---------------------------------------------------------------------------
# model only what the question needs
# ---------------------------------------------------------------------------

#: Largest estimated amplitude (rad) at which a Floquet-stable cell away from the
#: boundary is taken as stable without integrating it (bounded, mean).
SMALL_AMPLITUDE = 0.15
#: Default width (in grid steps) of the band around the Floquet boundary that is always integrated.
MARGIN = 2
#: Floquet-unstable cells of a resonance gap with a growth rate (per unit tau) below this are
#: integrated: there the nonlinear motion can stay bounded (on the 100 x 100 rod map with
#: (0.06, 0.01) every such bounded cell has mu < 0.25).
FLUTTER_MU = 0.5


def prune_plan(spec, margin=MARGIN, amplitude=None):
    """(predicted, simulate): the Floquet verdict and the cells whose nonlinear verdict it may not give.

    Both are bool arrays of ``spec.shape``.  The rule (docs/experiments.md):

    * every cell within ``margin`` grid steps (Chebyshev distance in the
      (omega0/omega, a/l) grid) of a cell with the other Floquet verdict is
      integrated: there the finite amplitude can move the boundary;
    * a Floquet-stable cell is integrated when the linear estimate of its
      amplitude, A = (1 + |theta1|) sqrt(theta(0)^2 + (theta'(0)/nu)^2) with nu
      the characteristic exponent (the slow frequency, 000 eq. 8), is not
      small: A >= 0.15 rad for ``bounded`` and ``mean``, (2/pi) A >= 0.05 (half
      the threshold) for ``mean-abs`` (the mean of |A cos| is (2/pi) A);
    * a Floquet-unstable cell in a resonance gap (exponent k + i mu, k >= 1)
      with mu < 0.5 is integrated: beyond the upper edge of the band the
      inverted position loses stability by period doubling and the nonlinear
      motion can settle on a bounded oscillation (amplitude ~0.9 rad there);
    * for ``mean`` every Floquet-unstable cell is integrated: a trajectory that
      falls and alternates rotation and oscillation can still have a small
      signed mean (the source's scattered circles, 000 sec. 4), which no linear
      model predicts;
    * every other cell takes the Floquet verdict.
    """
    import numpy as np
    import warnings

    from pendulab.analyses.floquet import exponent
    from pendulab.errors import AccuracyWarning

    if spec.criterion not in ("mean", "mean-abs", "bounded"):
        raise InputError("pruning applies to the criteria mean, mean-abs and bounded")
    kind = _stages(spec.system)[1].kind
    if kind != "mathieu":
        raise InputError("pruning needs Mathieu's equation (the Floquet exponents of (theta0, "
                         f"theta1) choose the cells integrated), and the drive gives a {kind} "
                         "equation, not Mathieu's: sweep without pruning")
    margin = _count(margin, "margin", 0, 1000)
    n_c, n_w, n_a = spec.shape
    F = floquet_verdict(spec, np.arange(n_w * n_a)).reshape(n_w, n_a)
    near = np.zeros_like(F)
    pad = np.pad(F, margin, mode="edge")
    for di in range(-margin, margin + 1):
        for dj in range(-margin, margin + 1):
            near |= pad[margin + di:margin + di + n_w, margin + dj:margin + dj + n_a] != F
    a, w = np.meshgrid(np.asarray(spec.a_over_l, float), np.asarray(spec.w0_over_w, float))
    t0, t1 = mathieu_pair(spec.system)(a, w)
    key = (spec.system, spec.a_over_l, spec.w0_over_w)
    stages = _stages(spec.system)
    if key not in _EXPONENTS or _EXPONENTS[key][0] is not stages:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AccuracyWarning)
            if len(_EXPONENTS) >= 32:
                _EXPONENTS.clear()
            _EXPONENTS[key] = (stages, exponent(t0, t1))
    lam = _EXPONENTS[key][1].copy()
    nu = np.abs(lam.real)
    # unstable in a resonance gap (Re lam = k >= 1, lam = k + i mu): beyond the upper edge of a
    # band the inverted position loses stability by period doubling and a bounded oscillation
    # of finite amplitude can take its place while the growth rate mu is small
    k = np.round(lam.real)
    flutter = (~F) & (k >= 1) & (np.abs(lam.real - k) < 1e-9) & (np.abs(lam.imag) < FLUTTER_MU)
    predicted = np.broadcast_to(F, spec.shape).copy()
    simulate = np.broadcast_to(near | flutter, spec.shape).copy()
    for c, (th, om) in enumerate(spec.initial):
        with np.errstate(divide="ignore", invalid="ignore"):
            amp = (1 + np.abs(t1)) * np.sqrt(th**2 + np.where(om == 0, 0.0, (om / nu))**2)
        amp = np.where(np.isfinite(amp), amp, np.inf)
        if spec.criterion == "mean-abs":
            big = 2 / math.pi * amp >= THRESHOLD / 2
        else:
            big = amp >= (SMALL_AMPLITUDE if amplitude is None else amplitude)
        simulate[c] |= F & big
        if spec.criterion == "mean":
            simulate[c] |= ~F
    return predicted, simulate


def pruned_sweep(spec, margin=MARGIN, **kwargs):
    """:func:`sweep` that integrates only the cells of :func:`prune_plan`; the rest take the Floquet verdict.

    Returns a :class:`SweepResult` whose ``simulated`` counts the trajectories
    integrated (``spec.cells - simulated`` were saved) and whose statistics
    are NaN in the cells not integrated.
    """
    import numpy as np

    predicted, simulate = prune_plan(spec, margin)
    index = np.flatnonzero(simulate.ravel())
    start = time.perf_counter()
    if index.size:
        res = sweep(spec, index=index, **kwargs)
        stable = np.where(simulate, res.stable, predicted)
        out = SweepResult(spec, stable, res.stats, res.simulated, res.executor, res.backends, 0.0)
    else:
        out = SweepResult(spec, predicted, {}, 0, "none", (), 0.0)
    out.seconds = time.perf_counter() - start
    out.note = (f"pruned: {out.simulated} of {spec.cells} trajectories integrated "
                f"({spec.cells - out.simulated} saved), the rest take the Floquet verdict")
    return out


def trajectory(spec, reference=False, backend="auto", max_evaluations=None):
    """One RK4 trajectory of the single cell of ``spec`` and its statistics.

    Returns {"tau": (steps+1,), "states": (steps+1, 2), "mean_theta",
    "mean_abs_theta", "max_abs_theta" (floats, over every step), "backend"};
    with ``reference`` also "reference" (DOP853 at rtol 1e-13 at the same
    tau) and "max_error_theta".  The reference is refused (InputError) when
    the RK4 run is no longer finite, and after ``max_evaluations`` right-hand
    side evaluations (see :func:`pendulab.numerics.integrate.reference_trajectory`).
    """
    import numpy as np

    from pendulab.numerics.integrate import reference_trajectory, rk4_trajectory

    if spec.cells != 1:
        raise InputError("trajectory needs a sweep spec with exactly one cell")
    fos = first_order_system(spec.system)
    y0, params = cell_arrays(spec, np.arange(1))
    steps = spec.periods * spec.steps_per_period
    out = rk4_trajectory(fos, y0[0], params[0], 0.0, _time_step(spec), steps, linear=spec.linear,
                         backend=backend)
    tau, states = np.asarray(out[0], float), np.asarray(out[1], float)
    # the statistics come from the ensemble integrator itself, so that they are the sweep's
    stats = run_chunk(spec, np.arange(1), backend=backend)
    rec = {"tau": tau, "states": states, "backend": stats["backend"],
           **{k: float(stats[k][0]) for k in STATS}}
    theta = states[:, 0]
    if reference:
        if not np.all(np.isfinite(states)):
            raise InputError("the RK4 trajectory overflowed (theta is no longer finite), so there "
                             "is nothing to compare with DOP853; use fewer periods or more steps "
                             "per period")
        ref = np.asarray(reference_trajectory(fos, y0[0], params[0], tau, linear=spec.linear,
                                              max_evaluations=max_evaluations), float)
        rec["reference"] = ref
        rec["max_error_theta"] = float(np.max(np.abs(ref[:, 0] - theta)))
    return rec
