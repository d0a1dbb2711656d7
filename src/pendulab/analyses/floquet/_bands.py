"""Band counting for 000 eq. 7: depth rules and Sturm counts of the characteristic values.

The number of characteristic values a_n, b_n below theta0 (DLMF 28.4.5-28.4.8,
four symmetric tridiagonal matrices) fixes the band: odd inside a stable band,
even in an instability gap.  The depth rules say how far the matrices and the
continued-fraction tails must reach for a given number of digits.
"""

from __future__ import annotations

import math

import mpmath

from pendulab.errors import ConvergenceError


def _edge_index(theta0, theta1):
    """Smallest even m0 >= 2 beyond which |C_m| > 2|theta1| (tails are minimal)."""
    m = math.sqrt(max(float(theta0), 0.0) + 2.0 * abs(float(theta1))) + 2.0
    m0 = int(math.ceil(m))
    return m0 + (m0 % 2)


def _tail_steps(theta0, theta1, m0, digits):
    """Number of continued-fraction levels (step 2 in the frequency index) past m0
    after which the neglected tail is below 10**-digits.

    Each level multiplies the tail by about theta1^2 / (C_m C_{m+2}) (000 eq. 10),
    so the count follows from a running product of those ratios.
    """
    t0, t1 = float(theta0), abs(float(theta1))
    if t1 == 0.0:
        return 1
    logsum, steps, m = 0.0, 0, m0
    target = -digits * math.log(10.0)
    while logsum > target:
        c1 = abs(t0 - m * m)
        c2 = abs(t0 - (m + 2) * (m + 2))
        logsum += 2.0 * math.log(t1) - math.log(c1) - math.log(c2)
        steps += 1
        m += 2
        if steps > 10 ** 6:  # pragma: no cover - unreachable for finite input
            raise ConvergenceError("continued-fraction tail did not converge")
    return steps + 2


# ---------------------------------------------------------------------------
# Sturm counts of the characteristic values (DLMF 28.4.5-28.4.8)
# ---------------------------------------------------------------------------

def _family_diagonals(family, q, n, one):
    """Diagonal and squared off-diagonal of the symmetric tridiagonal matrix whose
    eigenvalues are a_{2j} ("a_even"), a_{2j+1} ("a_odd"), b_{2j+1} ("b_odd") or
    b_{2j+2} ("b_even"), truncated to n rows (DLMF 28.4.5-28.4.8; the a_even
    matrix is symmetrised by scaling A_0 by sqrt 2)."""
    if family == "a_even":
        d = [one * (2 * j) ** 2 for j in range(n)]
        e2 = [q * q * (2 if j == 0 else 1) for j in range(n - 1)]
    elif family == "a_odd":
        d = [one * (2 * j + 1) ** 2 for j in range(n)]
        d[0] = d[0] + q
        e2 = [q * q for _ in range(n - 1)]
    elif family == "b_odd":
        d = [one * (2 * j + 1) ** 2 for j in range(n)]
        d[0] = d[0] - q
        e2 = [q * q for _ in range(n - 1)]
    elif family == "b_even":
        d = [one * (2 * j + 2) ** 2 for j in range(n)]
        e2 = [q * q for _ in range(n - 1)]
    else:  # pragma: no cover
        raise AssertionError(family)
    return d, e2


FAMILIES = ("a_even", "a_odd", "b_odd", "b_even")


def _sturm_count(d, e2, x):
    """Number of eigenvalues < x of the symmetric tridiagonal (d, e2) (LDL^T inertia)."""
    count = 0
    p = d[0] - x
    tiny = mpmath.mpf(2) ** (-mpmath.mp.prec - 20) if isinstance(x, mpmath.mpf) else 1e-300
    for i in range(len(d)):
        if i:
            p = d[i] - x - e2[i - 1] / p
        if p == 0:
            p = -tiny
        if p < 0:
            count += 1
    return count


def _edge_count(theta0, theta1, w):
    """Number of characteristic values a_n, b_n (all n) below theta0, at dps w."""
    q = -theta1
    m0 = _edge_index(theta0, theta1)
    n = m0 // 2 + _tail_steps(theta0, theta1, m0, w) + 2
    one = mpmath.mpf(1)
    total = 0
    for fam in FAMILIES:
        d, e2 = _family_diagonals(fam, q, n, one)
        total += _sturm_count(d, e2, theta0)
    return total
