"""The one adaptive-precision rule of the Floquet analysis (on the model of mpmath's autoprec).

Every multiprecision answer of the package (the exponent by each route, the
characteristic values, the first band and the inverse) is computed by
:func:`autoprec` at a sequence of working precisions given by one rule:

* guard digits: the first working precision is ``want + GUARD`` decimal digits;
* comparison: an mpmath route is computed at two precisions w and w + ``STEP``
  and accepted when the caller's test passes (they agree to the digits asked);
  the ball-arithmetic route (``two=False``) is computed once per precision and
  accepted when its proof succeeds;
* growth: w -> max(w + STEP, 2 w - want), i.e. the digits beyond ``want``
  double, up to the ceiling;
* range: from ``want + GUARD`` up to ``max_dps`` (default :func:`default_max_dps`,
  4 want + 60); ``want`` itself lies in 1 .. ``MAX_DPS_LIMIT``.

When the ceiling is reached, the caller's ``exhausted`` hook decides (the
exponent reports a point on a curve there); otherwise
:class:`~pendulab.errors.PrecisionError` is raised with one line.
"""

from __future__ import annotations

from pendulab.errors import PrecisionError

#: extra decimal digits carried beyond the precision asked for
GUARD = 10
#: offset of the second working precision of a two-precision comparison
STEP = 12


def default_max_dps(want):
    """Ceiling of the working precision when the caller gives none: 4 want + 60."""
    return 4 * want + 60


def precisions(want, max_dps, reach=STEP):
    """The working precisions w (decimal digits) tried for ``want`` digits, in order.

    w0 = want + GUARD, then w -> max(w + STEP, 2 w - want), capped so that
    w + reach <= max_dps (reach = STEP when a second precision w + STEP is
    computed beside w, 0 for the ball-arithmetic route); at least w0 is tried.
    """
    w = want + GUARD
    while True:
        yield w
        if w + reach + STEP > max_dps:
            return
        w = min(max(w + STEP, 2 * w - want), max_dps - reach)


def autoprec(compute, want, max_dps=None, accept=None, exhausted=None, what="the answer",
             two=True):
    """Run ``compute(w)`` at growing working precisions until the answer is accepted.

    two=True (mpmath routes): ``a = compute(w)``, ``b = compute(w + STEP)``;
    ``accept(a, b, w + STEP)`` true ends the loop with ``(b, w + STEP)``.
    two=False (ball arithmetic): ``r = compute(w)``; ``r is not None`` ends the
    loop with ``(r, w)``.  At the ceiling ``exhausted(a, b, w2)`` (two=True) or
    ``exhausted(w)`` returns the result or raises; without it a one-line
    PrecisionError names ``what``.
    """
    if max_dps is None:
        max_dps = default_max_dps(want)
    last = None
    for w in precisions(want, max_dps, STEP if two else 0):
        if two:
            a = compute(w)
            b = compute(w + STEP)
            if accept(a, b, w + STEP):
                return b, w + STEP
            last = (a, b, w + STEP)
        else:
            r = compute(w)
            if r is not None:
                return r, w
            last = (w,)
    if exhausted is not None:
        return exhausted(*last)
    raise PrecisionError(f"{what} not resolved to {want} digits within {last[-1]} working "
                         f"digits (max_dps={max_dps})")


def agree(a, b, want):
    """True when the mpmath numbers (or equal-length tuples of them) a and b agree to
    10^-(want + 2) relative (absolute below 1); call inside a workdps of the finer one."""
    import mpmath

    tol = mpmath.mpf(10) ** (-(want + 2))
    if isinstance(a, tuple):
        return all(abs(x - y) <= tol * max(1, abs(y)) for x, y in zip(a, b))
    return abs(a - b) <= tol * max(1, abs(b))
