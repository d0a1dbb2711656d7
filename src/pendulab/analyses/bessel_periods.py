"""Quarter periods of the variable-length pendulum from certified zeros (002, last page).

For L = L0 + r t the canonical stage gives z = (2/|r|) sqrt(g L) and the
B = 0 solution theta = -C z^-1 J1(z) (002, "Consequência"): theta = 0 where
J1(z) = 0 and theta' = 0 where J2(z) = 0 (d/dz[z^-1 J1] = -z^-1 J2).  Since
L = |r|^2 z^2/(4 g), a time interval is (|r|/(4 g)) |delta z^2|; durations
below are in that unit (002 writes v0/(4g)).

* **Growing string** (r > 0): z increases from z0 = j_2,m (the source takes
  m = 1).  inward[k] = j_1,m+k+1^2 - j_2,m+k^2 (from an extremum to theta = 0),
  outward[k] = j_2,m+k+1^2 - j_1,m+k+1^2; for m = 1 these are 002's
  22.8438, 21.6315, 32.6495, ...  The swings never end.
* **Shortening string** (r < 0): z decreases from z0 = j_2,m toward 0, so the
  order reverses: inward[i] = j_2,m-i^2 - j_1,m-i^2 (i = 0..m-1), outward[i] =
  j_1,m-i^2 - j_2,m-i-1^2 (i = 0..m-2), 2m - 1 quarter periods in all, and
  after the last zero of J1 the string reaches L = 0 (z = 0) at
  t = L0/|r| = j_2,m^2 in the unit above, before another extremum.

The order of the events (the zeros of J1 and J2 interlace,
j_1,k < j_2,k < j_1,k+1) is proved on the certified balls, and the source's
claim, "a swing toward equilibrium lasts longer than the outward swing before
it and after it", is decided on balls for every k with its two margins.
"""

import math
from dataclasses import dataclass, field

from flint import arb

from pendulab.analyses.bessel_zeros import (CertificationError, _Prec, ball_digits, bessel_zeros,
                                            bits_for, check_count, check_dps, check_interlacing)
from pendulab.errors import InputError

GROWING, SHORTENING = "growing", "shortening"


@dataclass
class QuarterPeriods:
    """Durations (balls and strings at ``dps`` significant digits, every digit correct).

    ``inward``/``outward`` in time order (see the module docstring for the
    indices); ``margin_after[k]`` = inward[k] - (outward swing after it),
    ``margin_before[k]`` = inward[k] - (outward swing before it), present
    where that swing exists; ``claim_holds`` is True when every margin is
    certainly positive, False when one is certainly negative, and None when
    there is no margin (no outward swing beside an inward one).
    ``time_to_zero_length`` (shortening only) is j_2,m^2.
    """

    direction: str
    start: int
    dps: int
    inward: list = field(default_factory=list)
    outward: list = field(default_factory=list)
    margin_after: list = field(default_factory=list)
    margin_before: list = field(default_factory=list)
    inward_balls: list = field(default_factory=list)
    outward_balls: list = field(default_factory=list)
    after_balls: list = field(default_factory=list)
    before_balls: list = field(default_factory=list)
    zeros_j1: list = field(default_factory=list)
    zeros_j2: list = field(default_factory=list)
    claim_holds: bool = None
    time_to_zero_length: str = None
    interlacing_checks: int = 0

    def _verdict(self):
        return {True: "the claim holds (every margin positive)",
                False: "the claim fails (a margin is negative)",
                None: "no margin to decide the claim"}[self.claim_holds]

    def _rows(self):
        return [[str(k), self.inward[k] if k < len(self.inward) else "",
                 self.outward[k] if k < len(self.outward) else ""]
                for k in range(max(len(self.inward), len(self.outward)))]

    def _repr_latex_(self):
        """The inward and outward quarter periods as a table for a notebook
        (:func:`pendulab.latex.math_table`), with the verdict on the source's claim."""
        from pendulab.latex import math_table, text
        lines = [text(f"quarter periods of the {self.direction} string, {self.dps} digits"),
                 text("(unit ") + r"|\dot L|/(4g)" + text(f"): {self._verdict()}")]
        return math_table(lines, ["k", text("inward"), text("outward")], self._rows())

    def _repr_html_(self):
        """The same table in HTML (:func:`pendulab.latex.html_table`), one row per k."""
        from pendulab.latex import html_table
        caption = (f"quarter periods of the {self.direction} string, {self.dps} digits "
                   f"(unit |dL/dt|/(4g)): {self._verdict()}")
        return html_table(caption, ["k", "inward", "outward"], self._rows())


def direction_of(rate):
    """GROWING or SHORTENING from the sign of the canonical stage's rate dL/dt (a SymPy number
    or expression); refuses a rate whose sign SymPy cannot decide, or zero."""
    import sympy as sp
    rate = sp.sympify(rate)
    if rate.is_positive:
        return GROWING
    if rate.is_negative:
        return SHORTENING
    if rate.is_zero:
        raise InputError("the length does not change (dL/dt = 0): no Bessel quarter periods")
    raise InputError(f"the sign of the rate dL/dt = {rate} is unknown; declare it (e.g. L0 + v0*t "
                     "or L0 - v0*t with v0 > 0)")


