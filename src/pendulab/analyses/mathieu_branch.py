"""Branch points of the characteristic values a_m(q), b_m(q), and the radii of their series.

The power series of a_m(q) and b_m(q) in q (DLMF 28.6) converge in the disc
|q| < rho reaching to the nearest singularity of the function on its own
sheet.  a_m and b_m are eigenvalues of the Hill matrix of their parity class
(:func:`pendulab.analyses.series.parity_rows`, DLMF 28.4), analytic in q
except where two eigenvalues of the class meet: a double eigenvalue at a
complex q (DLMF 28.7; Meixner, Schaefke and Wolf 1980, sec. 2.4).  There the
determinant D(a, q) of the (truncated) matrix minus a and its a-derivative
vanish together,

    D(a, q) = 0,    dD/da (a, q) = 0,

and the two eigenvalues behave like a_b +- c sqrt(q - q_b): a square-root
branch point.  D and its derivatives come from the three-term continuant of
the rows (f_i = (s_i^2 + q V_ii - a) f_{i-1} - q^2 W_i f_{i-2}, differentiated
row by row), and Newton's iteration on the 2x2 system (Jacobian
[[D_a, D_q], [D_aa, D_aq]], regular at a square-root branch point since
D_q != 0 and D_aa != 0 there) refines a start to the branch point.

Starts.  Nothing typed in: the exact coefficients c_k of the series itself
(:func:`pendulab.analyses.series.characteristic_series`) carry the nearest
singularities.  In x = q^2 (a_{2n}, b_{2n+2}: even functions of q) or x = q
(a_{2n+1}, b_{2n+1}), c_k ~ sum_j A_j x_j^(-k) k^(-3/2) for the dominant
square-root singularities x_j (Darboux), so a linear recurrence of order 4
fitted by least squares to k^(3/2) c_k over the last half of the coefficients
has the 1/x_j among its characteristic roots (Prony's method).  Each root
gives a start q; the double value a comes from following a_m along the ray
from 0 to just short of that q (eigenvalues of the truncated matrix, nearest
to the extrapolated path) and averaging it with its nearest neighbour there.

Sheet.  A branch point of the class is a singularity of a_m only if a_m
itself is one of the two eigenvalues that meet there: :func:`branch_point`
follows a_m along the ray to (1 - 1e-4) q_b and requires it to be one of the
two eigenvalues nearest to a_b, which are much closer to each other than to
the next one.  The radius is the smallest |q_b| among the branch points that
pass, and the one returned passes :func:`check_branch_point` too.  Where they
lie (the representative with Im q > 0, and Re q >= 0 for the even functions;
the class is symmetric under q -> conj q, and a_{2n}, b_{2n+2} under q -> -q,
while b_{2n+1}(q) = a_{2n+1}(-q)): a_0 and a_2 meet at q = +-1.46876861378514 i,
b_2 and b_4 at +-6.92895475876018 i, a_1 and a_3 at 1.93139250938531 +-
3.23763841114711 i (b_1 and b_3 at its mirror image); for larger m the nearest point leaves the imaginary axis
(a_4 and a_2 at 5.1742 + 5.1042 i) or stays on it (a_6: 16.4712 i), the
table in docs/series.md lists each.

Accuracy.  The branch point is computed at two truncations (N rows, then 2N)
and two working precisions (digits + 10, digits + 22); the radius is returned
only when both agree to digits + 2 significant digits, and is then rounded to
the digits asked (:attr:`BranchPoint.text`).  :func:`check_branch_point` is
the certificate's checker: it refuses a candidate whose Newton correction is
larger than 10^-digits of it or whose two nearest eigenvalues are apart.

>>> p = branch_point("a0", digits=12)
>>> p.text, mpmath.nstr(p.q, 12), mpmath.nstr(p.a.real, 12)     # DLMF Table 28.6.1: 1.46876 86138
('1.46876861379', '(0.0 + 1.46876861379j)', '2.08869890275')
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import mpmath

from pendulab.errors import ConvergenceError, InputError
from pendulab.analyses.series import characteristic_series, parity_rows

__all__ = ["BranchPoint", "branch_point", "check_branch_point", "kinds_of_row",
           "table_source", "TABLE_ROWS", "TABLE_DIGITS"]

#: rows n = 0 .. TABLE_ROWS - 1 of the shipped table (pendulab.analyses.mathieu_radii)
TABLE_ROWS = 16
#: significant digits of the shipped radii
TABLE_DIGITS = 15
#: highest m accepted (the exact series that gives the starts grows with m)
MAX_M = 64

_EPS_SHEET = 1e-4      # a_m is followed to (1 - _EPS_SHEET) q_b


class BranchPoint(NamedTuple):
    """The nearest branch point of a_m or b_m: ``q`` (mpc; the representative with
    Im q > 0, and Re q >= 0 for a_{2n}, b_{2n+2}), ``a`` the double eigenvalue there, ``radius`` = |q| (mpf),
    ``text`` the radius to ``digits`` significant digits, ``size`` the rows of the
    truncated matrix that gave it (2 ``size`` confirmed it)."""
    kind: str
    q: object
    a: object
    radius: object
    text: str
    digits: int
    size: int

    def _repr_latex_(self):
        """q, the double eigenvalue a and the radius |q| as one ``align*`` for a notebook (the
        numbers at ``digits`` digits, as :func:`pendulab.analyses.floquet_format.number_text`
        writes them; the radius is ``text``)."""
        from pendulab.analyses.floquet_format import number_text
        from pendulab.latex import align, gather, number_rows, number_tex, text
        letter, m = self.kind[0], self.kind[1:]
        rows = (number_rows("q", number_tex(number_text(self.q, self.digits)))
                + number_rows("a", number_tex(number_text(self.a, self.digits)))
                + [r"|q| &= " + self.text])
        note = (text("branch point of ") + f"{letter}_{{{m}}}(q)" + text(" nearest to 0: the radius of "
                "convergence of its series"))
        return align(rows) + "\n" + gather([note, text(f"(matrix of {self.size} rows, "
                                                        f"confirmed with {2 * self.size})")])


def _check_digits(digits):
    if isinstance(digits, bool) or not isinstance(digits, int) or not 3 <= digits <= 200:
        raise InputError(f"digits must be an integer between 3 and 200, got {digits!r}")
    return digits


def _kind(kind):
    parity_rows(kind, 1)                     # validates the kind (InputError)
    letter, m = kind[0], int(kind[1:])
    if m > MAX_M:
        raise InputError(f"kind {kind!r}: branch points are computed for m <= {MAX_M}")
    return letter, m


def _size(m, q_abs):
    """Rows of the truncated matrix: past m's row by enough that s^2 >> |q| there."""
    return m // 2 + 2 + max(20, int(4 * math.sqrt(q_abs)) + 10)


