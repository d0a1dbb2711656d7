"""The RK4 step of a driven-pivot run checked against the rates of the derived equation.

Classical RK4 applied to y' = lambda y multiplies y by the amplification polynomial
R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24, z = h lambda, at every step.  On the imaginary axis
|R(iy)| <= 1 exactly for |y| <= 2 sqrt(2) (Butcher, "Numerical Methods for Ordinary
Differential Equations", the stability region of the classical method; Hairer-Wanner II,
sec. IV.2); beyond it every oscillating mode grows.

The linearised equation the first-order system runs (:mod:`pendulab.numerics.model`) is
x'' + q(tau) x = 0, with q = -d(linear_rhs[1])/d(theta) read from the derivation, never
typed: for Mathieu's equation q = theta0 + 2 theta1 cos 2 tau (000 eq. 7) and max |q| =
|theta0| + 2|theta1|.  Frozen at one tau, its eigenvalues are +-sqrt(-q): the largest
|lambda| is sqrt(max |q|).  For the full equation dF/dtheta = -q(tau) cos(theta - theta*)
(theta* the inverted position), checked symbolically here, so |dF/dtheta| <= max |q| over
any motion and the same bound applies.

The rule (docs/certificates.md, "Step sizes of the integrators"), with h the step in tau:

* refused - h sqrt(max |q|) > 2 sqrt(2) (:data:`RK4_IMAGINARY_LIMIT`): at the tau where
  |q| is largest an oscillating mode is amplified at every step; max |q| is then the largest
  |q| on a grid of tau, a lower bound of the true max, so a refusal is never a false alarm;
  or h r >= 2 pi (:data:`ALIAS_LIMIT`), r the highest rate of q(tau) = sum of its harmonics
  cos(r tau), sin(r tau): the RK4 stages, h/2 apart, sample that harmonic at the Nyquist rate
  or below, and the run integrates an aliased drive (one step per period of the source's
  drive: a/l = 0.1, omega0/omega = 0.05 gives mean theta = -84 after 50 periods where the
  equation's is 0.19);
* inaccurate (a one-line warning, the run goes on) - h sqrt(max |q|) > :data:`WARN_RATE`
  with max |q| bounded from above (the grid maximum divided by 1 - r h_grid/2, Bernstein's
  inequality |q'| <= r max |q| for a trigonometric polynomial of highest rate r), or
  h r > :data:`WARN_DRIVE`: the step does not resolve the drive's highest harmonic
  cos(r tau) (the source's drive, r = 2: fewer than 13 steps per period).  Measured for
  a/l = 0.1, omega0/omega = 0.05 over 50 periods (``pendulab simulate ... --reference``):
  the largest |theta - theta_DOP853| is 5.2 at 2 steps per period (h r = pi), 0.83 at 6,
  0.11 at 8, 0.020 at 12 (h r = 0.52), 0.0026 at 20, 4.2e-6 at 100 (max |theta| = 0.42).

A harmonic counts where its coefficient at the cell is not zero (a/l = 0 has no drive).
"""

import math
from dataclasses import dataclass

from pendulab.errors import InputError

#: |R(iy)| <= 1 for |y| <= 2 sqrt(2): where RK4's stability region meets the imaginary axis
#: (Butcher; Hairer-Wanner II, sec. IV.2).
RK4_IMAGINARY_LIMIT = 2 * math.sqrt(2)
#: h r at or above this, r the highest rate of q(tau): the stages, h/2 apart, sample cos(r tau)
#: at two points per cycle or fewer (the Nyquist rate), so the integrator sees an aliased drive.
ALIAS_LIMIT = 2 * math.pi
#: h sqrt(max |q|) above this: the step is stable but coarse (warning).
WARN_RATE = 1.0
#: h r above this, r the highest rate of q(tau): the drive is under-resolved (warning).
WARN_DRIVE = 0.5
#: Grid points of tau per cycle of the highest harmonic at which |q| is evaluated (for
#: Mathieu's cos 2 tau the grid holds tau = 0 and pi/2, where |q| is largest: exact).
GRID_PER_CYCLE = 64
#: Cells whose |q| are evaluated together (memory: this x grid points floats).
CHUNK = 4096


