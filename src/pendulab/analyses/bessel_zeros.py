"""Certified zeros j_nu,k of the Bessel function J_nu (any real nu from 0 to 300).

``bessel_zeros(nu, count, dps)`` returns the first ``count`` positive zeros
j_nu,1 < j_nu,2 < ... to ``dps`` significant digits, each digit proved:

1. **Start.**  McMahon's expansion j ~ beta + sum c_j beta^-(2j-1),
   beta = (k + nu/2 - 1/4) pi (DLMF 10.21.19), with the coefficients derived
   in :mod:`pendulab.analyses.bessel_asymptotics`; where it is not accurate
   (small k, large nu) the start is taken inside the bracket of step 4.
2. **Newton**, f = J_nu, f' = (nu/x) J_nu - J_nu+1 (DLMF 10.6.2; 002 "Obs. 1"),
   in python-flint's arb at doubling precision.
3. **Certificate of the zero**: one interval Newton step on X = [m - r, m + r]:
   N(X) = m - f(m)/f'(X).  f'(X) is enclosed by f'(m) +- r sup_X |f''|, and
   sup_X |f''| <= (nu/x + 1)/x + max(|1 - nu^2/x^2|, 1) at x = inf X, from Bessel's
   equation f'' = -f'/x - (1 - nu^2/x^2) f with |J_nu| <= 1 (DLMF 10.14.1)
   and |f'| <= nu/x + 1.  If f'(X) excludes 0 and N(X) lies inside X, X holds
   exactly one zero, and it lies in N(X) (the returned ball).
4. **Certificate of the index** (no zero skipped or counted twice), by
   induction with Sturm's comparison theorem applied to u = sqrt(x) J_nu,
   u'' + q u = 0, q = 1 - (nu^2 - 1/4)/x^2:

   * J_nu(x) > 0 on (0, 2 sqrt(nu + 1)]: the power series (DLMF 10.2.2) is
     alternating with decreasing terms there; and on (0, sqrt(nu^2 - 1/4)]
     for nu > 1/2, where q < 0: u starts positive and increasing at 0+ and
     u'' = -q u > 0 keeps it so;
   * consecutive zeros are at least pi apart when nu >= 1/2 (q <= 1) and at
     least pi/sqrt(q(x)) (> 3 for x >= 2) after x when nu < 1/2; hence J_nu
     is evaluated (as balls) at points 1/2 apart from the end of the interval
     above: the first point where it is negative brackets j_nu,1 with no zero
     before it;
   * after a zero x the next one is at most pi/sqrt(q(x)) (nu >= 1/2), resp.
     pi (nu < 1/2), further, and the one after it at least twice the minimal
     gap: each certified ball must lie in the window between the previous
     ball and twice the minimal gap (:func:`next_window`; near the turning
     point x ~ nu, where q(x) <= 1/4, a two-sided window from both Sturm
     bounds, refused when it is too wide to exclude a second zero, which
     limits nu to 300).

   Two further checks, not needed for the proof but failing on a wrong index:
   the asymptotic phase theta_nu(x) ~ x - (nu/2 + 1/4) pi + phi(x)
   (:func:`phase_coefficients`) rounds to (k - 1/2) pi wherever its series is
   accurate, and :func:`check_interlacing` proves j_nu,k < j_nu+1,k < j_nu,k+1
   (DLMF 10.21.3) for two computed sequences.
5. **Digits**: both ends of the final ball round to the same ``dps``-digit
   decimal (else the precision is raised), so every printed digit is correct
   (correctly rounded, round-half-even).

mpmath.besseljzero is used only in the tests, as a cross-check.
"""

import gmpy2
import math
from dataclasses import dataclass, field
from fractions import Fraction

from flint import arb, ctx, fmpq

from pendulab.analyses.bessel_asymptotics import mcmahon_coefficients, phase_coefficients, poly_at
from pendulab.errors import ConvergenceError, InputError

#: limits of the public API (the command line and the product use the same)
MAX_DPS = 10_000
MAX_COUNT = 100_000
MAX_ORDER = 300


class CertificationError(ConvergenceError):
    """A zero or its index could not be proved (the message says which check failed)."""


# -- input ------------------------------------------------------------------------------