def _continuant(rows, a, q, rescale=False):
    """D, D_a, D_aa, D_q, D_aq of det(D + qV - a) over ``rows`` (mpmath or Python complex).

    With ``rescale`` (double precision) the ten values carried are divided by a common
    factor after every row: the recurrence is linear and homogeneous in them, so the
    five results share one unknown factor, which the Newton step does not see."""
    f1, fa1, faa1, fq1, faq1 = 1, 0, 0, 0, 0
    f2 = fa2 = faa2 = fq2 = faq2 = 0
    q2 = q * q
    for c, v, w in rows:
        al = c + q * v - a
        be = q2 * w
        bq = 2 * q * w
        f = al * f1 - be * f2
        fa = -f1 + al * fa1 - be * fa2
        faa = -2 * fa1 + al * faa1 - be * faa2
        fq = v * f1 + al * fq1 - bq * f2 - be * fq2
        faq = -fq1 + v * fa1 + al * faq1 - bq * fa2 - be * faq2
        f2, fa2, faa2, fq2, faq2 = f1, fa1, faa1, fq1, faq1
        f1, fa1, faa1, fq1, faq1 = f, fa, faa, fq, faq
        if rescale:
            k = 1.0 / max(abs(f1), abs(fa1), abs(faa1), abs(fq1), abs(faq1), 1e-300)
            f1, fa1, faa1, fq1, faq1 = f1 * k, fa1 * k, faa1 * k, fq1 * k, faq1 * k
            f2, fa2, faa2, fq2, faq2 = f2 * k, fa2 * k, faa2 * k, fq2 * k, faq2 * k
    return f1, fa1, faa1, fq1, faq1