@dataclass(frozen=True)
class StepCheck:
    """What :func:`check_step` found for a step ``dt`` over ``cells`` parameter points.

    ``rate`` is sqrt(max |q|) at the worst cell (grid maximum: a lower bound), ``rate_upper``
    its bound from above, ``harmonic`` the highest rate r of q in tau there, ``worst`` the
    parameters of that cell ({name: value}); ``unstable`` and ``inaccurate`` count the cells
    refused and warned about; ``period`` is the drive period in tau.
    """

    dt: float
    period: float
    rate: float
    rate_upper: float
    harmonic: float
    worst: dict
    cells: int
    unstable: int
    inaccurate: int

    @property
    def stiffness(self):
        """h sqrt(max |q|) at the worst cell (from the grid maximum)."""
        return self.dt * self.rate

    @property
    def aliased(self):
        """h r >= 2 pi at the worst cell: the drive's highest harmonic is not sampled."""
        return self.dt * self.harmonic >= ALIAS_LIMIT

    def _where(self):
        point = ", ".join(f"{k} = {v:.6g}" for k, v in self.worst.items())
        many = f"; {self.unstable or self.inaccurate} of {self.cells} cells" if self.cells > 1 else ""
        return f"at {point}{many}" if point else many.lstrip("; ")

    def _steps_for(self, product_limit, rate):
        return max(1, math.ceil(self.period * rate / product_limit * (1 + 1e-12)))

    def refusal(self, label):
        """The one-line problem of an unstable step, or None (``label`` names the option)."""
        if not self.unstable:
            return None
        # stable: period sqrt(max|q|) / S <= 2 sqrt(2); not aliased: period r / S < 2 pi
        need = max(self._steps_for(RK4_IMAGINARY_LIMIT, self.rate),
                   math.floor(self.period * self.harmonic / ALIAS_LIMIT * (1 + 1e-12)) + 1)
        why = []
        if self.stiffness > RK4_IMAGINARY_LIMIT:
            why.append(f"dtau*sqrt(max|q|) = {self.stiffness:.4g} > 2*sqrt(2) = "
                       f"{RK4_IMAGINARY_LIMIT:.4g} (RK4's stability limit on the imaginary axis; "
                       f"max|q| = {self.rate ** 2:.6g}, q(tau) the derived coefficient of the "
                       "linearised equation)")
        if self.aliased:
            why.append(f"dtau*r = {self.dt * self.harmonic:.4g} >= 2*pi for the drive's harmonic "
                       f"cos({self.harmonic:g} tau): the RK4 stages see an aliased drive")
        return (f"{label}: the RK4 step dtau = {self.dt:.6g} is unstable: {'; '.join(why)} "
                f"{self._where()}; ask for at least {need} steps per drive period")

    def warning(self, label):
        """The one-line warning of a stable but inaccurate step, or None."""
        if self.unstable or not self.inaccurate:
            return None
        need = max(self._steps_for(WARN_RATE, self.rate_upper),
                   self._steps_for(WARN_DRIVE, self.harmonic))
        drive = (f"; dtau*r = {self.dt * self.harmonic:.3g} for the drive's highest harmonic "
                 f"cos({self.harmonic:g} tau), limit {WARN_DRIVE:g}" if self.harmonic else "")
        return (f"warning: {label}: the RK4 step dtau = {self.dt:.6g} is stable but coarse "
                f"(dtau*sqrt(max|q|) <= {self.dt * self.rate_upper:.3g}, limit {WARN_RATE:g}"
                f"{drive} {self._where()}): the numbers may be far from the equation's; {need} "
                "or more steps per drive period resolve it")


_COEFFICIENTS = {}


def coefficient(fos):
    """(q, {rate r > 0: |amplitude| function}, r_max) of ``fos``'s linearised equation.

    q(tau, *params) is a NumPy function of -d(linear_rhs[1])/d(theta); refuses (InputError)
    a system whose full equation is not q(tau) sin-shaped about its inverted position (then
    |dF/dtheta| <= max |q| would not hold) or whose q is not a trigonometric polynomial.
    """
    key = id(fos)
    hit = _COEFFICIENTS.get(key)
    if hit is not None and hit[0] is fos:
        return hit[1]
    import sympy as sp

    from pendulab.exprs import trig_spectrum
    from pendulab.numerics.model import DTHETA, THETA

    tau = fos.time
    q = -sp.diff(fos.linear_rhs[1], THETA)
    dFdtheta = sp.diff(fos.rhs[1], THETA)
    if (q.has(THETA, DTHETA) or sp.diff(fos.rhs[1], DTHETA) != 0
            or sp.simplify(dFdtheta + q * sp.cos(THETA - fos.about)) != 0):
        raise InputError("the RK4 step check needs theta'' = -q(tau) sin(theta - theta*); "
                         f"this system has theta'' = {fos.rhs[1]}")
    spectrum = trig_spectrum(q, tau)
    if spectrum is None or any(not r.is_number for r in spectrum):
        raise InputError(f"the RK4 step check needs a periodic coefficient; q(tau) = {q}")
    amplitudes = {}
    for r, c in spectrum.items():
        r = abs(float(r))
        if r > 0:
            amp = sp.Abs(sp.expand(c))
            amplitudes[r] = amplitudes.get(r, 0) + amp
    fns = {r: sp.lambdify(fos.params, a, "numpy") for r, a in amplitudes.items()}
    made = (sp.lambdify((tau, *fos.params), q, "numpy"), fns, max(fns, default=0.0))
    if len(_COEFFICIENTS) > 64:
        _COEFFICIENTS.clear()
    _COEFFICIENTS[key] = (fos, made)
    return made