def parse_order(nu, what="order"):
    """nu (int, float, Fraction or a decimal/fraction string such as "1/3") as a Fraction >= 0."""
    if isinstance(nu, bool):
        raise InputError(f"{what} must be a real number >= 0, got {nu!r}")
    try:
        if isinstance(nu, float):
            if not math.isfinite(nu):
                raise ValueError
            value = Fraction(nu)
        elif isinstance(nu, (int, Fraction)):
            value = Fraction(nu)
        elif isinstance(nu, str):
            value = Fraction(nu.strip())
        else:
            raise ValueError
    except (ValueError, ZeroDivisionError):
        raise InputError(f"{what} must be a real number >= 0 (such as 1, 2.5 or 1/3), got {nu!r}") from None
    if value < 0:
        raise InputError(f"{what} must be >= 0, got {nu!r}")
    if value > MAX_ORDER:
        raise InputError(f"{what} must be at most {MAX_ORDER}, got {nu!r}")
    return value


def check_count(count, what="count", maximum=MAX_COUNT):
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= maximum:
        raise InputError(f"{what} must be an integer from 1 to {maximum}, got {count!r}")
    return count


def check_dps(dps, what="dps"):
    if isinstance(dps, bool) or not isinstance(dps, int) or not 1 <= dps <= MAX_DPS:
        raise InputError(f"{what} must be an integer from 1 to {MAX_DPS}, got {dps!r}")
    return dps


def bits_for(dps):
    """Working precision in bits for ``dps`` decimal digits (with 20 guard bits)."""
    return int(math.ceil(dps * math.log2(10))) + 20


#: Least working precision of the zeros, whatever the digits asked: the certificates need
#: a ball far narrower than the gap between zeros (near the turning point x ~ nu of a large
#: order, a few units wide), which bits_for(dps) of a few digits (24 bits at dps = 1) does not
#: give.  The digits printed are still ``dps``, correctly rounded.
MIN_ZERO_BITS = 64


# -- exact decimal rounding of a ball ---------------------------------------------------------

def _man_exp(x):
    man, exp = x.man_exp()
    return int(man), int(exp)


def _round_sig(n, e2, digits):
    """(d, e): the positive n 2^e2 rounded half-even to ``digits`` significant digits,
    i.e. n 2^e2 ~ d 10^(e - digits + 1) with 10^(digits-1) <= d < 10^digits (exact integers)."""
    e = math.floor((n.bit_length() + e2) * 0.30102999566398120) - 1
    while True:
        shift = digits - 1 - e  # want round(n 2^e2 10^shift)
        num, den = n, 1
        if shift >= 0:
            num *= 10 ** shift
        else:
            den *= 10 ** (-shift)
        if e2 >= 0:
            num <<= e2
        else:
            den <<= -e2
        q, rem = divmod(num, den)
        if q >= 10 ** digits:
            e += 1
            continue
        if q < 10 ** (digits - 1):
            e -= 1
            continue
        if 2 * rem > den or (2 * rem == den and q % 2 == 1):
            q += 1
        if q == 10 ** digits:
            q //= 10
            e += 1
        return q, e


def _format(n, e, digits):
    sign = "-" if n < 0 else ""
    # gmpy2 prints integers of any length (str() of an int stops at 4300 digits)
    s = gmpy2.mpz(abs(n)).digits(10).rjust(digits, "0")
    if 0 <= e < digits:
        body = s[:e + 1] + ("." + s[e + 1:] if e + 1 < digits else "")
    elif -5 <= e < 0:
        body = "0." + "0" * (-e - 1) + s
    else:
        body = s[0] + ("." + s[1:] if digits > 1 else "") + f"e{e:+d}"
    return sign + body


def ball_digits(ball, digits):
    """The ``digits``-significant-digit decimal of the value in ``ball``, or None.

    None when the two ends of the ball round differently (more precision is
    needed) or the ball contains 0.  A returned string is correct in every
    digit: it is the correctly rounded value of every number in the ball.
    """
    (m1, e1), (m2, e2) = _man_exp(ball.mid()), _man_exp(ball.rad())
    if m2 == 0:
        e2 = e1
    e = min(e1, e2)
    M, R = m1 << (e1 - e), m2 << (e2 - e)
    lo, hi = M - R, M + R
    if lo <= 0 <= hi:
        return None
    sign = 1
    if hi < 0:
        lo, hi, sign = -hi, -lo, -1
    a, b = _round_sig(lo, e, digits), _round_sig(hi, e, digits)
    if a != b:
        return None
    return _format(sign * a[0], a[1], digits)