def _newton_step(rows, a, q, rescale=False):
    """The Newton correction (da, dq) of {D = 0, D_a = 0} at (a, q), and D, D_a, D_aa there."""
    f, fa, faa, fq, faq = _continuant(rows, a, q, rescale)
    det = fa * faq - fq * faa
    if det == 0:
        raise ConvergenceError("the Jacobian of {D = 0, dD/da = 0} vanishes")
    return (fq * fa - f * faq) / det, (faa * f - fa * fa) / det, (f, fa, faa)


def _newton(rows, a, q, digits, iterations=60):
    """Newton's iteration, in double precision first (to 1e-10) and then at the working
    precision until the correction is below 10^-digits."""
    a, q = complex(a), complex(q)
    for _ in range(iterations):
        try:
            da, dq, _ = _newton_step(rows, a, q, rescale=True)
        except (ConvergenceError, ZeroDivisionError, OverflowError):
            break
        a, q = a + da, q + dq
        if abs(dq) <= 1e-10 * abs(q) and abs(da) <= 1e-10 * max(1.0, abs(a)):
            break
    return _newton_mp(rows, mpmath.mpc(a), mpmath.mpc(q), digits, iterations)


def _newton_mp(rows, a, q, digits, iterations=30):
    tol = mpmath.mpf(10) ** (-digits)
    for _ in range(iterations):
        da, dq, _ = _newton_step(rows, a, q)
        a, q = a + da, q + dq
        if abs(dq) <= tol * abs(q) and abs(da) <= tol * max(1, abs(a)):
            return a, q
    raise ConvergenceError(f"Newton's iteration for the branch point did not converge near q = "
                           f"{mpmath.nstr(q, 8)}")


def _matrix(rows, q):
    """The truncated Hill matrix at q (complex symmetric, NumPy)."""
    import numpy as np
    n = len(rows)
    M = np.zeros((n, n), dtype=complex)
    for i, (c, v, w) in enumerate(rows):
        M[i, i] = c + q * v
        if i:
            M[i, i - 1] = M[i - 1, i] = q * math.sqrt(w)
    return M


def _logderivs(rows, a, q):
    """D_a / D and D_aa / D of det(D + qV - a) in double precision: the continuant of
    D, D_a, D_aa, rescaled whenever it grows or shrinks by 10^100 (it is linear and
    homogeneous in the six values it carries, so a common factor cancels from the
    ratios)."""
    f1, fa1, faa1, f2, fa2, faa2 = 1.0, 0.0, 0.0, 0.0, 0.0, 0.0
    q2 = q * q
    for c, v, w in rows:
        al = c + q * v - a
        be = q2 * w
        f = al * f1 - be * f2
        fa = -f1 + al * fa1 - be * fa2
        faa = -2.0 * fa1 + al * faa1 - be * faa2
        f2, fa2, faa2, f1, fa1, faa1 = f1, fa1, faa1, f, fa, faa
        size = abs(f1) + abs(fa1)
        if size > 1e100 or size < 1e-100:
            k = 1.0 / (size + abs(faa1))
            f1, fa1, faa1, f2, fa2, faa2 = f1 * k, fa1 * k, faa1 * k, f2 * k, fa2 * k, faa2 * k
    return fa1 / f1, faa1 / f1


