"""Characteristic values a_m(q), b_m(q) (DLMF 28.2(v)) and the first stable band."""

from __future__ import annotations

from fractions import Fraction

import mpmath

from pendulab.errors import ConvergenceError, InputError, PrecisionError
from pendulab.analyses.floquet._bands import _edge_index, _family_diagonals, _tail_steps
from pendulab.analyses.floquet._cf import _illinois
from pendulab.analyses.floquet._inputs import (
    DOUBLE_DPS, SIZE_LIMIT, _check_dps, _check_size, _exact, _mp, _size_text,
)
from pendulab.analyses.floquet._precision import agree, autoprec

#: routes of the characteristic values and the first band: "arb" (ball arithmetic,
#: every digit proved; the default when dps is given) and "mpmath" (the default in
#: double precision, and the independent cross-check)
VALUE_METHODS = ("arb", "mpmath")


def _value_method(method, dps, name):
    if method is None:
        return "mpmath" if dps is None else "arb"
    if method not in VALUE_METHODS:
        raise InputError(f"{name}: method must be one of {', '.join(VALUE_METHODS)}, "
                         f"got {method!r}")
    return method


def _proved_or_none(asked, prove):
    """``prove()`` (the ball-arithmetic route), or None where it raises PrecisionError and
    no method was asked for: the default route then falls back to mpmath, which claims no
    digits (tiny q, where neighbouring Sturm pivots nearly vanish and the balls cannot be
    made narrow enough).  With method "arb" asked for, the PrecisionError stands."""
    try:
        return prove()
    except PrecisionError:
        if asked is not None:
            raise
        return None


def _certified(compute, want, what):
    """The arb routes: ``compute(w)`` returns (text, ball) or None; the text (``want``
    correctly rounded digits) read as an mpf at want + 10 digits."""
    (text, _), _ = autoprec(compute, want, two=False, what=what)
    with mpmath.workdps(want + 10):
        return mpmath.mpf(text)


