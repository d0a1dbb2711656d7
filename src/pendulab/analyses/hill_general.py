"""Hill's determinant for a periodic coefficient with several harmonics.

The canonical stage writes a periodic drive as Hill's equation
(:class:`pendulab.canonical.PeriodicForm`, ``fourier``)

    theta'' + P(tau) theta = 0,   P(tau) = A_0 + sum_{k>=1} (A_k cos k tau + B_k sin k tau),

with period T in tau (pi when only even k occur, 2 pi otherwise).  With
d = 2 pi/T and P = sum_j c_j exp(i d j tau) (c_0 = A_0, c_{+-j} = (A_{dj} -+ i
B_{dj})/2), the Floquet ansatz theta = exp(i rho tau) sum_n b_n exp(i d n tau)
gives the infinite system

    (c_0 - (rho + d n)^2) b_n + sum_{j != 0} c_j b_{n-j} = 0.

Dividing row n by c_0 - (rho + d n)^2 gives a matrix with unit diagonal whose
determinant D(rho) converges absolutely (Whittaker & Watson, sec. 19.42, for
the even case; Magnus & Winkler, *Hill's Equation*, sec. 2.3, for complex
Fourier coefficients).  D is even in rho (the transpose of the matrix at -rho,
indices reversed, is the matrix with c_j -> c_{-j}, and det(I + N C) =
det(I + C N)), periodic with period d, has simple poles at rho = +-sigma + d n
(sigma = sqrt(c_0)), vanishes at the Floquet exponents and tends to 1 as
Im rho -> infinity.  Hence D(rho) - 1 = K/(cos(T rho) - cos(T sigma)), and
eliminating K with rho = s gives Hill's relation

    cos(T lam) = cos(T s) + D(s) (cos(T sigma) - cos(T s)),     tr M = 2 cos(T lam),

which for Mathieu's equation (d = 2, T = pi, c_{+-1} = theta1) is the relation
used by :func:`pendulab.analyses.floquet.characteristic_exponent` ("hill";
s = 0 gives W&W's sin^2(pi lam/2) = D(0) sin^2(pi sqrt(theta0)/2)).  s is 0
or d/2, whichever keeps every c_0 - (s + d n)^2 farthest from 0.

The truncated determinants D_N (|n| <= N) converge like N^-3; D is taken as
the Richardson extrapolation over N0, 2 N0, 4 N0, 8 N0 removing the N^-3,
N^-4 and N^-5 terms, and the same extrapolation from 2 N0 .. 16 N0 is the
convergence check (its difference is reported as ``error``).  Double
precision (NumPy determinants); about 1e-10 relative to max(1, |trace|) for
moderate coefficients.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pendulab.errors import ConvergenceError, InputError

__all__ = ["HillTrace", "hill_trace", "numeric_fourier"]


@dataclass(frozen=True)
class HillTrace:
    """tr M of theta'' + P(tau) theta = 0 from Hill's determinant (module docstring).

    trace     2 cos(T lam) (float)
    stable    |trace| < 2
    error     difference of two extrapolations (the convergence check)
    depth     largest truncation N used
    period    T
    shift     s
    """

    trace: float
    stable: bool
    error: float
    depth: int
    period: float
    shift: float


def numeric_fourier(fourier, values):
    """{k: (A_k, B_k)} as floats, with ``values`` ({Symbol: number}) substituted."""
    import sympy as sp

    out = {}
    for k, (A, B) in fourier.items():
        pair = []
        for c in (A, B):
            v = sp.sympify(c).subs(values)
            if not v.is_number:
                raise InputError(f"hill_trace: the Fourier coefficient {c} still has "
                                 f"symbols {sorted(map(str, v.free_symbols))}")
            pair.append(float(v))
        out[int(k)] = tuple(pair)
    return out


def _coefficients(fourier, period):
    T = float(period)
    d_float = 2 * math.pi / T
    d = int(round(d_float))
    if d < 1 or abs(d - d_float) > 1e-12:
        raise InputError(f"hill_trace: the period must be 2 pi/d for an integer d, got {period}")
    c = {}
    for k, (A, B) in fourier.items():
        k = int(k)
        if k < 0:
            raise InputError(f"hill_trace: harmonic numbers must be >= 0, got {k}")
        if k == 0:
            c[0] = complex(A)
            continue
        if k % d:
            raise InputError(f"hill_trace: harmonic {k} is not periodic with period {period}")
        j = k // d
        c[j] = complex(A, -B) / 2
        c[-j] = complex(A, B) / 2
    c.setdefault(0, 0j)
    return c, d, T


def _det(c, d, s, N):
    """det of the normalised Hill matrix truncated to |n| <= N (banded LU, LAPACK gbtrf)."""
    import numpy as np
    from scipy.linalg import lapack

    n = np.arange(-N, N + 1)
    size = 2 * N + 1
    real = all(v.imag == 0 for v in c.values())
    diag = (c[0].real if real else c[0]) - (s + d * n) ** 2
    band = min(max(abs(j) for j in c), size - 1)
    kl = ku = band
    # LAPACK band storage: ab[kl + ku + i - j, j] = M[i, j]
    ab = np.zeros((2 * kl + ku + 1, size), dtype=float if real else complex)
    ab[kl + ku, :] = 1.0
    for j, cj in c.items():
        if j == 0 or cj == 0 or abs(j) > band:
            continue
        rows = np.arange(max(0, j), min(size, size + j))
        ab[kl + ku + j, rows - j] = (cj.real if real else cj) / diag[rows]
    lu, piv, info = (lapack.dgbtrf if real else lapack.zgbtrf)(ab, kl, ku)
    if info < 0:  # pragma: no cover
        raise ConvergenceError(f"hill_trace: LAPACK gbtrf failed (info {info})")
    u = lu[kl + ku, :]
    swaps = int(np.count_nonzero(piv != np.arange(size)))
    return float((np.prod(u) * (-1) ** swaps).real)


def _extrapolate(values):
    T = list(values)
    for p in (3, 4, 5):
        fac = 2.0 ** p
        T = [(fac * T[i + 1] - T[i]) / (fac - 1) for i in range(len(T) - 1)]
    return T[0]


def hill_trace(fourier, period):
    """Trace of the monodromy matrix of theta'' + P(tau) theta = 0 by Hill's determinant.

    ``fourier``: {k: (A_k, B_k)} numbers (P as in the module docstring; the
    canonical stage's ``PeriodicForm.fourier`` after :func:`numeric_fourier`);
    ``period``: T in tau (pi or 2 pi).  Returns a :class:`HillTrace`.

    >>> import math
    >>> r = hill_trace({0: (-0.01, 0.0), 2: (0.4, 0.0)}, math.pi)   # theta0 = -0.01, theta1 = 0.2
    >>> round(r.trace, 9), r.stable
    (1.901005301, True)
    """
    c, d, T = _coefficients(fourier, period)
    c0 = c[0]
    if abs(c0.imag) > 0:
        raise InputError("hill_trace: the constant term A_0 must be real")
    x0 = c0.real
    size = abs(x0) + 2 * sum(abs(v) for j, v in c.items() if j)
    if size > 1e5:
        raise InputError(f"hill_trace: |A_0| + sum |A_k| + |B_k| = {size:.3g} is too large "
                         "for the double-precision determinant (limit 1e5)")

    # every n with (s + d n)^2 up to beyond |x0|: the zero of c_0 - (s + d n)^2 may lie at
    # any n up to sqrt(|x0|)/d (above 200 for d = 1 within the size limit)
    reach = int(math.sqrt(abs(x0)) / d) + 2

    def gap(s):
        return min(abs(x0 - (s + d * n) ** 2) for n in range(-reach, reach + 1))

    s = max((0.0, d / 2), key=gap)
    jmax = max(abs(j) for j in c)
    N0 = 2 * int(math.ceil(math.sqrt(size))) + 24 + 2 * jmax
    dets = [_det(c, d, s, N0 * 2 ** i) for i in range(5)]
    D1, D2 = _extrapolate(dets[:4]), _extrapolate(dets[1:])
    if x0 >= 0:
        cs = math.cos(T * math.sqrt(x0))
    else:
        cs = math.cosh(T * math.sqrt(-x0))
    cref = math.cos(T * s)
    y1 = cref + D1 * (cs - cref)
    y2 = cref + D2 * (cs - cref)
    if not (math.isfinite(y1) and math.isfinite(y2)):
        raise ConvergenceError("hill_trace: the determinant overflowed")
    error = 2 * abs(y2 - y1)
    if error > 1e-6 * max(1.0, abs(y2)):
        raise ConvergenceError(f"hill_trace: the truncated determinants did not converge "
                               f"(two extrapolations differ by {error:.2g})")
    trace = float(2 * y2)
    return HillTrace(trace, bool(abs(trace) < 2), float(error), N0 * 16, T, float(s))