def _follow(rows, m, q_end, steps=64):
    """a_m followed along the ray from 0 to ``q_end`` (double precision), and the
    matrix's eigenvalues at q_end.

    Each step starts Newton's iteration on D(a, q) = 0 from the linear extrapolation
    of the last two points; the step is halved until Newton converges and its total
    correction is under a quarter of the distance 2 |D_a / D_aa| to the nearest other
    eigenvalue (so that the path cannot jump to another eigenvalue).
    """
    import numpy as np
    row = next(i for i, r in enumerate(rows) if r[0] == m * m)
    prev, last, h_last = None, complex(rows[row][0]), 1.0
    t, h = 0.0, 1.0 / steps
    while t < 1.0:
        h = min(h, 1.0 - t)
        q = (t + h) * q_end
        guess = last if prev is None else last + (last - prev) * (h / h_last)
        a, da = guess, math.inf
        for _ in range(10):
            try:
                hd, kd = _logderivs(rows, a, q)
                da = -1.0 / hd
            except ZeroDivisionError:
                break
            a += da
            if abs(da) <= 1e-12 * max(1.0, abs(a)):
                break
        ok = False
        if abs(da) <= 1e-8 * max(1.0, abs(a)):       # converged (to rounding near a close pair)
            hd, kd = _logderivs(rows, a, q)
            gap = abs(2 * hd / kd) if kd else math.inf
            ok = abs(a - guess) < 0.25 * gap and abs(da) < 1e-3 * gap
        if not ok:
            if h < 1e-12:
                raise ConvergenceError(f"a_{m} could not be followed along the ray to q = {q_end:.6g}")
            h /= 2
            continue
        prev, last, h_last = last, a, h
        t += h
        h = min(2 * h, 1.0 / steps)
    return last, np.linalg.eigvals(_matrix(rows, q_end))


