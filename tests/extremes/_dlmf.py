"""Reference formulas typed from DLMF for the extremes tests (not pendulab code).

DLMF 28.8.1 (Mathieu characteristic values for large q = h^2, s = 2m + 1):
a_m(h^2) ~ b_{m+1}(h^2) ~ -2h^2 + 2sh - (s^2+1)/8 - (s^3+3s)/(2^7 h)
  - (5s^4+34s^2+9)/(2^12 h^2) - (33s^5+410s^3+405s)/(2^17 h^3)
  - (63s^6+1260s^4+2943s^2+486)/(2^20 h^4) - (527s^7+15617s^5+69001s^3+41607s)/(2^25 h^5).
Each term is about 1/h of the one before at h = 100 (checked on a_0(1e4) and
a_0(4e4): the residual falls by ~h per term), so the error after the eight terms is
below a tenth of the last one.

DLMF 28.8.2: b_{m+1}(h^2) - a_m(h^2) ~ (2^{4m+5}/m!) sqrt(2/pi) h^{m+3/2} e^{-4h}
  (1 - (6m^2+14m+7)/(32h) + O(h^-2)).

DLMF 10.21.19 (McMahon), a = (k + nu/2 - 1/4) pi, mu = 4 nu^2:
j_{nu,k} ~ a - (mu-1)/(8a) - 4(mu-1)(7mu-31)/(3(8a)^3)
  - 32(mu-1)(83mu^2-982mu+3779)/(15(8a)^5)
  - 64(mu-1)(6949mu^3-153855mu^2+1585743mu-6277237)/(105(8a)^7).
"""

import mpmath


def large_q_terms(m, q):
    """The eight terms of DLMF 28.8.1 at the current mpmath precision."""
    h, s = mpmath.sqrt(mpmath.mpf(q)), 2 * m + 1
    return [-2 * h ** 2, 2 * s * h, -mpmath.mpf(s * s + 1) / 8,
            -(s ** 3 + 3 * s) / (2 ** 7 * h),
            -(5 * s ** 4 + 34 * s ** 2 + 9) / (2 ** 12 * h ** 2),
            -(33 * s ** 5 + 410 * s ** 3 + 405 * s) / (2 ** 17 * h ** 3),
            -(63 * s ** 6 + 1260 * s ** 4 + 2943 * s ** 2 + 486) / (2 ** 20 * h ** 4),
            -(527 * s ** 7 + 15617 * s ** 5 + 69001 * s ** 3 + 41607 * s) / (2 ** 25 * h ** 5)]


def large_q(m, q):
    """(DLMF 28.8.1 to eight terms, a bound on its error: a tenth of the last term)."""
    t = large_q_terms(m, q)
    return mpmath.fsum(t), abs(t[-1]) / 10


def band_width(m, q):
    """DLMF 28.8.2 with its first correction: b_{m+1}(q) - a_m(q)."""
    h = mpmath.sqrt(mpmath.mpf(q))
    lead = mpmath.mpf(2) ** (4 * m + 5) / mpmath.factorial(m) * mpmath.sqrt(2 / mpmath.pi) \
        * h ** (m + mpmath.mpf(3) / 2) * mpmath.exp(-4 * h)
    return lead * (1 - (6 * m * m + 14 * m + 7) / (32 * h))


def mcmahon(nu, k):
    """DLMF 10.21.19 to five terms; the next term is O((8a)^-9)."""
    mu = 4 * mpmath.mpf(nu) ** 2
    a = (k + mpmath.mpf(nu) / 2 - mpmath.mpf(1) / 4) * mpmath.pi
    e = 8 * a
    return (a - (mu - 1) / e - 4 * (mu - 1) * (7 * mu - 31) / (3 * e ** 3)
            - 32 * (mu - 1) * (83 * mu ** 2 - 982 * mu + 3779) / (15 * e ** 5)
            - 64 * (mu - 1) * (6949 * mu ** 3 - 153855 * mu ** 2 + 1585743 * mu - 6277237)
            / (105 * e ** 7))
