"""Inputs and guards of the Floquet analysis: exact numbers, dps and size checks.

Numbers given as text or fractions stay exact (:func:`_exact`) and are
rounded afresh at every working precision (:func:`_mp`).  The size
S = |theta0| + 2|theta1| bounds the work of every method (``SIZE_LIMITS``).
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

import mpmath

from pendulab.errors import InputError


METHODS = ("hill", "cf", "monodromy", "arb")

from pendulab.analyses.floquet._precision import GUARD  # noqa: E402,F401  (the one guard rule)
#: precision used when ``dps=None`` (the result is then returned as float/complex)
DOUBLE_DPS = 16
MAX_DPS_LIMIT = 20000

#: Largest size S = |theta0| + 2|theta1| each method accepts.  The work of all
#: three grows with sqrt(S) (cf: block and tail length; hill: number of truncated
#: determinants and the Richardson guard digits; monodromy: Taylor steps and the
#: growth digits).  Measured in double precision (one run, 2-core machine):
#: hill 1.8 s at S = 2e6 (theta1 = 1e6), 9.7 s at S = 8e6; cf 3.2 s at S = 2e4,
#: 6.1 s at S = 3e4, and a PrecisionError after 18 s at S = 2e5; monodromy
#: 3.5 s at S = 2e3, 10 s at S = 6e3, 41 s at S = 2e4.
SIZE_LIMITS = {"hill": 4e6, "cf": 3e4, "monodromy": 5e3, "arb": 3e4}
#: The same bound for the characteristic values (S = 2|q|), the stability limits
#: (S = 4 ratio^2) and the vectorised functions (the largest S of the arrays).
SIZE_LIMIT = 4e6


_DEC = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def _exact(x, name):
    """Return ``x`` as an exact number (Fraction or mpf), or raise InputError.

    Strings may be decimals ("-0.002", "1e-3") or fractions ("1/5"); they are
    kept exact so that they can be rounded afresh at every working precision.
    """
    if isinstance(x, bool):
        raise InputError(f"{name} must be a real number, not a bool")
    if isinstance(x, (int, Fraction)):
        return Fraction(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            raise InputError(f"{name} must be finite, got {x!r}")
        return Fraction(x)
    if isinstance(x, mpmath.mpf):
        if not mpmath.isfinite(x):
            raise InputError(f"{name} must be finite, got {x}")
        return x
    if isinstance(x, str):
        from pendulab.limits import fraction
        try:
            val = fraction(x)
        except ValueError as exc:
            reason = "" if str(exc).startswith("not a") else f" ({exc})"
            raise InputError(f"{name} must be a real number such as -0.002 or 1/5, "
                             f"got {x[:60]!r}{reason}") from None
        except ZeroDivisionError:
            raise InputError(f"{name} must be a real number such as -0.002 or 1/5, "
                             f"got {x[:60]!r} (division by zero)") from None
        return val
    try:  # numpy scalars, sympy numbers
        import numbers
        if isinstance(x, numbers.Rational):
            return Fraction(int(x.numerator), int(x.denominator))
        if isinstance(x, numbers.Real):
            return _exact(float(x), name)
    except (TypeError, ValueError):
        pass
    raise InputError(f"{name} must be a real number, got {type(x).__name__} {x!r}")


def _mp(v):
    """An exact value rounded to the current mpmath precision."""
    if isinstance(v, Fraction):
        if v.denominator == 1:
            return mpmath.mpf(v.numerator)
        return mpmath.mpf(v.numerator) / v.denominator
    return +v


def _check_dps(dps, name="dps"):
    if dps is None:
        return None
    if isinstance(dps, bool) or not isinstance(dps, int):
        raise InputError(f"{name} must be a positive integer or None, got {dps!r}")
    if dps < 1 or dps > MAX_DPS_LIMIT:
        raise InputError(f"{name} must be between 1 and {MAX_DPS_LIMIT}, got {dps}")
    return dps


def _size_text(v, above=None):
    """Short text of an exact value that may be far beyond the float range.

    With ``above`` (a limit that ``v`` exceeds) the text has as many digits (3 to 30) as
    it takes to read as more than the limit: 4000000.5, not 4.0e+6 next to 4e+06.
    """
    for digits in range(3, 31):
        with mpmath.workdps(digits + 5):
            text = mpmath.nstr(_mp(v), digits)
            if above is None or mpmath.mpf(text) > above:
                return text
    return text + " (just above)"


def _check_size(X0, X1, limit, what, names=("theta0", "theta1")):
    """InputError when S = |X0| + 2|X1| exceeds ``limit`` (exact comparison, so
    values beyond the float range such as 1e400 are refused, not overflowed)."""
    size = abs(X0) + 2 * abs(X1)
    if size > limit:
        raise InputError(f"|{names[0]}| + 2|{names[1]}| = {_size_text(size, limit)} is too large "
                         f"for {what} (limit {limit:g}; the work grows like its square root)")


def _is_zero(v):
    return v == 0


def _is_int_square(v):
    """Return k if the exact value v equals k**2 for an integer k >= 0, else None."""
    if isinstance(v, Fraction):
        if v.denominator != 1 or v < 0:
            return None
        k = math.isqrt(v.numerator)
        return k if k * k == v.numerator else None
    if v < 0 or not mpmath.isint(v):
        return None
    k = math.isqrt(int(v))
    return k if k * k == int(v) else None

def _is_array(x):
    """True for inputs the vectorised routines take (numpy arrays, lists, tuples)."""
    import numpy as np
    return isinstance(x, (np.ndarray, list, tuple))