def _starts(letter, m):
    """Starts q for the nearest singularities of a_m or b_m, nearest first (module docstring)."""
    import numpy as np
    order = 160 + 4 * max(0, m - 16)
    c = characteristic_series(f"{letter}{m}", order).coefficients
    step = 2 if m % 2 == 0 else 1
    ks = list(range(step, order + 1, step))
    with mpmath.workdps(30):
        vals = [mpmath.mpf(c[k].numerator) / c[k].denominator for k in ks]
        tail = [abs(v) ** (-mpmath.mpf(step) / k) for v, k in zip(vals[-20:], ks[-20:]) if v]
        X0 = min(tail)
        u = [float(v * X0 ** (k // step) * mpmath.mpf(k // step) ** 1.5) for v, k in zip(vals, ks)]
    u = np.array(u)
    r, L = 4, len(u)
    W = L // 2
    A = np.array([[u[k - i] for i in range(1, r + 1)] for k in range(L - W, L)])
    coef, *_ = np.linalg.lstsq(A, u[L - W:], rcond=None)
    roots = np.roots(np.concatenate([[1.0], -coef]))
    out = []
    for z in roots:
        if abs(z) < 1e-3:
            continue
        x = float(X0) / complex(z)
        q = complex(np.sqrt(x + 0j)) if step == 2 else x
        q = complex(abs(q.real), abs(q.imag)) if step == 2 else complex(q.real, abs(q.imag))
        if all(abs(q - p) > 1e-6 * abs(q) for p in out):
            out.append(q)
    out.sort(key=abs)
    return out


def _representative(letter, m, q, a):
    """The symmetric image with Im q > 0 (and Re q >= 0 for the even functions of q)."""
    tiny = mpmath.mpf(10) ** (-(mpmath.mp.dps - 8)) * abs(q)
    if abs(q.real) < tiny:          # on the imaginary axis, to the working precision
        q, a = mpmath.mpc(0, q.imag), mpmath.mpc(a.real, 0) if abs(a.imag) < tiny else a
    # -q first (it changes the sign of Im q, a stays: the matrix at -q is similar to the one
    # at q), then the conjugate (Re q kept)
    if m % 2 == 0 and q.real < 0:
        q = -q
    if q.imag < 0:
        q, a = mpmath.conj(q), mpmath.conj(a)
    return q, a


def _refine(letter, m, q0, a0, digits):
    """Newton at N rows and dps digits + 10, then at 2N rows and dps digits + 22; the
    radius must agree to digits + 2 significant digits."""
    n = _size(m, abs(q0))
    kind = f"{letter}{m}"
    with mpmath.workdps(digits + 10):
        a1, q1 = _newton(parity_rows(kind, n), mpmath.mpc(a0), mpmath.mpc(q0), digits + 6)
    with mpmath.workdps(digits + 22):
        a2, q2 = _newton_mp(parity_rows(kind, 2 * n), a1, q1, digits + 14)
        if abs(abs(q2) - abs(q1)) > mpmath.mpf(10) ** (-(digits + 2)) * abs(q2):
            raise ConvergenceError(f"{kind}: the branch point near q = {mpmath.nstr(q2, 8)} changes "
                                   f"with the truncation or the precision beyond {digits} digits")
        return a2, q2, n


def _on_sheet(letter, m, q, a, n):
    """True when a_m followed along the ray arrives at one of the two eigenvalues meeting at q."""
    import numpy as np
    rows = parity_rows(f"{letter}{m}", n)
    end = complex(q) * (1 - _EPS_SHEET)
    value, vals = _follow(rows, m, end)
    d = np.abs(vals - complex(a))
    order = np.argsort(d)
    pair = vals[order[:2]]
    apart = abs(pair[0] - pair[1])
    third = d[order[2]] if len(vals) > 2 else float("inf")
    return bool(np.min(np.abs(pair - value)) < 1e-6 * max(1.0, abs(value)) and apart < 0.1 * third)


def _extrapolated(letter, m, digits):
    """A start from the branch points of m - 4, m - 8, m - 12 (same letter): the radii grow
    like m^2 and the points of one residue of m mod 4 lie on one smooth curve (docs/series.md),
    so the quadratic extrapolation 3 q_1 - 3 q_2 + q_3 (complex) lands near the next one."""
    if m - 12 < (0 if letter == "a" else 1):
        return []
    q1, q2, q3 = (complex(_branch(letter, m - k, digits).q) for k in (4, 8, 12))
    return [3 * q1 - 3 * q2 + q3]


def branch_point(kind, digits=15):
    """The branch point nearest to q = 0 on the sheet of a_m or b_m, to ``digits`` digits.

    ``kind`` is "a<m>" or "b<m>" (m <= MAX_M).  Returns a :class:`BranchPoint`;
    its ``radius`` is the radius of convergence of the series of ``kind`` in q
    (DLMF 28.6, Table 28.6.1 for m <= 19).  Raises ConvergenceError when no
    start converges to a branch point on the sheet.  Results are cached; for
    m >= 12 the kinds m - 4, m - 8, m - 12 are computed too (one start comes from
    them, :func:`_extrapolated`).
    """
    _check_digits(digits)
    letter, m = _kind(kind)
    return _branch(letter, m, digits)


@functools.lru_cache(maxsize=None)
def _branch(letter, m, digits):
    import numpy as np
    kind = f"{letter}{m}"
    best = None
    for q0 in sorted(_starts(letter, m) + _extrapolated(letter, m, digits), key=abs):
        if best is not None and abs(q0) > 1.25 * float(abs(best[1])):
            break
        rows = parity_rows(kind, _size(m, abs(q0)))
        try:
            value, vals = _follow(rows, m, q0 * 0.98)
        except ConvergenceError:        # the ray passes through a branch point
            continue
        others = vals[np.abs(vals - value) > 1e-9 * max(1.0, abs(value))]
        if not len(others):
            continue
        near = others[int(np.argmin(np.abs(others - value)))]
        try:
            a, q, n = _refine(letter, m, q0, (value + near) / 2, digits)
        except ConvergenceError:
            continue
        try:
            if not _on_sheet(letter, m, q, a, n):
                continue
        except ConvergenceError:
            continue
        if best is None or abs(q) < abs(best[1]):
            best = (a, q, n)
    if best is None:
        raise ConvergenceError(f"{kind}: no branch point on its sheet was found from the series' "
                               f"singularities")
    a, q, n = best
    with mpmath.workdps(digits + 22):
        q, a = _representative(letter, m, q, a)
        check_branch_point(kind, q, a, digits)
        radius = abs(q)
        text = mpmath.nstr(radius, digits, strip_zeros=False)
    return BranchPoint(kind, q, a, radius, text, digits, n)


def check_branch_point(kind, q, a, digits=15):
    """Refuse (ConvergenceError) a (q, a) that is not a branch point of kind's class to ``digits``.

    The candidate passes when, at N and 2N rows (N from |q|) and dps digits + 10,
    the Newton correction of {D = 0, dD/da = 0} is at most 10^-digits |q| in q and
    10^-digits max(1, |a|) in a, and the two roots of D(., q) nearest to a (from the
    quadratic D + D_a d + D_aa d^2 / 2) lie within 10^(-digits/2) max(1, |a|) of each
    other.  Returns the largest relative correction seen.
    """
    _check_digits(digits)
    letter, m = _kind(kind)
    worst = mpmath.mpf(0)
    with mpmath.workdps(digits + 10):
        q, a = mpmath.mpc(q), mpmath.mpc(a)
        if q == 0:
            raise ConvergenceError(f"{kind}: q = 0 is not a branch point (the eigenvalues m^2 are simple)")
        tol = mpmath.mpf(10) ** (-digits)
        n = _size(m, float(abs(q)))
        for size in (n, 2 * n):
            da, dq, (f, fa, faa) = _newton_step(parity_rows(kind, size), a, q)
            rel = max(abs(dq) / abs(q), abs(da) / max(1, abs(a)))
            worst = max(worst, rel)
            if rel > tol:
                raise ConvergenceError(
                    f"{kind}: (q, a) = ({mpmath.nstr(q, 10)}, {mpmath.nstr(a, 10)}) is not a branch "
                    f"point to {digits} digits: Newton's correction of {{D = 0, dD/da = 0}} is "
                    f"{mpmath.nstr(rel, 3)} of it at {size} rows")
            apart = 2 * abs(mpmath.sqrt(fa * fa - 2 * f * faa) / faa) if faa != 0 else mpmath.inf
            if apart > mpmath.mpf(10) ** (-digits / 2) * max(1, abs(a)):
                raise ConvergenceError(
                    f"{kind}: at q = {mpmath.nstr(q, 10)} the two eigenvalues nearest to "
                    f"a = {mpmath.nstr(a, 10)} are {mpmath.nstr(apart, 3)} apart, not double")
    return worst


def kinds_of_row(n):
    """The kinds whose radius is rho_n^(1), rho_n^(2), rho_n^(3) of DLMF Table 28.6.1:
    (a_{2n},), (b_{2n+2},), (a_{2n+1}, b_{2n+1})."""
    return (f"a{2 * n}",), (f"b{2 * n + 2}",), (f"a{2 * n + 1}", f"b{2 * n + 1}")


def table_source(rows=TABLE_ROWS, digits=TABLE_DIGITS):
    """The text of pendulab/analyses/mathieu_radii.py: every kind of rows 0 .. rows - 1."""
    kinds = sorted({k for n in range(rows) for col in kinds_of_row(n) for k in col},
                   key=lambda k: (k[0], int(k[1:])))
    lines = []
    for kind in kinds:
        p = branch_point(kind, digits)
        with mpmath.workdps(digits + 5):
            qt = f"{mpmath.nstr(p.q.real, digits)}+{mpmath.nstr(p.q.imag, digits)}j"
        lines.append(f'    "{kind}": ("{p.text}", "{qt}"),')
    body = "\n".join(lines)
    return f'''"""Radii of convergence of the series of a_m(q), b_m(q) in q (DLMF 28.6), computed.

Generated by `python -m pendulab.analyses.mathieu_branch` (pendulab.analyses.mathieu_branch.
table_source) from the branch points of the Hill matrices; do not edit.  Rows n = 0 .. {rows - 1}
of DLMF Table 28.6.1's layout: a_0 .. a_{2 * rows - 1}, b_1 .. b_{2 * rows}.
"""

#: significant digits of every radius below
DIGITS = {digits}
#: kind -> (radius |q_b|, nearest branch point q_b on the kind's sheet), decimal text
BRANCH_POINTS = {{
{body}
}}
'''


def _main(argv=None):
    import argparse
    import pathlib
    parser = argparse.ArgumentParser(prog="python -m pendulab.analyses.mathieu_branch",
                                     description="Write (or --check) pendulab/analyses/mathieu_radii.py.")
    parser.add_argument("--check", action="store_true", help="compare instead of writing")
    args = parser.parse_args(argv)
    path = pathlib.Path(__file__).with_name("mathieu_radii.py")
    text = table_source()
    if args.check:
        same = path.exists() and path.read_text() == text
        print(f"{path.name}: {'up to date' if same else 'differs from a fresh computation'}")
        return 0 if same else 1
    tmp = path.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(path)
    print(f"wrote {path.name}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(_main())