def quarter_periods(count, dps, direction=GROWING, start=None):
    """Certified quarter periods of the B = 0 motion (module docstring).

    ``count`` quarter periods (inward and outward each, growing string; in
    total, shortening string), ``dps`` significant digits; ``start`` = m of
    z0 = j_2,m (growing: default 1, the source's choice; shortening: default
    the smallest m with 2m - 1 >= count).  Returns :class:`QuarterPeriods`.
    """
    check_count(count, "count", 10_000)
    check_dps(dps)
    if direction not in (GROWING, SHORTENING):
        raise InputError(f"direction must be {GROWING!r} or {SHORTENING!r}, got {direction!r}")
    if start is None:
        start = 1 if direction == GROWING else (count + 2) // 2
    check_count(start, "start", 10_000)
    if direction == SHORTENING and count > 2 * start - 1:
        raise InputError(f"a shortening string started at z0 = j_2,{start} has only {2 * start - 1} "
                         f"quarter periods before L reaches 0, not {count}")
    nmax = start + count + 1 if direction == GROWING else start
    extra = int(math.log2(4 * nmax + 8)) + 8  # differences of squares lose log2(x) bits
    for _ in range(MAX_RAISES):
        res = _compute(count, dps, direction, start, nmax, extra)
        if res is not None:
            return res
        extra += 32
    raise CertificationError(f"a quarter period or margin still cannot be rounded to {dps} digits "
                             f"with {32 * MAX_RAISES} more bits: its ball holds 0 or a rounding "
                             "boundary (a margin of exactly 0 would never be decided)")


#: how many times :func:`quarter_periods` raises the precision (by 32 bits) before it refuses
MAX_RAISES = 16


def _compute(count, dps, direction, m, nmax, extra):
    z1 = bessel_zeros(1, nmax, dps, extra_bits=extra)
    z2 = bessel_zeros(2, nmax, dps, extra_bits=extra)
    out = QuarterPeriods(direction, m, dps, zeros_j1=z1.strings, zeros_j2=z2.strings)
    j1 = [None] + z1.balls  # 1-based
    j2 = [None] + z2.balls
    with _Prec(bits_for(dps) + extra + 16):
        out.interlacing_checks = check_interlacing(z1.balls, z2.balls)
        if direction == GROWING:
            ins = [j1[m + k + 1] ** 2 - j2[m + k] ** 2 for k in range(count)]
            outs = [j2[m + k + 1] ** 2 - j1[m + k + 1] ** 2 for k in range(count)]
            after = [ins[k] - outs[k] for k in range(count)]
            before = [ins[k] - outs[k - 1] for k in range(1, count)]
        else:
            seq = []  # time order: inward, outward, inward, ... ending with the inward j_2,1 -> j_1,1
            for i in range(m):
                seq.append(("in", j2[m - i] ** 2 - j1[m - i] ** 2))
                if i < m - 1:
                    seq.append(("out", j1[m - i] ** 2 - j2[m - i - 1] ** 2))
            seq = seq[:count]
            ins = [v for kind, v in seq if kind == "in"]
            outs = [v for kind, v in seq if kind == "out"]
            after = [ins[i] - outs[i] for i in range(len(ins)) if i < len(outs)]
            before = [ins[i] - outs[i - 1] for i in range(1, len(ins)) if i - 1 < len(outs)]
            ttz = j2[m] ** 2
            out.time_to_zero_length = ball_digits(ttz, dps)
            if out.time_to_zero_length is None:
                return None
        texts = [[ball_digits(b, dps) for b in group] for group in (ins, outs, after, before)]
    if any(t is None for group in texts for t in group):
        return None
    out.inward, out.outward, out.margin_after, out.margin_before = texts
    out.inward_balls, out.outward_balls, out.after_balls, out.before_balls = ins, outs, after, before
    margins = after + before
    if not margins:  # no outward swing beside an inward one: nothing to compare
        out.claim_holds = None
    elif all(b > 0 for b in margins):
        out.claim_holds = True
    elif any(b < 0 for b in margins):
        out.claim_holds = False
    return out


def margin_limits():
    """The limits of the two margins as k -> oo, derived (SymPy) from McMahon's expansion.

    Returns (after, before, expansions): 6 - pi^2/2 and 6 + pi^2/2 come out of
    :func:`pendulab.analyses.bessel_asymptotics.quarter_period_asymptotics`.
    """
    from pendulab.analyses.bessel_asymptotics import quarter_period_asymptotics
    asym = quarter_period_asymptotics()
    return asym["limit_margin_after"], asym["limit_margin_before"], asym


def asymptotic_value(expr, k, dps=30):
    """Evaluate one of the derived expansions (a SymPy expression in the symbol ``k``) at k."""
    import sympy as sp
    ksym = [s for s in expr.free_symbols if s.name == "k"]
    val = expr.subs(ksym[0], k) if ksym else expr
    return sp.N(val, dps)


def as_arb(x):
    """A SymPy/mpmath number as an arb (for comparisons with balls)."""
    return arb(str(x))
