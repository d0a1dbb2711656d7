"""Method "arb": the characteristic exponent of 000 eq. 7 proved in ball arithmetic.

theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0 (000 eq. 7) with the
recurrence theta1 b_{m-2} + C_m b_m + theta1 b_{m+2} = 0,
C_m = theta0 - (m + t)^2, m = 2n + e, t = lam - e (000 eqs. 8-10).

1. **Band** (:func:`band_count`): the number of characteristic values a_n, b_n
   below theta0 by the LDL^T pivots of the four infinite matrices of DLMF
   28.4.5-28.4.8, every pivot sign decided on balls (undecided: more
   precision).  The pivots are continued only until row n where
   d_{n+1} - theta0 >= 2|q| and p_n >= |q|: then every later pivot is >= |q|
   (p_i >= 2|q| - q^2/|q|), so the count of the first n rows is the count of
   the infinite matrix (each truncation past n has it, and the k-th eigenvalue
   of the truncations decreases to the k-th of the operator, Cauchy
   interlacing / min-max).  Odd count 2k+1: band k; even count 2k: gap k.
2. **Characteristic function** f_e(u) of u = t^2 (:func:`cf_kernel`): the
   block |m| <= M of the recurrence closed by T continued-fraction levels of
   the minimal solution on each side (the "cf" route, module ``_cf``),
   evaluated in the algebra a + b t with t^2 = u, i.e. in real arithmetic for
   either sign of u.  One kernel serves Python floats (the guess), and arb
   balls (Newton and the proof), with d/du carried alongside (forward mode).
3. **Guess** in plain floats: a safeguarded Newton iteration on the bracket of
   the "cf" route ((0, 1/4] next to edge k or k+1 inside band k; [-U, 0] in
   gap k).
4. **Newton** in arb at doubling precision from the guess.
5. **Proof**: f_e is evaluated on balls at u_lo < u_hi around the Newton
   root with the neglected tails enclosed: if |C_j| >= 2|theta1| for every
   j beyond the last level kept, every tail ratio b_{j+2}/b_j of the minimal
   solution lies in the closed unit disk (if |r_{j+2}| <= 1 then
   |C_j + theta1 r_{j+2}| >= |theta1|; the continued fraction converges by
   Sleszynski-Pringsheim and its value is the minimal ratio, Pincherle), and
   the disk is carried through the levels kept.  Strictly opposite signs at
   the two ends prove a root in [u_lo, u_hi]; it is the only one in
   (-inf, 1) because (-1)^e cos(pi sqrt(u)) is strictly monotone there and
   f_e(u) = 0 exactly when cos(pi (e + sqrt u)) = cos(pi lam).  The band
   count then fixes lam = k + sqrt(u) (e = k), k + 1 - sqrt(u) (e = k + 1) or
   k + i sqrt(-u) (gap, e = k), a ball; any other e is refused.
6. **Digits**: the ball of lam is printed to ``dps`` digits only when both ends
   round to the same decimal (:func:`pendulab.analyses.bessel_zeros.ball_digits`);
   otherwise the precision grows (:mod:`._precision`).
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

from flint import acb, arb, ctx, fmpq, fmpz

from pendulab.analyses.bessel_zeros import _Prec, ball_digits  # the one flint precision guard
from pendulab.analyses.floquet._bands import FAMILIES, _edge_index, _tail_steps
from pendulab.errors import ConvergenceError


def bits_of(digits):
    return int(math.ceil(digits * 3.3219280948873623)) + 8


def to_ball(v):
    """An exact input (Fraction or mpf) as an arb ball at the current precision (exact
    when representable, else a ball that contains it)."""
    if isinstance(v, Fraction):
        if v.denominator == 1:
            return arb(fmpz(v.numerator))
        return arb(fmpq(v.numerator, v.denominator))
    sign, man, exp, _ = v._mpf_
    b = arb(fmpz(int(man))) * arb(2) ** int(exp)
    return -b if sign else b


# ---------------------------------------------------------------------------
# 1. band count on balls
# ---------------------------------------------------------------------------

def _diag(family, i, q):
    if family == "a_even":
        return (2 * i) ** 2
    if family == "b_even":
        return (2 * i + 2) ** 2
    d = (2 * i + 1) ** 2
    if i == 0:
        return d + q if family == "a_odd" else d - q
    return d


_INF, _ZERO = object(), object()


def family_count(family, q, x):
    """Certified number of eigenvalues < x of the infinite DLMF 28.4 matrix of ``family``
    at q (balls), or None when a pivot sign is undecided at this precision.

    A pivot that is exactly 0 (x exactly a diagonal entry, exact inputs) is read
    as the limit x - 0: that pivot +0, the next one -inf, the one after
    d - x; the count of eigenvalues below x - eps equals the one below x for
    every small eps > 0."""
    aq = abs(q)
    q2 = q * q
    count = 0
    p = None          # previous pivot; "inf" after an exact zero
    i = 0
    while True:
        d = _diag(family, i, q)
        if i == 0 or p is _INF:
            p = d - x
        elif p is _ZERO:
            p = _INF       # -infinity: negative
            count += 1
            i += 1
            continue
        else:
            e2 = 2 * q2 if (family == "a_even" and i == 1) else q2
            p = d - x - e2 / p
        if p.is_zero():
            p = _ZERO
            i += 1
            continue
        if p < 0:
            count += 1
        elif not p > 0:
            return None
        if i >= 1 and p > aq and _diag(family, i + 1, 0) - x > 2 * aq:
            return count
        i += 1
        if i > 10 ** 6:
            # theta0 and theta1 within their ranges stop the count within a few thousand rows;
            # a count that runs on has lost its pivots (an undecided one taken as decided),
            # which is an error, not an undecided count
            raise ConvergenceError(f"the Sturm count of the {family} matrix at q = {q} did not "
                                   "stop within 10^6 rows")


def band_count(x0, x1):
    """Number of characteristic values below theta0 (balls x0, x1), or None if undecided."""
    q = -x1
    total = 0
    for fam in FAMILIES:
        c = family_count(fam, q, x0)
        if c is None:
            return None
        total += c
    return total


# ---------------------------------------------------------------------------
# 2. the characteristic function, one kernel for floats and balls
# ---------------------------------------------------------------------------

def cf_kernel(u, x0, x1, M, T, tails=None, deriv=True, rescale=False):
    """f_e(u) of the block m = -M, -M+2, ..., M (M = e mod 2) of 000 eq. 10 closed by
    T continued-fraction levels each side, in the algebra a + b t, t^2 = u.

    Arguments are all floats or all arb balls (M, T ints).  ``tails`` = None
    starts each tail at 0 (the truncated fraction); otherwise a pair
    ((ra, rb), (la, lb)) of algebra elements enclosing the neglected right and
    left ratios.  Returns (A, B, dA/du): the value of the block determinant is
    A + B t (B = 0 up to rounding for zero tails; for u < 0 the value is A).
    ``rescale`` divides the continuants by their size now and then (floats:
    only the ratio A/A' is used, and the products overflow beyond M ~ 100).
    """
    c0 = x0 - u
    zero = u * 0
    if tails is None:
        (ra, rb), (la, lb) = (zero, zero), (zero, zero)
    else:
        (ra, rb), (la, lb) = tails
    dra = drb = dla = dlb = zero
    x12 = x1 * x1

    # one level r <- -theta1 / (C_m + theta1 r), C_m = (theta0 - m^2 - u) - 2m t; the
    # inverse of D = Da + Db t is (Da - Db t)/n, n = Da^2 - Db^2 u
    for side, ms in ((0, range(M + 2 * T, M, -2)), (1, range(-M - 2 * T, -M, 2))):
        a, b, da, db = (ra, rb, dra, drb) if side == 0 else (la, lb, dla, dlb)
        for m in ms:
            Da = c0 - m * m + x1 * a
            Db = x1 * b - 2 * m
            n = Da * Da - Db * Db * u
            inv = 1 / n
            if deriv:
                dDa = x1 * da - 1
                dDb = x1 * db
                dn = 2 * (Da * dDa - Db * dDb * u) - Db * Db
                da = -x1 * (dDa - Da * dn * inv) * inv
                db = x1 * (dDb - Db * dn * inv) * inv
            a, b = -x1 * Da * inv, x1 * Db * inv
        if side == 0:
            ra, rb, dra, drb = a, b, da, db
        else:
            la, lb, dla, dlb = a, b, da, db

    # continuant p_j = d_j p_{j-1} - theta1^2 p_{j-2} over the block
    qa, qb, dqa, dqb = 1 + zero, zero, zero, zero      # p_{-1}
    pa = pb = dpa = dpb = None
    ms = range(-M, M + 1, 2)
    last = M
    for m in ms:
        da, db = c0 - m * m, -2 * m + zero
        dda, ddb = -1 + zero, zero
        if m == -M:
            da, db = da + x1 * la, db + x1 * lb
            dda, ddb = dda + x1 * dla, x1 * dlb
        if m == last:
            da, db = da + x1 * ra, db + x1 * rb
            dda, ddb = dda + x1 * dra, ddb + x1 * drb
        if pa is None:
            pa, pb, dpa, dpb = da, db, dda, ddb
            continue
        na = da * pa + db * pb * u - x12 * qa
        nb = da * pb + db * pa - x12 * qb
        if deriv:
            dna = (dda * pa + da * dpa + (ddb * pb + db * dpb) * u + db * pb - x12 * dqa)
            dnb = dda * pb + da * dpb + ddb * pa + db * dpa - x12 * dqb
        else:
            dna = dnb = zero
        qa, qb, dqa, dqb = pa, pb, dpa, dpb
        pa, pb, dpa, dpb = na, nb, dna, dnb
        if rescale:
            s = abs(pa) + abs(pb)
            if s > 1e100 or 0 < s < 1e-100:
                s = 1 / s
                pa, pb, dpa, dpb = pa * s, pb * s, dpa * s, dpb * s
                qa, qb, dqa, dqb = qa * s, qb * s, dqa * s, dqb * s
    return pa, pb, dpa


def cf_kernel_t(t, x0, x1, M, T, tails=None, deriv=True):
    """The same block determinant as :func:`cf_kernel` at real t (u = t^2 >= 0), in plain
    real arithmetic (about half the operations): returns (g(t), dg/dt); f_e(u) = g(t),
    df/du = g'(t)/(2t).  Used where t is not small (the band's Newton steps and the
    proof at u > 0); ``tails`` = (right, left) balls enclosing the neglected ratios."""
    zero = t * 0
    r, l = (zero, zero) if tails is None else tails
    dr = dl = zero
    x12 = x1 * x1
    for side, ms in ((0, range(M + 2 * T, M, -2)), (1, range(-M - 2 * T, -M, 2))):
        a, da = (r, dr) if side == 0 else (l, dl)
        for m in ms:
            s = m + t
            D = x0 - s * s + x1 * a
            if deriv:
                da = x1 * (x1 * da - 2 * s) / (D * D)
            a = -x1 / D
        if side == 0:
            r, dr = a, da
        else:
            l, dl = a, da
    q = dq = None
    p, dp = 1 + zero, zero
    for m in range(-M, M + 1, 2):
        s = m + t
        d, dd = x0 - s * s, -2 * s
        if m == -M:
            d, dd = d + x1 * l, dd + x1 * dl
        if m == M:
            d, dd = d + x1 * r, dd + x1 * dr
        if q is None:
            q, dq, p, dp = p, dp, d, dd
            continue
        p, q, dp, dq = d * p - x12 * q, p, (dd * p + d * dp - x12 * dq) if deriv else zero, dp
    return p, dp


def _depths(x0f, x1f, e, digits):
    return _depths_cached(x0f, x1f, e, int(digits) + 1)


@functools.lru_cache(maxsize=4096)
def _depths_cached(x0f, x1f, e, digits):
    """(M, T): block half-width (M = e mod 2, M >= edge index) and tail levels."""
    m0 = _edge_index(x0f, x1f)
    M = max(m0, e + 2)
    if (M - e) % 2:
        M += 1
    # the proof starts the tails from the unit disk, not from the fraction itself: a few
    # more levels than the truncation rule asks (measured: +22 digits at 1000)
    return M, _tail_steps(x0f, x1f, M, digits + 4 + digits / 30)


# ---------------------------------------------------------------------------
# 3. the double-precision guess
# ---------------------------------------------------------------------------

def loss_bits(x0f, x1f):
    """Bits the block continuant loses to cancellation, measured (one run) as about
    0.85 sqrt(S), S = |theta0| + 2|theta1|: 42 bits at S = 2e3, 87 at 2e4."""
    return int(math.sqrt(abs(x0f) + 2 * abs(x1f))) + 4


def _fvals(X0, X1, e, prec=None, depth_digits=18):
    """u -> (f_e(u), f_e'(u)) for the guess: in floats (prec None) or, when the
    continuant loses too many bits for floats, in arb at ``prec`` bits returning the
    floats (f/|f'|, sign f') -- the Newton step and the sign are all the guess uses."""
    x0f, x1f = float(X0), float(X1)
    M, T = _depths(x0f, x1f, e, depth_digits)
    if prec is None:
        def f(u):
            a, _, da = cf_kernel(float(u), x0f, x1f, M, T, rescale=True)
            return a, da
        return f
    with _Prec(prec):
        x0, x1 = to_ball(X0), to_ball(X1)

    def f(u):
        with _Prec(prec):
            a, _, da = cf_kernel(arb(u), x0, x1, M, T)
            if da == 0 or not (da > 0 or da < 0):
                return float(a.mid()), 0.0
            return float((a / abs(da)).mid()), (1.0 if da > 0 else -1.0)
    return f


def _safe_newton(f, lo, hi, flo, fhi, u0, iters=60):
    """Root of f in [lo, hi] (f(lo) f(hi) <= 0) by Newton steps kept inside the bracket
    (bisection otherwise).  f returns (value, derivative)."""
    u = u0 if lo < u0 < hi else 0.5 * (lo + hi)
    for _ in range(iters):
        fu, du = f(u)
        if fu == 0:
            return u
        if (fu > 0) == (flo > 0):
            lo, flo = u, fu
        else:
            hi = u
        step = fu / du if du != 0 else math.inf
        if abs(step) <= 1e-13 * abs(u) or hi - lo <= 1e-13 * max(abs(u), 1e-300):
            return u - step if lo <= u - step <= hi else u
        nu = u - step
        if not (lo < nu < hi) or not math.isfinite(nu):
            nu = 0.5 * (lo + hi)
        u = nu
    return u


def _plain_newton(f, u, lo, hi, iters=8):
    """Newton from u while the iterates stay in (lo, hi); the root or None."""
    last = math.inf
    for _ in range(iters):
        fu, du = f(u)
        if du == 0:
            return None
        step = fu / du
        u = u - step
        if not lo < u < hi:
            return None
        # ~40 correct bits are all the arb Newton needs; rounding noise of the float
        # continuant stops the steps from shrinking further
        if abs(step) <= 1e-13 * abs(u) or (abs(step) >= 0.5 * last and abs(step) < 1e-8 * abs(u)):
            return u
        last = abs(step)
    return None


def guess(X0, X1, count):
    """(e, u) in double precision for band count ``count`` (exact X0, X1).  Plain floats
    for S = |theta0| + 2|theta1| up to ~600; beyond, the same kernel in arb at
    53 + :func:`loss_bits` bits."""
    x0f, x1f = float(X0), float(X1)
    lost = loss_bits(x0f, x1f)
    prec = None if lost < 28 else 60 + lost

    def fv(e):
        return _fvals(X0, X1, e, prec)

    if count % 2 == 1:
        k = (count - 1) // 2
        for e in (k, k + 1):
            # plain Newton from the edge u = 0 first (the proof checks the answer)
            u = _plain_newton(fv(e), 0.0, 0.0, 0.3)
            if u is not None:
                return e, u
        for e in (k, k + 1):
            f = fv(e)
            (f0, d0), (fq, _) = f(0.0), f(0.25)
            if f0 == 0:
                return e, 0.0
            if (f0 > 0) != (fq > 0):
                u0 = -f0 / d0 if d0 else 0.125
                return e, _safe_newton(f, 0.0, 0.25, f0, fq, u0)
        # the root is at u <= 0 within rounding: next to the edge whose root is nearest 0
        best = None
        for e in (k, k + 1):
            f0, d0 = fv(e)(0.0)
            step = abs(f0 / d0) if d0 else math.inf
            if best is None or step < best[0]:
                best = (step, e)
        return best[1], 0.0
    k = count // 2
    f = fv(k)
    u = _plain_newton(f, 0.0, -1e12, 0.0)
    if u is not None:
        return k, u
    f0, d0 = f(0.0)
    if f0 == 0 or (d0 and abs(f0 / d0) < 1e-12):
        return k, 0.0   # within rounding of the edge: the arb Newton goes on from there
    U = 1.0
    fU, _ = f(-U)
    while (fU > 0) == (f0 > 0):
        U *= 4
        if U > 1e12:
            return k, 0.0
        fU, _ = f(-U)
    u0 = -f0 / d0 if d0 else -0.5 * U
    return k, _safe_newton(f, -U, 0.0, fU, f0, u0)


# ---------------------------------------------------------------------------
# 4.-5. Newton in arb and the proof
# ---------------------------------------------------------------------------

def _tail_ok(j, u, x0, x1):
    """|C_j| >= 2|theta1| for every frequency index >= j on both sides (balls), for u."""
    a1 = abs(x1)
    if u >= 0:
        t = u.sqrt().upper()
        return j > t and (j - t) ** 2 - x0 - 2 * a1 > 0
    s2 = -u
    return bool(j * j - x0 - s2 - 2 * a1 > 0 or j * j * s2 - x1 * x1 > 0)


def _value_ball(u, x0, x1, M, T):
    """Ball containing the exact f_e(u) at the exact point u (an arb), or None if the
    tail condition cannot be shown."""
    if not _tail_ok(M + 2 * T + 2, u, x0, x1):
        return None
    if u > 0 or u == 0:
        g, _ = cf_kernel_t(u.sqrt(), x0, x1, M, T, tails=(arb(0, 1), arb(0, 1)), deriv=False)
        return g
    # u < 0: t = i s; complex balls (the tail disk |r| <= 1 as a complex ball; in the
    # a + b t basis it would need |b| <= 1/s, wide next to an edge); f is the real part
    t = acb(0, (-u).sqrt())
    disk = acb(arb(0, 1), arb(0, 1))
    g, _ = cf_kernel_t(t, acb(x0), acb(x1), M, T, tails=(disk, disk), deriv=False)
    return g.real


def _log2(x):
    """About log2 of a positive arb bound (exponent arithmetic, no float overflow)."""
    man, exp = x.man_exp()
    man = int(man)
    return -10 ** 9 if man == 0 else int(exp) + man.bit_length()


_T_SMALL = 2.0 ** -20   # below it (t < 1e-3) the derivative in t loses too many digits


def _newton_steps(X0, X1, e, u, prec, x0f, x1f, ladder=True):
    """Newton on f_e from u at doubling precision up to ``prec`` bits.  Returns
    (u, last step, rounding uncertainty of u in bits) or None.

    The ladder halves the useful bits from ``prec`` down to ~100 (a double guess
    has ~50 correct bits); further steps at ``prec`` follow only when the last
    one was not already below half the digits."""
    extra = loss_bits(x0f, x1f)
    steps = []
    p = (prec - extra) // 2 + 8
    while ladder and p > 100:
        steps.append(p + extra)
        p = p // 2 + 8
    steps.reverse()
    delta = lost = dA = None

    def step(bits, u, dA):
        with _Prec(bits + 16):
            x0, x1 = to_ball(X0), to_ball(X1)
            M, T = _depths(x0f, x1f, e, bits / 3.32 + 2)
            um = u.mid()
            if um > _T_SMALL:
                # t = sqrt(u) not small: real arithmetic in t, df/du = g'(t)/(2t)
                t = um.sqrt()
                A, dg = cf_kernel_t(t, x0, x1, M, T)
                dA = dg / (2 * t)
            elif um < -_T_SMALL:
                # t = i sqrt(-u): complex balls, f = Re g(t), df/du = Re g'(t)/(2t)
                t = acb(0, (-um).sqrt())
                g, dg = cf_kernel_t(t, acb(x0), acb(x1), M, T)
                A, dA = g.real, (dg / (2 * t)).real
            else:
                A, _, dA = cf_kernel(um, x0, x1, M, T)
            if dA == 0 or not A.is_finite() or not dA.is_finite():
                return None
            delta = (A / dA).mid()
            lost = _log2(A.rad()) - _log2(abs(dA).abs_lower()) if A.rad() != 0 else None
            return (um - delta).mid(), delta, lost, dA

    for bits in steps:
        got = step(bits, u, None)
        if got is None:
            return None
        u, delta, lost, dA = got
    for k in range(4):
        got = step(prec, u, None)
        if got is None:
            return None
        u, delta, lost, dA = got
        with _Prec(prec + 16):
            # converged when this step is below half the digits (the next is below all)
            small = abs(delta) <= (abs(u) + arb(2) ** (-prec // 3)) * arb(2) ** (8 - (prec - extra) // 2)
        if small:
            break
    return u, delta, lost, abs(dA).abs_lower()


def is_tiny(u, digits):
    """True when the estimate u (float or arb) has |u| <= 10^-digits."""
    if u is None:
        return False
    with _Prec(64):
        return bool(abs(arb(u)).upper() <= arb(10) ** (-digits))


def certify(X0, X1, count, e, u0, want, info=None):
    """Certified lam ball (and u ball) for band ``count`` and edge e from the start u0
    (float or arb midpoint), at about ``want`` digits.  Returns (lam, u_ball, depth)
    with lam an arb (band) or the imaginary part mu (gap), or None when the proof fails
    at this precision (the caller raises the precision).

    The working precision is raised once within the call by the bits the
    continuant loses to cancellation (measured from the radius of f at the last
    Newton step), so that large |theta1| does not need a second attempt."""
    x0f, x1f = float(X0), float(X1)
    prec = bits_of(want) + loss_bits(x0f, x1f)
    band = count % 2 == 1
    u = arb(u0) if not isinstance(u0, arb) else u0
    target = None   # log2 of the uncertainty of u wanted: |u| 2^(16 - prec)
    for attempt in range(2):
        # a second attempt starts from a u already good to the first precision
        got = _newton_steps(X0, X1, e, u, prec, x0f, x1f, ladder=attempt == 0)
        if got is None:
            return None
        u, delta, lost, slope = got
        if info is not None:
            info["u"] = u
        with _Prec(prec + 16):
            um = u.mid()
            if um == 0:
                return None
            if target is None:
                target = _log2(abs(um).upper()) + 16 - prec
            if lost is not None and lost + 4 > target:
                # the continuant loses bits to cancellation (large |theta1|) or u is
                # tiny (next to an edge): raise the precision once by what is missing
                if attempt == 0:
                    prec += lost + 4 - target + 16
                    continue
                return None
            ad = abs(delta).upper()
            r0 = max(8 * ad * ad, arb(2) ** (target - 8 if lost is None else lost + 4))
        if not band:
            r0 = r0 * 256   # complex balls of the gap's proof are wider than the Newton's
        return _prove(X0, X1, count, e, band, um, ad, r0, prec, x0f, x1f, slope)
    return None


def _prove(X0, X1, count, e, band, um, ad, r0, prec, x0f, x1f, slope):
    """The sign-change proof around um: start half-width r0 (last Newton step ad, |f'|
    about ``slope``).  A ball f containing 0 widens the bracket to what its radius asks
    (16 rad / slope); if the bracket was that wide already, the tail is doubled once
    (the disk contracts more slowly than the fraction converges when |theta1| is
    large); equal signs at both ends (the root outside) widen it by 2^10.

    Only the edges the count names are read: f_e depends on e through its parity
    alone, so an edge k + 2 (or k - 1) has the same root and would turn it into
    k + 2 - sqrt(u), a number outside the band; such an e is refused (None)."""
    k = (count - 1) // 2 if band else count // 2
    if e not in ((k, k + 1) if band else (k,)):
        return None
    with _Prec(prec + 16):
        x0, x1 = to_ball(X0), to_ball(X1)
        M, T = _depths(x0f, x1f, e, prec / 3.32 + 2)
        T = T + T // 4 + 2
        r = r0
        doubled = False
        for _ in range(5):
            lo, hi = (um - r).lower(), (um + r).upper()
            if hi >= 1:
                return None
            if band and not lo > 0:
                return None
            if not band and not hi < 0:
                return None
            flo = _value_ball(arb(lo), x0, x1, M, T)
            fhi = _value_ball(arb(hi), x0, x1, M, T)
            if flo is None or fhi is None:
                return None
            if (flo > 0 and fhi < 0) or (flo < 0 and fhi > 0):
                U = arb(lo).union(arb(hi))
                if band:
                    t = U.sqrt()
                    lam = (count - 1) // 2 + t if e == (count - 1) // 2 else e - t
                    return lam, U, M // 2 + T
                return (-U).sqrt(), U, M // 2 + T
            if (flo > 0 or flo < 0) and (fhi > 0 or fhi < 0):
                r = max(r * 1024, 8 * ad)
                continue
            need = (16 * max(flo.rad(), fhi.rad()) / slope).upper() if slope > 0 else 1024 * r
            if need > r:
                r = need          # rounding: a wider bracket clears it
            elif not doubled:
                T, doubled = 2 * T, True   # the bracket was wide enough: the tail
            else:
                r = r * 1024
        return None


def to_mpf(x):
    """The midpoint of an arb as an mpmath mpf (exact: mantissa and exponent)."""
    import mpmath
    man, exp = x.mid().man_exp()
    return mpmath.mpf((int(man), int(exp)))


def multipliers(part, e, band, digits):
    """(exp(i pi lam), exp(-i pi lam)) as mpc at ``digits`` from the ball ``part``: lam
    itself in a band, mu with lam = e + i mu in a gap."""
    import mpmath
    with _Prec(bits_of(digits) + 8):
        if band:
            s, c = part.sin_cos_pi()
            vals = [(c, s), (c, -s)]
        else:
            sign = -1 if e % 2 else 1
            g = (arb.pi() * part).exp()
            vals = [(sign / g, arb(0)), (sign * g, arb(0))]
        with mpmath.workdps(digits):
            return tuple(mpmath.mpc(to_mpf(a), to_mpf(b)) for a, b in vals)


def lam_text(ball, digits):
    """The ``digits``-digit decimal of a ball when both ends round alike, else None."""
    if ball.is_zero():
        return "0"
    return ball_digits(ball, digits)


def exponent_at(X0, X1, want, w, info=None):
    """One attempt at working precision w digits: a dict with the certified answer, or
    None (count, sign of u or digits undecided at this precision).  ``info`` (a dict)
    receives the last band edge and estimate of u, for the caller's verdict when the
    precision runs out."""
    info = {} if info is None else info
    bits = bits_of(w)
    with _Prec(bits):
        x0, x1 = to_ball(X0), to_ball(X1)
        count = band_count(x0, x1)
        if count is None:
            # undecided: theta0 is within its rounding of the curve v_c between counts
            # c and c + 1 (a_0 < b_1 < a_1 < b_2 ... for q > 0), of edge (c + 1) // 2
            c = band_count(x0.mid(), x1.mid())
            info["e"] = (c + 1) // 2 if c is not None else int(round(math.sqrt(max(float(X0), 0))))
            # the distance to the curve is below the balls' width, ~10^-w: so is |u|
            info["u"] = 10.0 ** -w if w < 300 else 0.0
    if count is None:
        return None
    g = guess(X0, X1, count)
    e, u0 = g
    info["e"], info["u"] = e, u0
    if count % 2 == 1 and u0 <= 0:
        # next to an edge in double precision: start just inside
        u0 = 1e-30 if u0 == 0 else -u0
    if count % 2 == 0 and u0 >= 0:
        u0 = -1e-30 if u0 == 0 else -u0
    res = certify(X0, X1, count, e, u0, w, info)
    if res is None:
        return None
    part, U, depth = res
    with _Prec(bits):
        text = lam_text(part, want)
    if text is None:
        return None
    return {"count": count, "e": e, "u": U, "part": part, "text": text, "depth": depth,
            "band": count % 2 == 1}


# ---------------------------------------------------------------------------
# characteristic values a_m(q), b_m(q) and the first band, proved by Sturm counts
# ---------------------------------------------------------------------------

def _pivots_logdiff(family, q, x, n, dq=False):
    """Sum over the n x n truncation of p_i'/p_i (d/dx, or d/dq when dq) and the sign of
    prod p_i, for the LDL^T pivots p_i of T(q) - x (floats or balls).  Newton steps on
    det(T - x) are -sign/sum; no product is formed (no overflow in floats)."""
    s = 0
    p = dp = None
    for i in range(n):
        d = _diag(family, i, q)
        dd = (1 if family == "a_odd" else -1 if family == "b_odd" else 0) if (i == 0 and dq) else 0
        if not dq:
            dd = -1
        if i == 0:
            p, dp = d - x, dd
        else:
            e2 = 2 * q * q if (family == "a_even" and i == 1) else q * q
            de2 = (4 * q if (family == "a_even" and i == 1) else 2 * q) if dq else 0
            if p == 0:
                p = p + 1e-300 if isinstance(p, float) else p + arb(2) ** (-ctx.prec - 40)
            r = e2 / p
            p, dp = d - x - r, dd - (de2 - r * dp) / p
        s = s + dp / p
    return s


def _newton_on_pivots(family, q, x, n, bits_list, var_is_q, start):
    """Newton on det(T_n(q) - x) = 0 for x (var_is_q False) or q (True) at the
    precisions ``bits_list``; returns (value, last step) as arb midpoints."""
    v = arb(start)
    delta = arb(0)
    for bits in bits_list:
        with _Prec(bits + 16):
            vm = v.mid()
            qq, xx = (vm, x()) if var_is_q else (q(), vm)
            s = _pivots_logdiff(family, qq, xx, n, dq=var_is_q)
            if s == 0 or not s.is_finite():
                return None
            delta = (1 / s).mid()
            v = (vm - delta).mid()
    return v, delta


def _ladder(prec):
    steps = []
    p = prec
    while p > 100:
        steps.append(p)
        p = p // 2 + 8
    steps.reverse()
    return [steps[0]] + steps if steps else [prec, prec]


def char_value_at(family, j, Q, want, w):
    """Certified ball of the j-th eigenvalue of ``family`` at q = Q (exact), to ``want``
    digits at working precision w: (text, ball) or None."""
    from pendulab.analyses.floquet._charvalues import _double_char_value, _family_size

    qf = float(Q)
    a0, centre = _double_char_value(family, j, qf)
    prec = bits_of(w) + loss_bits(0.0, qf)
    n = max(_family_size(j, qf, w + 5), centre + 3)

    def qball():
        return to_ball(Q)
    got = _newton_on_pivots(family, qball, None, n, _ladder(prec), False, a0)
    if got is None:
        return None
    a, delta = got
    with _Prec(prec + 16):
        q = qball()
        scale = max(abs(a).upper(), arb(1))
        ad = abs(delta).upper()
        r0 = max(8 * ad * ad / scale, scale * arb(2) ** (16 - prec))
        for r in (r0, r0 * arb(2) ** 20, max(8 * ad, r0 * arb(2) ** 40)):
            lo, hi = arb((a - r).lower()), arb((a + r).upper())
            if family_count(family, q, lo) == j and family_count(family, q, hi) == j + 1:
                ball = lo.union(hi)
                text = lam_text(ball, want)
                return (text, ball) if text is not None else None
    return None


def band_end_ball(family, X0, w, q_start):
    """Ball [q_lo, q_hi] proved to contain the q > 0 where the lowest eigenvalue of
    ``family`` ("a_even": a_0, "b_odd": b_1) equals theta0 = X0 (exact, < 1), Newton
    from ``q_start`` at working precision w digits: (ball, bits) or None.

    Both curves decrease strictly in q > 0 (DLMF 28.2(v), 28.7), so the family's
    count of eigenvalues below theta0 is 0 before the crossing and 1 after it;
    counts 0 at q_lo and 1 at q_hi prove the crossing in [q_lo, q_hi]."""
    from pendulab.analyses.floquet._charvalues import _family_size

    qf = float(q_start)
    prec = bits_of(w) + loss_bits(float(X0), qf)
    n = _family_size(0, qf, w + 5) + 2

    def xball():
        return to_ball(X0)
    got = _newton_on_pivots(family, None, xball, n, _ladder(prec), True, q_start)
    if got is None:
        return None
    q, delta = got
    with _Prec(prec + 16):
        x = xball()
        size = abs(q).upper()
        ad = abs(delta).upper()
        r0 = max(8 * ad * ad / size, size * arb(2) ** (16 - prec))
        for r in (r0, r0 * arb(2) ** 20, max(8 * ad, r0 * arb(2) ** 40)):
            lo, hi = arb((q - r).lower()), arb((q + r).upper())
            if not lo > 0:
                return None
            if family_count(family, lo, x) == 0 and family_count(family, hi, x) == 1:
                return lo.union(hi), prec + 16
    return None


def band_end_at(family, X0, want, w, q_start, scale=None):
    """Certified ball of the q > 0 where the lowest eigenvalue of ``family`` ("a_even":
    a_0, "b_odd": b_1) equals theta0 = X0 (exact, < 1), times the exact ``scale`` when
    given, to ``want`` digits: (text, ball) or None (:func:`band_end_ball`)."""
    got = band_end_ball(family, X0, w, q_start)
    if got is None:
        return None
    ball, bits = got
    if scale is not None:   # a/l = q * (exact scale), the limits of a ParameterMap
        with _Prec(bits):
            ball = ball * to_ball(scale)
    text = lam_text(ball, want)
    return (text, ball) if text is not None else None


def nearest_double(ball):
    """The double nearest (round-half-even) to every number in ``ball``, or None when
    the ends of the ball round to different doubles (then no double is proved).

    The ends mid -+ rad are formed exactly (integers times a power of 2) and rounded
    by Python's int / int division, which is correctly rounded."""
    (m1, e1), (m2, e2) = (tuple(int(v) for v in x.man_exp()) for x in (ball.mid(), ball.rad()))
    if m2 == 0:
        e2 = e1
    e = min(e1, e2)
    mid, rad = m1 << (e1 - e), m2 << (e2 - e)
    ends = []
    for n in (mid - rad, mid + rad):
        try:
            ends.append(float(Fraction(n * 2 ** e) if e >= 0 else Fraction(n, 2 ** -e)))
        except OverflowError:
            return None
    return ends[0] if ends[0] == ends[1] else None


def _float_count(family, q, x, n):
    """Eigenvalues < x of the n x n truncation of ``family`` at q, in floats (a guess)."""
    count = 0
    p = 0.0
    for i in range(n):
        d = _diag(family, i, q)
        if i == 0:
            p = d - x
        else:
            e2 = 2 * q * q if (family == "a_even" and i == 1) else q * q
            p = d - x - e2 / (p if p != 0 else 1e-300)
        if p < 0:
            count += 1
    return count


def band_end_guess(family, x):
    """A double estimate of the q > 0 where the lowest eigenvalue of ``family`` equals
    x (a float < 1), or None: a bracket [q/2, q] by float Sturm counts of the truncated
    matrix (0 below the crossing, >= 1 above), then Newton on its determinant
    (:func:`_pivots_logdiff`), a bisection step whenever Newton leaves the bracket.
    Nothing here is proved: :func:`band_end_ball` proves the end from this start."""
    from pendulab.analyses.floquet._charvalues import _family_size

    sizes = {}

    def size(q):
        # the rows for 18 digits at the next power of 2 above q (more rows than q needs)
        top = math.frexp(q)[1]
        if top not in sizes:
            sizes[top] = _family_size(0, math.ldexp(1.0, top), 18) + 2
        return sizes[top]

    def count(q):
        return _float_count(family, q, x, size(q))
    hi = 1.0
    if count(hi) == 0:
        while count(hi) == 0:
            hi *= 2
            if hi > 1e9:
                return None
    else:
        while count(hi / 2) >= 1:
            hi /= 2
            if hi < 1e-150:
                return None
    lo, q = hi / 2, 0.75 * hi
    for _ in range(200):
        try:
            s = _pivots_logdiff(family, q, x, size(q), dq=True)
            new = q - 1 / s
        except (ZeroDivisionError, OverflowError):   # a pivot exactly 0: bisect
            new = math.nan
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        elif abs(new - q) <= 4e-16 * new:
            return new
        if count(new) == 0:
            lo = new
        else:
            hi = new
        if hi - lo <= 4e-16 * hi:
            return new
        q = new
    return q