#: Cycles of the highest harmonic per drive period beyond which an aliased step is refused
#: before the grid of q is built (a drive such as cos(10**60*omega*t)).
HUGE_CYCLES = 1e4


def check_step(fos, dt, params):
    """Check the RK4 step ``dt`` (in tau) of ``fos`` at the parameter rows ``params`` (n, k).

    Returns a :class:`StepCheck` (see the module docstring for the rule).
    """
    import numpy as np

    q, amplitudes, r_max = coefficient(fos)
    params = np.atleast_2d(np.asarray(params, float))
    n = params.shape[0]
    period = float(fos.period) if fos.period is not None else 2 * math.pi / max(r_max, 1.0)
    cycles = r_max * period / (2 * math.pi)   # of the highest harmonic in one drive period
    steps = period / dt
    if not math.isfinite(cycles) or (cycles > HUGE_CYCLES and cycles >= steps):
        # RK4's stages sample that harmonic below the Nyquist rate (the rule below), said
        # before a grid of GRID_PER_CYCLE points per cycle is built that would not fit in memory
        raise InputError(f"the drive's highest harmonic turns {cycles:.6g} times per drive "
                         f"period, and {steps:.6g} RK4 steps per period sample it below the "
                         f"Nyquist rate; ask for more than {cycles:.6g} steps per period, or "
                         "drop that harmonic")
    points = GRID_PER_CYCLE * max(1, round(cycles))
    grid = np.arange(points) * (period / points)
    maxq = np.empty(n)
    try:
        with np.errstate(all="ignore"):
            for s in range(0, n, CHUNK):
                cols = [params[s:s + CHUNK, j:j + 1] for j in range(params.shape[1])]
                vals = np.broadcast_to(q(grid[None, :], *cols),
                                       (len(cols[0]) if cols else 1, points))
                maxq[s:s + CHUNK] = np.max(np.abs(vals), axis=1)
            harmonic = np.zeros(n)
            for r, fn in amplitudes.items():
                amp = np.broadcast_to(np.asarray(fn(*params.T), float), (n,))
                harmonic = np.where(amp > 0, np.maximum(harmonic, r), harmonic)
            # Bernstein: max |q| <= grid max / (1 - r (grid step)/2) for rate r <= r_max
            upper = maxq / (1 - harmonic * (period / points) / 2)
    except (OverflowError, ValueError):  # a coefficient as large as 1e308 a (exact integers)
        raise InputError("the drive's coefficient q(tau) of the linearised equation is too "
                         "large for double precision here: the RK4 step cannot be checked "
                         "(a smaller amplitude or frequency)") from None
    rate, rate_upper = np.sqrt(maxq), np.sqrt(upper)
    unstable = (dt * rate > RK4_IMAGINARY_LIMIT) | (dt * harmonic >= ALIAS_LIMIT)
    inaccurate = ~unstable & ((dt * rate_upper > WARN_RATE) | (dt * harmonic > WARN_DRIVE))
    bad = unstable if unstable.any() else inaccurate
    # the worst cell: the largest h sqrt(max|q|) among the cells refused (else warned, else all)
    pool = np.nonzero(bad)[0] if bad.any() else np.arange(n)
    score = np.maximum(dt * rate_upper / WARN_RATE, dt * harmonic / WARN_DRIVE)
    if unstable.any():
        score = np.maximum(dt * rate / RK4_IMAGINARY_LIMIT, dt * harmonic / ALIAS_LIMIT)
    # ties (one harmonic for every cell) go to the larger sqrt(max|q|)
    k = int(pool[np.lexsort((rate[pool], score[pool]))[-1]])
    worst = {s.name: float(params[k, j]) for j, s in enumerate(fos.params)}
    return StepCheck(float(dt), period, float(rate[k]), float(rate_upper[k]), float(harmonic[k]),
                     worst, n, int(unstable.sum()), int(inaccurate.sum()))


def check_spec(spec):
    """:func:`check_step` for a sweep or trajectory spec (:class:`pendulab.numerics.sweep.SweepSpec`):
    every (a/l, omega0/omega) cell, the step period / steps_per_period."""
    import numpy as np

    from pendulab.numerics import sweep as S
    fos = S.first_order_system(spec.system)
    if fos.period is None:
        raise InputError("the drive is not periodic: the RK4 step needs a drive period")
    _, n_w, n_a = spec.shape
    _, params = S.cell_arrays(spec, np.arange(n_w * n_a))
    return check_step(fos, float(fos.period) / spec.steps_per_period, params)


def enforce(spec, label, warn=None):
    """Refuse an unstable step of ``spec`` (InputError naming ``label``); a coarse one is
    passed to ``warn`` (one line) when given.  Returns the :class:`StepCheck`."""
    found = check_spec(spec)
    refused = found.refusal(label)
    if refused:
        raise InputError(refused)
    said = found.warning(label)
    if said and warn is not None:
        warn(said)
    return found