def _family_of(kind, m):
    """(family, index within the family) of a_m or b_m (DLMF 28.4.5-28.4.8)."""
    if kind == "a":
        return ("a_even", m // 2) if m % 2 == 0 else ("a_odd", (m - 1) // 2)
    return ("b_odd", (m - 1) // 2) if m % 2 == 1 else ("b_even", m // 2 - 1)


def _family_size(j, q, digits):
    m0 = _edge_index(0, q)
    return j + 2 + m0 // 2 + _tail_steps(0, q, m0, digits) + _tail_steps(0, q, 2 * j + m0, digits)


def _double_char_value(family, j, qf):
    """Double-precision eigenvalue (and eigenvector peak) of the truncated matrix."""
    import numpy as np
    from scipy.linalg import eigh_tridiagonal

    n = _family_size(j, qf, 18)
    d, e2 = _family_diagonals(family, qf, n, 1.0)
    d = np.array(d, dtype=float)
    e = np.sqrt(np.array(e2, dtype=float))
    if n == 1:
        return float(d[0]), 0
    vals, vecs = eigh_tridiagonal(d, e, select="i", select_range=(j, j))
    return float(vals[0]), int(np.argmax(np.abs(vecs[:, 0])))


def _char_value_mp(family, j, q, w, guess=None, relative=False):
    """Characteristic value at dps w (inside an active workdps): the root of the
    two-sided continued fraction centred on the dominant Fourier coefficient
    (the recurrences DLMF 28.4.5-28.4.8), bracketed around a double estimate.
    To 10^-w relative (absolute below 1); with ``relative``, relative below 1 too."""
    qf = float(q)
    a0, centre = _double_char_value(family, j, qf)
    n = _family_size(j, qf, w + 5)
    n = max(n, centre + 3)

    def solve(A, scale, extra):
        """The root near A to 10^-w * scale, with ``extra`` more working digits."""
        with mpmath.workdps(w + extra):
            d, e2 = _family_diagonals(family, +q, n, mpmath.mpf(1))

            def G(a):
                # continued fraction from row 0 up to the centre, and from the
                # truncation depth down to the centre
                low = 0
                for i in range(centre):
                    denom = d[i] - a - low
                    low = e2[i] / denom
                up = 0
                for i in range(n - 1, centre, -1):
                    up = e2[i - 1] / (d[i] - a - up)
                return d[centre] - a - low - up

            delta = mpmath.mpf(10) ** -11 * scale
            for _ in range(60):
                lo, hi = A - delta, A + delta
                glo, ghi = G(lo), G(hi)
                if (glo > 0) != (ghi > 0):
                    break
                delta *= 8
            else:
                raise ConvergenceError(f"could not bracket the characteristic value ({family}, "
                                       f"{j}, q={qf})")
            root, _ = _illinois(G, lo, hi, glo, ghi, mpmath.mpf(10) ** (-w) * scale)
            # the root's size when it came out as 0: G's slope in a is about -1 there
            return root, (abs(G(root)) if root == 0 else abs(root))

    root, size = solve(mpmath.mpf(a0), mpmath.mpf(max(1.0, abs(a0))), 0)
    # a value far below 1 (a_0 at tiny q: about -q^2/2) was found to 10^-w absolute only:
    # solve again relative to its size, with as many more digits, until the size settles
    # (the double start can be off by many orders there: -1e-50 for a_0(1e-40) = -5e-81,
    # and 0 for a_0(1e-300))
    extra = 0
    while relative and size != 0 and size < mpmath.mpf(10) ** -5:
        need = int(mpmath.ceil(-mpmath.log10(size))) + 2
        if need <= extra or need > 20000:
            break
        extra = need
        root, size = solve(root, size, extra)
    return root


def _char_value(kind, m, q, dps, method=None):
    name = f"mathieu_{kind}"
    if isinstance(m, bool) or not isinstance(m, int):
        raise InputError(f"{name}: order m must be an integer, got {m!r}")
    if kind == "a" and m < 0:
        raise InputError(f"{name}: order m must be >= 0, got {m}")
    if kind == "b" and m < 1:
        raise InputError(f"{name}: order m must be >= 1, got {m}")
    dps = _check_dps(dps)
    asked, method = method, _value_method(method, dps, name)
    Q = _exact(q, "q")
    _check_size(m * m, Q, SIZE_LIMIT, name, names=("m^2", "q"))
    want = DOUBLE_DPS if dps is None else dps
    family, j = _family_of(kind, m)
    if Q == 0:
        val = mpmath.mpf(m * m)
        return float(val) if dps is None else val
    what = f"{name}({m}, {q})"
    v = None
    if method == "arb":
        from pendulab.analyses.floquet._arb import char_value_at
        v = _proved_or_none(asked, lambda: _certified(
            lambda w: char_value_at(family, j, Q, want, w), want, what))
    if v is None:
        def compute(w):
            with mpmath.workdps(w):
                return _char_value_mp(family, j, _mp(Q), w, relative=True)

        def accept(a, b, w2):
            with mpmath.workdps(w2):
                return agree(a, b, want)
        v, _ = autoprec(compute, want, accept=accept, what=what)
    if dps is None:
        return float(v)
    with mpmath.workdps(want):
        return +v


def mathieu_a(m, q, dps=None, method=None):
    """Characteristic value a_m(q) of w'' + (a - 2q cos 2z) w = 0 (DLMF 28.2(v)).

    Eigenvalue of the tridiagonal recurrence DLMF 28.4.5 (m even) or 28.4.6
    (m odd), truncated at a depth that grows like sqrt(q) plus what the digits
    need, refined by the continued fraction at the working precision.  Works for
    q < 0 directly (it reproduces a_{2n}(-q) = a_{2n}(q) and
    a_{2n+1}(-q) = b_{2n+1}(q), DLMF 28.2.26-28.2.27) and for |q| up to 1e4
    and beyond.  dps=None returns a float; otherwise an mpf with dps digits.

    method: None (default: "arb" when dps is given, else "mpmath"), "arb" or
    "mpmath".  "arb" proves every one of the dps digits: Newton on the
    determinant of the truncated matrix in ball arithmetic, then two Sturm
    counts of the *infinite* matrix on balls (module _arb) show a_m in
    [lo, hi], and the digits are those both ends round to.  "mpmath" is the
    route described above (bracketed continued fraction at two precisions).

    >>> round(mathieu_a(0, 1), 10)   # A&S Table 20.1: a_0(1) = -0.4551386041
    -0.4551386041
    """
    return _char_value("a", m, q, dps, method)


def mathieu_b(m, q, dps=None, method=None):
    """Characteristic value b_m(q), m >= 1 (DLMF 28.2(v); recurrences 28.4.7-28.4.8).

    See :func:`mathieu_a`; b_{2n+1}(-q) = a_{2n+1}(q) and b_{2n+2}(-q) = b_{2n+2}(q).
    """
    return _char_value("b", m, q, dps, method)

class Limits(tuple):
    """(lower, upper) with ``certified_digits``: the significant digits of each end
    proved in ball arithmetic (None for the mpmath route and double precision)."""

    certified_digits = None
    #: what the two ends bound, as LaTeX (``|\\theta_1|``, ``a/l``); None: not said
    quantity = None

    def __new__(cls, pair, certified_digits=None, quantity=None):
        obj = super().__new__(cls, pair)
        obj.certified_digits = certified_digits
        obj.quantity = quantity
        return obj

    def of(self, quantity):
        """The same limits, saying that they bound ``quantity`` (LaTeX), as a new pair."""
        return Limits(self, self.certified_digits, quantity)

    def _repr_latex_(self):
        """lower < quantity < upper and how many digits are proved, for a notebook (the numbers
        as :func:`pendulab.analyses.floquet_format.number_text` writes them)."""
        from pendulab.analyses.floquet_format import number_text
        from pendulab.latex import LINE_WIDTH, align, gather, number_rows, number_tex, text, visible_width
        digits = self.certified_digits
        ends = [number_tex(number_text(x, None if isinstance(x, float) else (digits or 15)))
                for x in self]
        what = self.quantity or r"x"
        if digits is None:
            proof = "first stable band; certified digits not counted"
        else:
            proof = f"first stable band; {digits} significant digits of each end proved"
        rows = [rf"{ends[0]} &< {what} < {ends[1]}"]
        if visible_width(rows[0]) > LINE_WIDTH:  # each end on rows of its own
            rows = (number_rows(text("lower end of ") + what, ends[0])
                    + number_rows(text("upper end of ") + what, ends[1]))
        return align(rows) + "\n" + gather([text(proof)])


def first_band(theta0, dps=None, method=None):
    """(lower, upper) |theta1| of the first stable band of 000 eq. 7 at a given theta0 < 1.

    The band is a_0(q) < theta0 < b_1(|q|) with |q| = |theta1| (DLMF 28.2(v);
    a_0 is even in q, b_1(|q|) = a_1(-|q|)): the lower end solves
    a_0(q) = theta0 (0 when theta0 >= 0), the upper one b_1(q) = theta0.
    method "mpmath" (the default in double precision): Brent's method on the
    characteristic values at two working precisions; "arb" (the default with
    dps): Newton in q on the determinant of the truncated matrix in ball
    arithmetic, each end proved by two Sturm counts of the infinite matrix at
    theta0 (count 0 at q_lo, 1 at q_hi; both curves decrease in q > 0), every
    digit proved.  Returns a :class:`Limits` pair (``certified_digits``).

    >>> lo, up = first_band(-0.01)
    >>> round(lo, 10), round(up, 10)
    (0.1415759161, 0.9164371642)
    >>> round(mathieu_a(0, lo), 12), round(mathieu_b(1, up), 12)   # on the two curves
    (-0.01, -0.01)
    >>> first_band("-1/100", dps=30).certified_digits
    30
    """
    dps = _check_dps(dps)
    asked, method = method, _value_method(method, dps, "first_band")
    X0 = _exact(theta0, "theta0")
    if X0 >= 1:
        raise InputError(f"theta0 = {theta0} >= 1: the first stable band at theta0 >= 1 "
                         "is not the one that starts at theta1 = 0")
    if abs(X0) > SIZE_LIMIT:
        raise InputError(f"|theta0| = {_size_text(abs(X0), SIZE_LIMIT)} is too large "
                         f"(limit {SIZE_LIMIT:g})")
    if method == "arb":
        band = _proved_or_none(asked, lambda: _band_certified(X0, dps, f"first_band({theta0})"))
        if band is not None:
            return band.of(r"|\theta_1|")
    return _band_at_two_precisions(lambda ww: _first_band_mp(_mp(X0), ww), dps,
                                   f"first_band({theta0})").of(r"|\theta_1|")


def _band_certified(X0, dps, what, scale=None):
    """The arb route of the first band at exact theta0 = X0 (times the exact ``scale``):
    ``dps`` proved digits, or in double precision (dps None) the proved correctly
    rounded doubles (:func:`_band_double`)."""
    from pendulab.analyses.floquet._arb import band_end_at
    if dps is None:
        band = _band_double(X0, scale)
        if band is None:
            raise PrecisionError(f"{what}: the ends of the first band were not proved to "
                                 "double precision")
        return band
    want = dps
    starts = [0.0 if family == "a_even" and X0 >= 0 else _end_start(family, X0)
              for family in ("a_even", "b_odd")]
    if None in starts:   # no double start (theta0 beyond the range of doubles)
        with mpmath.workdps(20):
            starts = _first_band_mp(_mp(X0), 20)
    ends = []
    for family, start in zip(("a_even", "b_odd"), starts):
        if family == "a_even" and X0 >= 0:
            ends.append(mpmath.mpf(0))
            continue
        if scale is None:
            ends.append(_certified(lambda w: band_end_at(family, X0, want, w, start), want,
                                   what))
        else:
            ends.append(_certified(lambda w: band_end_at(family, X0, want, w, start,
                                                         Fraction(scale)), want, what))
    with mpmath.workdps(want):
        return Limits((+ends[0], +ends[1]), want)


#: (family, theta0) -> double start, (family, theta0, w) -> proved ball of the band end
#: in q (with its bits) or None, kept for the process: the rod and the point mass of a
#: build meet the same theta0 = -4 (omega0/omega)^2.
_ENDS = {}


def _end_start(family, X0):
    """:func:`_arb.band_end_guess` at exact theta0 = X0 (memoised): a double or None."""
    from pendulab.analyses.floquet._arb import band_end_guess

    if len(_ENDS) >= 4096:
        _ENDS.clear()
    if (family, X0) not in _ENDS:
        _ENDS[family, X0] = band_end_guess(family, float(X0))
    return _ENDS[family, X0]


def _end_ball(family, X0, w):
    """:func:`_arb.band_end_ball` from :func:`_end_start` (memoised)."""
    from pendulab.analyses.floquet._arb import band_end_ball

    start = _end_start(family, X0)
    if start is None:
        return None
    if (family, X0, w) not in _ENDS:
        _ENDS[family, X0, w] = band_end_ball(family, X0, w, start)
    return _ENDS[family, X0, w]


def _band_double(X0, scale=None):
    """The first band at exact theta0 = X0 (times the exact ``scale``) in double
    precision by the arb route: each end is the double nearest to every number of a
    ball proved to contain it (Sturm counts of the infinite matrices), so it is the
    correctly rounded value of the exact end.  The working precision grows by the one
    rule of :mod:`._precision` while the ball's ends round to different doubles; None
    when no double is proved (the caller falls back on the mpmath route or raises)."""
    from pendulab.analyses.floquet._arb import _Prec, nearest_double, to_ball
    from pendulab.analyses.floquet._precision import default_max_dps, precisions

    ends = []
    for family in ("a_even", "b_odd"):
        if family == "a_even" and X0 >= 0:
            ends.append(0.0)
            continue
        for w in precisions(DOUBLE_DPS, default_max_dps(DOUBLE_DPS), reach=0):
            got = _end_ball(family, X0, w)
            if got is None:
                continue
            ball, bits = got
            if scale is not None:
                with _Prec(bits):
                    ball = ball * to_ball(Fraction(scale))
            value = nearest_double(ball)
            if value is not None:
                ends.append(value)
                break
        else:
            return None
    return Limits((ends[0], ends[1]))


def _band_at_two_precisions(band, dps, what):
    """``band(ww)`` (a pair, computed at working precision ww) resolved to ``dps`` digits.

    Computed at w and w + STEP digits by the rule of _precision.autoprec until
    both agree to dps + 2 digits; a float pair when ``dps`` is None.
    """
    want = DOUBLE_DPS if dps is None else dps

    def compute(ww):
        with mpmath.workdps(ww):
            return band(ww)

    def accept(a, b, w2):
        with mpmath.workdps(w2):
            return agree(tuple(a), tuple(b), want)
    (lower, upper), _ = autoprec(compute, want, accept=accept, what=what)
    if dps is None:
        return Limits((float(lower), float(upper)))
    with mpmath.workdps(want):
        return Limits((+lower, +upper))


#: (theta0, dps) -> ends of the first band, kept for the process: the rod and the point mass
#: of a build meet the same theta0 = -4 (omega0/omega)^2.
_BANDS = {}


def _first_band_mp(th0, w):
    """|q| at the ends of the first band at theta0 = th0 (an mpf, th0 < 1), at dps w (memoised)."""
    key = (th0, w)
    if key not in _BANDS:
        if len(_BANDS) >= 4096:
            _BANDS.clear()
        _BANDS[key] = _first_band_mp_once(th0, w)
    return _BANDS[key]


def _power_of_two_bracket(h):
    """(lo, h(lo)) with lo = 2^-k, h(lo) > 0 >= h(2 lo), for h decreasing in q on (0, 1]
    with h(1) <= 0 < h(0+): the exponent k found by doubling, then by bisection."""
    far = 1
    while h(mpmath.ldexp(1, -far)) <= 0:
        far *= 2
    near = far // 2            # h(2^-near) <= 0 < h(2^-far)
    while far - near > 1:
        mid = (far + near) // 2
        if h(mpmath.ldexp(1, -mid)) > 0:
            far = mid
        else:
            near = mid
    lo = mpmath.ldexp(1, -far)
    return lo, h(lo)


def _first_band_mp_once(th0, w):
    """|q| at the ends of the first band at theta0 = th0 (an mpf, th0 < 1), to w digits.

    Near theta0 = 0 the lower end solves a_0(q) = theta0 with a_0(q) ~ -q^2/2 (DLMF
    28.6.1): both sides are of size |theta0|, so the characteristic value and the root
    are computed with -log10|theta0| more digits, which keeps w significant digits of
    the root however small it is (an absolute tolerance lost them below ~1e-16).
    """
    if th0 >= 1:
        raise InputError(f"theta0 = {mpmath.nstr(th0, 8)} >= 1: the first stable band at "
                         "theta0 >= 1 is not the one that starts at theta1 = 0")
    if th0 != 0 and abs(th0) < 1:
        w = w + int(mpmath.ceil(-mpmath.log10(abs(th0)))) + 2
    with mpmath.workdps(w):
        out = []
        for family in ("a_even", "b_odd"):
            if family == "a_even" and th0 >= 0:
                out.append(mpmath.mpf(0))
                continue

            def h(q, family=family):
                return _char_value_mp(family, 0, q, w) - th0

            Q = mpmath.mpf(1)
            while h(Q) > 0:
                Q *= 2
            lo = Q / 2 if Q > 1 else mpmath.mpf(0)
            if family == "a_even":
                lo = mpmath.mpf(0)
                hlo = -th0
            else:
                hlo = h(lo) if lo > 0 else 1 - th0
            if family == "a_even" and Q == 1 and abs(th0) < mpmath.mpf(10) ** -20:
                # a root far below 1 (omega0/omega -> 0): bracket it within a factor 2 by
                # bisecting the exponent, since Brent's method on [0, 1] approaches a root
                # of 1e-200 by some thousand bisections (15 s at omega0/omega = 1e-300)
                lo, hlo = _power_of_two_bracket(h)
                Q = 2 * lo
            root, _ = _illinois(h, lo, Q, hlo, h(Q), mpmath.mpf(10) ** (-w) * Q)
            out.append(root)
        return tuple(out)