# -- the certified Newton step ----------------------------------------------------------------

class _Prec:
    """Set python-flint's working precision and restore it afterwards."""

    def __init__(self, bits):
        self.bits = bits

    def __enter__(self):
        self.saved = ctx.prec
        ctx.prec = self.bits

    def __exit__(self, *exc):
        ctx.prec = self.saved


def _order_ball(nu):
    if nu.denominator == 1:
        return arb(int(nu.numerator))  # exact at every precision
    return arb(fmpq(nu.numerator, nu.denominator))


def _f_fp(nu_b, x):
    """(J_nu(x), J_nu'(x)) as balls; J_nu' = (nu/x) J_nu - J_nu+1 (DLMF 10.6.2)."""
    f = x.bessel_j(nu_b)
    return f, nu_b / x * f - x.bessel_j(nu_b + 1)


def _log2(x):
    """About log2 |x| for an arb (exponent arithmetic, no float underflow); -inf for 0."""
    man, exp = abs(x).abs_upper().man_exp()
    man = int(man)
    return -math.inf if man == 0 else int(exp) + man.bit_length()


def _eval(nu, x, bits, tol_bits):
    """(f, f') at x with rad(f)/|f'| below 2^-tol_bits |x|: the precision is raised past
    the digits arb loses (J_nu for x below nu loses many).  Returns (f, f', bits used)."""
    w, last = bits, None
    for _ in range(12):
        with _Prec(w):
            nu_b = _order_ball(nu)
            xm = arb(x).mid()
            f, fp = _f_fp(nu_b, xm)
            if not fp.contains(0):
                # rad(f)/|f'| <= 2^-tol |x|, by exponents (a bit or two either way is fine)
                lrel = _log2(f.rad()) - _log2(abs(fp).abs_lower()) + 1 - _log2(xm)
                if lrel <= -tol_bits - 1:
                    return f, fp, w
                step = max(int(lrel) + tol_bits + 8, 16)
                if last is not None and lrel > last - 8:
                    # the last raise did not narrow the ball: its width is not rounding but
                    # the truncation bound of the method arb chose (for a non-integer order
                    # near x ~ 1.4 nu, an asymptotic expansion up to ~1000 bits): grow
                    # geometrically until arb changes method
                    step = max(step, w)
                last = lrel
                w += step
            else:
                w += max(32, w // 2)
    raise CertificationError(f"J_{nu} cannot be evaluated accurately near {x}")


def second_derivative_bound(nu_b, lo):
    """sup |J_nu''| on [lo, oo), lo > 0, from Bessel's equation (see the module docstring).

    Each term is bounded by its supremum over x >= lo: (nu/x + 1)/x decreases, but
    |1 - nu^2/x^2| falls to 0 at x = nu and then rises toward 1, so its supremum is
    max(|1 - nu^2/lo^2|, 1), not its value at lo (for lo = nu that value is 0).
    """
    t = nu_b / lo
    swing = abs(1 - t * t).abs_upper()  # an exact upper bound: compared with 1 decisively
    if not swing > 1:
        swing = arb(1)
    return ((t + 1) / lo + swing).abs_upper()


def interval_newton(nu, mid, radius, bits):
    """One interval Newton step for J_nu on X = [mid - radius, mid + radius].

    ``nu`` is a Fraction (or anything :func:`parse_order` takes), ``mid`` and
    ``radius`` exact numbers (arb midpoints, ints, Fractions as arb).
    Returns the ball N(X), which holds the unique zero of J_nu in X, or raises
    :class:`CertificationError` (f'(X) contains 0, or N(X) is not inside X:
    X holds no zero or its midpoint is too far from one).
    """
    if not isinstance(nu, Fraction):
        nu = parse_order(nu)
    with _Prec(bits):
        nu_b = _order_ball(nu)
        m = arb(mid).mid()
        r = arb(radius).abs_upper()
        X = arb(m, r)
        lo = X.lower()
        if not lo > 0:
            raise CertificationError(f"interval [{X}] for a zero of J_{nu} is not positive")
        rel = max(_log2(m) - _log2(r) + 3, 8)
        f, fp, w = _eval(nu, m, bits, rel)
    with _Prec(w):
        nu_b = _order_ball(nu)
        widen = (second_derivative_bound(nu_b, lo) * r).abs_upper()
        fpX = fp + arb(0, widen)
        if fpX.contains(0):
            raise CertificationError(f"J_{nu}' may vanish on [{X}]: no certificate")
        N = m - f / fpX
        if not X.contains(N):
            raise CertificationError(f"interval Newton image of [{X}] is not inside it: no zero of "
                                     f"J_{nu} certified there")
        return N


# -- starts -------------------------------------------------------------------------------------

_COEFF_CACHE = {}
_COEFF_BALLS = {}


def _mcmahon_values(nu):
    """c_j(4 nu^2) as exact rationals (fmpq), cached per order."""
    key = (nu.numerator, nu.denominator)
    if key not in _COEFF_CACHE:
        mu = fmpq(4) * fmpq(nu.numerator, nu.denominator) ** 2
        # exact rationals: an arb made now would keep the precision of the first caller
        _COEFF_CACHE[key] = [poly_at(c, mu) for c in mcmahon_coefficients()]
    return _COEFF_CACHE[key]


def mcmahon_start(nu, k, bits):
    """(x, accurate_bits): McMahon's j_nu,k at ``bits`` and a rough count of its correct bits.

    Terms are added while they decrease; the estimate is -log2 of the last
    term used relative to x (0 when the first correction is not small).
    """
    key = (nu.numerator, nu.denominator, bits)
    with _Prec(bits):
        if key not in _COEFF_BALLS:  # the rationals as balls at this precision, made once
            _COEFF_BALLS[key] = [arb(c) for c in _mcmahon_values(nu)]
        coeffs = _COEFF_BALLS[key]
        beta = (arb(k) + _order_ball(nu) / 2 - arb(1) / 4) * arb.pi()
        x = beta
        inv2 = 1 / (beta * beta)
        power = 1 / beta
        last = None
        enough = abs(beta).abs_upper() * arb(2) ** (-bits)
        for c in coeffs:
            term = c * power
            size = abs(term).abs_upper()
            if last is not None and size >= last:
                break
            x = x + term
            last = size
            if size < enough:
                break
            power = power * inv2
        x = x.mid()
        if last is None or last == 0:
            return x, bits
        rel = float(last / abs(x))
        acc = 0 if rel >= 1e-2 else int(-math.log2(rel)) if rel > 0 else bits
        return x, min(acc, bits)


def _sign(v):
    if v > 0:
        return 1
    if v < 0:
        return -1
    return 0


def _bracket_newton(nu, a, b, sa, x0, bits=64, iters=200):
    """Safeguarded Newton (bisection fallback) for the one zero of J_nu in (a, b); sa = sign J(a).

    Returns (x, accurate bits) once the Newton step is below 2^-(bits-12) |x|.
    """
    with _Prec(bits):
        a, b = arb(a).mid(), arb(b).mid()
        x = arb(x0).mid() if a < arb(x0) < b else ((a + b) / 2).mid()
    tol = bits - 12
    for _ in range(iters):
        f, fp, w = _eval(nu, x, bits, tol)
        with _Prec(w):
            s = _sign(f)
            if s == sa:
                a = x
            elif s == -sa:
                b = x
            step = (f / fp).mid()
            nxt = (x - step).mid()
            if not (a < nxt < b):
                nxt = ((a + b) / 2).mid()
            if abs(nxt - x) < abs(x) * arb(2) ** (-tol) or (b - a) < abs(x) * arb(2) ** (-tol):
                return nxt, tol - 2
            x = nxt
    raise CertificationError(f"Newton/bisection for a zero of J_{nu} did not converge in ({a}, {b})")


def _refine(nu, x, acc, bits):
    """Newton steps at doubling precision from x (about ``acc`` correct bits) to about bits/2 + 10."""
    goal = bits // 2 + 10
    schedule = []
    b = goal
    while b > max(acc, 1):
        schedule.append(b)
        b = b // 2 + 4
    for p in reversed(schedule):
        f, fp, w = _eval(nu, x, p + 10, p + 4)
        with _Prec(w):
            x = (x - f / fp).mid()
    return x


def _certify(nu, x, bits, acc):
    """Final interval Newton step at ``bits`` from the midpoint x (about ``acc`` correct bits).

    X starts with radius 2^-(acc-3) |x| and widens (after one more Newton
    step) if the certificate fails.
    """
    with _Prec(bits):
        r = abs(x).abs_upper() * arb(2) ** (-(max(min(acc, bits - 12), 8) - 3))
    for _ in range(4):
        try:
            return interval_newton(nu, x, r, bits)
        except CertificationError:
            f, fp, w = _eval(nu, x, bits, bits - 14)
            with _Prec(w):
                dx = abs(f / fp).abs_upper()
                x = (x - f / fp).mid()
                r = max(r * 16, 4 * dx)
    return interval_newton(nu, x, r, bits)


# -- the sequence ---------------------------------------------------------------------------------

def _gap_q(nu_b, x):
    """q(x) = 1 - (nu^2 - 1/4)/x^2 of u = sqrt(x) J_nu as a ball."""
    return 1 - (nu_b * nu_b - arb(1) / 4) / (x * x)


def next_window(nu, prev, bits=64):
    """(a, b, c): after the zero x in the ball ``prev``, (a, b) holds exactly one zero, the next.

    Sturm's comparison for u'' + q u = 0 (module docstring, step 4): zeros
    are at least pi apart for nu >= 1/2 (q <= 1) and at least pi/sqrt(Q)
    apart after x for nu < 1/2 (q <= Q = q(inf prev)); the next zero is at
    most pi/sqrt(q(x)) (nu >= 1/2), resp. pi (nu < 1/2), after x.  So with
    G = 2 pi, resp. 2 pi/sqrt(Q), the interval (sup prev, inf prev + G) holds
    the next zero and not the one after it.  ``c`` (> a) is a point with no
    zero in (a, c], where a bracket search for the next zero can start.
    """
    with _Prec(bits):
        nu_b = _order_ball(nu)
        lo, hi = prev.lower(), prev.upper()
        pi = arb.pi()
        q = _gap_q(nu_b, lo)
        if q > arb(1) / 4:
            gap = pi if nu >= Fraction(1, 2) else pi / q.sqrt()
            return hi.upper(), (lo + 2 * gap).lower(), (hi + gap / 2).upper()
        # Near the turning point (x < 1.16 nu): the next zero z1 is in [a1, b1] with
        # b1 = x + pi/sqrt(q(x)) and, q increasing, z1 - x >= pi/sqrt(q(z1)) >= pi/sqrt(q(b1));
        # the zero after it is at least pi beyond z1, hence beyond b1 if a1 + pi > b1.
        if not q > 0:
            raise CertificationError(f"zero {prev} of J_{nu} is below sqrt(nu^2 - 1/4)")
        b1 = (hi + pi / q.sqrt()).upper()
        a1 = (lo + pi / _gap_q(nu_b, b1).sqrt()).lower()
        if not a1 + pi > b1:
            raise CertificationError(f"the Sturm window after the zero {prev} of J_{nu} is too wide "
                                     "to exclude a second zero")
        return a1, b1, a1


def first_bracket(nu, bits=64, step=Fraction(1, 2)):
    """(a, b, sign J(a)): j_nu,1 is the only zero of J_nu in (0, b) and lies in (a, b).

    J_nu > 0 on (0, max(2 sqrt(nu+1), sqrt(nu^2 - 1/4))] (module docstring); from there J_nu is
    evaluated at points ``step`` apart until it is certainly negative.  Two
    zeros are never closer than ``step`` (Sturm), so no zero is missed.
    """
    with _Prec(bits):
        nu_b = _order_ball(nu)
        a = (2 * (nu_b + 1).sqrt()).lower()
        if nu > 1:
            a = max(a, (nu_b * nu_b - arb(1) / 4).sqrt().lower())
        h = arb(fmpq(step.numerator, step.denominator))
    x = a
    for _ in range(10 * MAX_ORDER):
        y = _point(x + h, bits)
        s = _sign_certain(nu, y, bits)
        if s == 0:  # a point too close to the zero: move it a little
            y = _point(y + h / 7, bits)
            s = _sign_certain(nu, y, bits)
            if s == 0:
                raise CertificationError(f"cannot decide the sign of J_{nu} near {y}")
        if s < 0:
            return x, y, 1
        x = y
    raise CertificationError(f"no sign change of J_{nu} found")


def _point(y, bits):
    """An exact point (radius 0) at or within 2^-bits |y| of the ball ``y``'s midpoint.

    The points where the sign of J_nu is decided must be exact: arb's J_nu of a
    non-integer order propagates an input radius (even 1e-13, the rounding of a
    sum at the default 53 bits) into an enclosure too wide for any sign, at every
    precision.  A point moved by 2^-bits changes the step by far less than the
    gap between zeros the bracket search relies on.
    """
    with _Prec(bits):
        return arb(y).mid()


def _sign_certain(nu, y, bits, top=4096):
    """The sign of J_nu(y), raising the precision until the ball decides it (0 if it never does)."""
    while bits <= top:
        with _Prec(bits):
            v = arb(y).bessel_j(_order_ball(nu))
            if v > 0:
                return 1
            if v < 0:
                return -1
        bits *= 2
    return 0


_PHASE_CACHE = {}


def phase_index(nu, x):
    """k with theta_nu(x) closest to (k - 1/2) pi, from the asymptotic phase, or None.

    Evaluated in double precision (the terms are small and x < 10^6, so the
    rounding error is far below the 0.25 margin asked for); None where the
    phase series is not accurate to 0.05 at x (x not large against nu^2).
    """
    if nu not in _PHASE_CACHE:
        mu = fmpq(4) * fmpq(nu.numerator, nu.denominator) ** 2
        # int / int is exact before rounding: p and q may be too long for float (nu ~ 1e-20)
        _PHASE_CACHE[nu] = [(j, int(poly_at(c, mu).p) / int(poly_at(c, mu).q))
                            for j, c in enumerate(phase_coefficients()) if j % 2]
    xf = float(arb(x).mid())
    y = 1.0 / xf
    phi, last = 0.0, None
    for j, c in _PHASE_CACHE[nu]:
        term = c * y ** j
        if last is not None and abs(term) >= last:
            break
        phi, last = phi + term, abs(term)
    if last is None or not last < 0.05:
        return None
    kk = (xf - (float(nu) / 2 + 0.25) * math.pi + phi) / math.pi + 0.5
    k = int(kk + 0.5)
    return k if abs(kk - k) < 0.25 else None


@dataclass
class ZeroSet:
    """The first ``count`` zeros of J_nu, certified (see the module docstring).

    ``balls[i]`` (python-flint arb) holds j_nu,i+1; ``strings[i]`` is it to
    ``dps`` significant digits, every digit correct; ``phase_checked`` counts
    the zeros whose index the asymptotic phase confirmed as well.
    """

    nu: Fraction
    dps: int
    balls: list = field(default_factory=list)
    strings: list = field(default_factory=list)
    phase_checked: int = 0

    @property
    def order_text(self):
        return str(self.nu)

    def _rows(self):
        return [[str(k + 1), text] for k, text in enumerate(self.strings)]

    def _repr_latex_(self):
        """The zeros as a table for a notebook (:func:`pendulab.latex.math_table`): k and
        j_nu,k to ``dps`` digits, as :func:`ball_digits` wrote them."""
        from pendulab.latex import math_table, text
        caption = (text("zeros of ") + f"J_{{{self.order_text}}}"
                   + text(f", {self.dps} significant digits, every digit proved"))
        return math_table(caption, ["k", f"j_{{{self.order_text},k}}"], self._rows())

    def _repr_html_(self):
        """The same table in HTML (:func:`pendulab.latex.html_table`), one row per zero."""
        from pendulab.latex import html_table
        caption = (f"zeros of $J_{{{self.order_text}}}$, {self.dps} significant digits, "
                   "every digit proved")
        return html_table(caption, ["k", f"$j_{{{self.order_text},k}}$"], self._rows())


def bessel_zeros(nu, count, dps, extra_bits=0, window_bits=None):
    """The first ``count`` zeros of J_nu to ``dps`` significant digits, certified.

    ``nu``: real >= 0 (int, float, Fraction or a string "1", "2.5", "1/3");
    ``count``: 1 .. MAX_COUNT; ``dps``: 1 .. MAX_DPS.  ``extra_bits`` raises
    the precision of the balls (the quarter periods, differences of squares,
    need about log2(x) more).  Returns a :class:`ZeroSet`; raises
    :class:`InputError` for bad arguments and :class:`CertificationError` if
    a certificate fails (which would be a bug, not a property of the input).
    """
    nu = parse_order(nu)
    check_count(count)
    check_dps(dps)
    bits = max(bits_for(dps), MIN_ZERO_BITS) + extra_bits
    out = ZeroSet(nu, dps)
    prev = None
    for k in range(1, count + 1):
        if prev is None:
            lo, hi, sa = first_bracket(nu)
        else:
            lo, hi, start = next_window(nu, prev, bits)
            sa = None
        x, acc = mcmahon_start(nu, k, min(bits, 256))
        if not (lo < x and x < hi) or acc < 20:
            if sa is None:
                lo_s = start
                sa = _sign_certain(nu, lo_s, 64)
                if sa == 0:
                    raise CertificationError(f"J_{nu} has no certain sign at {lo_s}")
            else:
                lo_s = lo
            x, acc = _bracket_newton(nu, lo_s, hi, sa, x)
        if acc < bits // 2 + 10:
            x = _refine(nu, x, acc, bits)
            acc = bits // 2 + 10
        while True:
            ball = _certify(nu, x, bits, acc)
            if not (lo < ball and ball < hi):  # exact comparisons of balls
                raise CertificationError(f"zero {ball} of J_{nu} is not in the window ({lo}, {hi}) of "
                                         f"zero number {k}: index not certified")
            text = ball_digits(ball, dps)
            if text is not None:
                break
            bits += 32  # both ends of the ball do not round alike yet
            x, acc = ball.mid(), bits // 2
        pk = phase_index(nu, ball.mid())
        if pk is not None:
            if pk != k:
                raise CertificationError(f"asymptotic phase gives index {pk} for zero {k} of J_{nu}")
            out.phase_checked += 1
        out.balls.append(ball)
        out.strings.append(text)
        prev = ball
    return out


def check_index(nu, balls):
    """Re-prove that ``balls`` are j_nu,1, j_nu,2, ... in order (each in its Sturm window).

    Raises :class:`CertificationError` naming the first ball that is not the
    zero it should be (skipped, repeated or out of order).  Each ball is
    assumed to hold a zero of J_nu (see :func:`interval_newton`).
    """
    nu = parse_order(nu)
    for k, ball in enumerate(balls, start=1):
        if k == 1:
            lo, hi, _ = first_bracket(nu)
        else:
            lo, hi, _ = next_window(nu, balls[k - 2], max(64, balls[k - 2].mid().bits() + 16))
        if not (lo < ball and ball < hi):
            raise CertificationError(f"ball {k} ({ball}) is not zero number {k} of J_{nu}: it is outside "
                                     f"({lo}, {hi})")
    return True


def check_interlacing(lower, upper):
    """Prove j_nu,k < j_nu+1,k < j_nu,k+1 (DLMF 10.21.3) for two lists of balls.

    ``lower`` holds zeros of J_nu, ``upper`` of J_nu+1; returns the number of
    comparisons made, raises :class:`CertificationError` at the first failure.
    """
    n = 0
    for k, b in enumerate(upper):
        if k < len(lower) and not lower[k] < b:
            raise CertificationError(f"interlacing fails: j_nu,{k + 1} < j_nu+1,{k + 1} not proved")
        if k + 1 < len(lower) and not b < lower[k + 1]:
            raise CertificationError(f"interlacing fails: j_nu+1,{k + 1} < j_nu,{k + 2} not proved")
        n += 2
    return n
