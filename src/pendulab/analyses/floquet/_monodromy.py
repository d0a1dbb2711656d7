"""Method "monodromy": Taylor integration of the fundamental matrix over half a period."""

from __future__ import annotations

import math

import mpmath

from pendulab.errors import ConvergenceError
from pendulab.analyses.floquet._inputs import _mp


def _monodromy_y(X0, X1, w):
    """cos(pi lam) = w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1 by a Taylor method at dps w.

    Returns (y, order)."""
    omega = math.sqrt(abs(float(X0)) + 2 * abs(float(X1))) + 2.0
    nsteps = max(1, int(math.ceil((math.pi / 2) * omega / 1.5)))
    growth = math.exp(omega * math.pi / 2) ** 2  # bound on |fundamental matrix|^2
    wl = w + int(math.log10(growth)) + 5
    K = 0  # largest Taylor order used (reported as the depth)
    with mpmath.workdps(wl):
        x0, x1 = _mp(X0), _mp(X1)
        h = mpmath.pi / 2 / nsteps
        h2 = h * h
        states = [[mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(0), mpmath.mpf(1)]]
        for step in range(nsteps):
            tau0 = step * h
            c, s = mpmath.cos(2 * tau0), mpmath.sin(2 * tau0)
            cyc = (c, -s, -c, s)
            # P_j = p_j h^(j+2): Taylor coefficients of theta0 + 2 theta1 cos(2 tau);
            # the series is extended until two successive terms of both
            # solutions fall below 10^-(wl+5) (a posteriori truncation)
            P = []
            tol = mpmath.mpf(10) ** (-(wl + 5))

            def coef(j):
                while len(P) <= j:
                    i = len(P)
                    f = mpmath.mpf(1)
                    for r in range(1, i + 1):
                        f = f * 2 * h / r
                    P.append(2 * x1 * f * cyc[i % 4] * h2 + (x0 * h2 if i == 0 else 0))
                return P[j]

            zs = [[y0, yp * h] for y0, yp in states]
            k = 0
            while True:
                for z in zs:
                    acc = mpmath.fsum(coef(j) * z[k - j] for j in range(k + 1))
                    z.append(-acc / ((k + 1) * (k + 2)))
                k += 1
                if k > 8 and all(abs(z[-1]) + abs(z[-2]) < tol * (1 + abs(z[0]) + abs(z[1]))
                                 for z in zs):
                    break
                if k > 100000:  # pragma: no cover
                    raise ConvergenceError("Taylor series of the monodromy did not converge")
            K = max(K, k + 2)
            new = []
            for z in zs:
                yv = mpmath.fsum(z)
                ypv = mpmath.fsum(i * z[i] for i in range(1, len(z))) / h
                new.append([yv, ypv])
            states = new
        wI, wIp = states[0]
        wII, wIIp = states[1]
        y = 2 * wI * wIIp - 1
    with mpmath.workdps(w):
        return +y, K
