"""Exact Floquet analysis of Mathieu's equation in the source's form.

The linearised inverted pendulum in dimensionless time is (000 eq. 7)

    theta'' + (theta0 + 2 theta1 cos 2 tau) theta = 0,

which is DLMF 28.2.1, w'' + (a - 2 q cos 2z) w = 0, with a = theta0 and
q = -theta1.  With the Floquet ansatz theta = exp(i lam tau) sum_n b_n
exp(2 i n tau) (000 eq. 8) the coefficients obey (000 eqs. 9-10)

    theta1 b_{n-1} + C_n b_n + theta1 b_{n+1} = 0,   C_n = theta0 - (2n + lam)^2,

and lam is DLMF's characteristic exponent nu (DLMF 28.2.16-28.2.17).  The
coefficient has period pi in tau, so the Floquet multipliers are
exp(+- i pi lam) and the trace of the monodromy matrix is 2 cos(pi lam)
(DLMF 28.2.21: cos(pi nu) = w_I(pi)).

Conventions used throughout
---------------------------
* lam is the *unfolded* exponent: in the k-th stable band (k = 0, 1, ...)
  lam is real in (k, k + 1); in the k-th instability gap lam = k + i mu with
  mu > 0; below a_0 lam = i mu.  With theta1 = 0 this gives lam = sqrt(theta0)
  exactly (imaginary for theta0 < 0).
* The band index comes from counting the characteristic values (a_n and b_n
  of all orders, DLMF 28.2(v)) below theta0 with a Sturm sequence on the four
  tridiagonal matrices of DLMF 28.4.5-28.4.8: an odd count means the interior
  of a stable band, an even count an instability gap.
* Every method computes u = (lam - e)^2 for the nearest band edge e (an
  integer), which is a well-conditioned quantity even when lam sits at an
  edge; lam = e +- sqrt(u).  u > 0: stable, u < 0: unstable.

Routes (``method=``)
--------------------
"arb"       (the default when dps is given) ball arithmetic, module ``_arb``: the
            band by Sturm counts of the infinite DLMF 28.4 matrices decided on
            balls, u by Newton on the "cf" function (one kernel for floats and
            balls, in the algebra a + b t, t^2 = u), proved by a sign change with
            the continued-fraction tails enclosed; ``certified_digits`` says how
            many digits of lam are proved.  mathieu_a/b, first_band and the
            limits have the same route (method "arb"; "mpmath" is the route below).

The three independent mpmath methods:
"cf"        the source's continued fractions (000 sec. 2.2): the recurrence is
            closed by the minimal-solution continued fractions on both sides
            of a central block and the determinant of that block, an even
            function of lam - e, is solved for u.
"hill"      Hill's determinant (Whittaker & Watson sec. 19.42, after dividing
            row n by (2n + s)^2 - theta0): cos(pi lam) = cos(pi s)
            + Delta_s (cos(pi sqrt(theta0)) - cos(pi s)), where Delta_s is the
            normalised infinite determinant.  s = 0 gives the classical
            sin^2(pi lam/2) = Delta(0) sin^2(pi sqrt(theta0)/2); s = 1 is used
            when theta0 is near an even square, where the s = 0 normalisation
            divides by zero.  The truncated determinants converge only
            algebraically (error ~ N^-3), so the limit is taken by Richardson
            extrapolation in the truncation depth N.
"monodromy" integrates the even and odd solutions over half a period with a
            Taylor method at the working precision and uses
            w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1 (a consequence of the even,
            pi-periodic coefficient; DLMF 28.2(iv)).

Precision: one rule for every route (``_precision.autoprec``): start at
dps + 10 digits, double the digits beyond dps, up to ``max_dps`` (default
4 dps + 60).  The mpmath routes compute each answer at two working
precisions and accept it when they agree to the digits asked; the arb route
accepts it when its proof succeeds.  Otherwise
:class:`~pendulab.errors.PrecisionError` is raised (one line).

Layout (one module per method, on the model of scipy.integrate._ivp)
-------------------------------------------------------------------
``_inputs``      exact inputs, dps and size guards, the constants
``_bands``       depth rules and Sturm counts of the characteristic values
``_cf``          method "cf"
``_hill``        method "hill"
``_monodromy``   method "monodromy"
``_exponent``    characteristic_exponent: from y or u to lam, verdict, precision loop
``_charvalues``  mathieu_a, mathieu_b, first_band
``_inverse``     theta0_of_exponent
``_vectorised``  exponent, is_stable, trace_monodromy on arrays (double precision)
``_arb``         method "arb": certified exponent, characteristic values, first band
``_precision``   autoprec, the one adaptive-precision rule

The inverted pendulum's limits and map (stability_limits, map_limits,
stability_map, map_stability) read the canonical stage through a
ParameterMap and live in :mod:`pendulab.analyses.stability_map`; they are
re-exported here.
"""


from pendulab.analyses.floquet._charvalues import first_band, mathieu_a, mathieu_b
from pendulab.analyses.floquet._exponent import FloquetResult, characteristic_exponent
from pendulab.analyses.floquet._inputs import (  # noqa: F401  (_check_size, _exact: commands)
    METHODS, SIZE_LIMIT, SIZE_LIMITS, _check_size, _exact,
)
from pendulab.analyses.floquet._inverse import theta0_of_exponent
from pendulab.analyses.floquet._vectorised import exponent, is_stable, trace_monodromy

__all__ = [
    "FloquetResult",
    "characteristic_exponent",
    "theta0_of_exponent",
    "mathieu_a",
    "mathieu_b",
    "stability_limits",
    "is_stable",
    "trace_monodromy",
    "stability_map",
    "map_stability",
    "map_limits",
    "first_band",
    "exponent",
    "METHODS",
    "SIZE_LIMITS",
    "SIZE_LIMIT",
]

_PENDULUM = ("stability_limits", "map_limits", "stability_map", "map_stability")


def __getattr__(name):
    # the pendulum's limits and map import this package, so they are fetched lazily
    if name in _PENDULUM:
        from pendulab.analyses import stability_map
        return getattr(stability_map, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
