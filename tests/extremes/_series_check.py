"""The residual of the truncated series (000 eqs. 20-21) in Mathieu's equation (000 eq. 7),
formed here from the equation, not from pendulab's recursion (tests only)."""

from fractions import Fraction


def residual(s, nu, top):
    """{(p, k): coefficient of theta1^p cos((nu + 2k) tau)} of the residual, p <= top."""
    alpha = {n: s.alpha_raw[n].evaluate(nu) for n in range(1, top + 1)}
    C = {0: {0: Fraction(1)}}
    for n in range(1, top + 1):
        C[n] = {k: v.evaluate(nu) for k, v in s.c_raw[n]}
    R = {}
    for p in range(1, top + 1):
        ks = set(C[p]) | {k + 1 for k in C[p - 1]} | {k - 1 for k in C[p - 1]}
        for m in range(2, p + 1):
            ks |= set(C[p - m])
        for k in ks:
            r = (nu * nu - (nu + 2 * k) ** 2) * C[p].get(k, 0)
            r += sum((alpha[m] * C[p - m].get(k, 0) for m in range(2, p + 1)), Fraction(0))
            r += alpha[1] * C[p - 1].get(k, 0)
            r += C[p - 1].get(k - 1, 0) + C[p - 1].get(k + 1, 0)
            R[(p, k)] = r
    return R
