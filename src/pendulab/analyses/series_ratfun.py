"""Exact rational functions of nu whose denominators are products of (nu + j).

Every coefficient of the perturbation series of 000 sec. 3 (alpha_n, and the
coefficient of cos((nu + 2k) tau) in c_n) is a rational function of nu whose
denominator is an integer times a product of linear factors (nu + j), j a
nonzero integer: the only divisions in the recursion are by 4k(nu + k)
(000 eq. 24 solved for c_n, see :mod:`pendulab.analyses.series`).  So a value
is stored as

    num(nu) / (den * prod_j (nu + j)**e_j)

with ``num`` a tuple of Python integers (coefficients, lowest degree first),
``den`` a positive integer and ``exps`` a sorted tuple of pairs (j, e_j), e_j > 0.

Sums take the least common multiple of the denominators (the exponents' maximum,
no polynomial gcd); products add exponents.  Polynomial products are done by
Kronecker substitution: a polynomial with integer coefficients is evaluated at
nu = 2**b (b larger than any coefficient of the result needs), the integers are
multiplied by Python's big-integer arithmetic, and the digits of the result,
read in base 2**b with signs, are the coefficients of the product.  A whole sum
of products is formed in that packed form and unpacked once.  Lowest terms are
restored per coefficient by :func:`reduce`: a factor (nu + j) cancels when the
numerator vanishes at nu = -j, which is tested modulo a prime (vectorised over
all j) and confirmed by exact synthetic division.
"""

from fractions import Fraction
from math import gcd, lcm, log2

import numpy as np

__all__ = ["RatFun", "ZERO", "ONE", "linear_sum", "reduce", "reflect"]

#: a prime below 2**26: residues times residues, summed over 2**10 terms, fit in int64
_PRIME = 67108859


class RatFun:
    """num(nu) / (den * prod (nu + j)**e) with integer data; immutable by convention."""

    __slots__ = ("num", "den", "exps", "_l1bits")

    def __init__(self, num, den=1, exps=()):
        self.num = tuple(num)
        self.den = den
        self.exps = tuple(exps)
        self._l1bits = None

    # -- inspection ------------------------------------------------------------------
    def is_zero(self):
        return not self.num

    def l1bits(self):
        """Bit length of the sum of |coefficients| of the numerator (a size bound)."""
        if self._l1bits is None:
            self._l1bits = sum(abs(c) for c in self.num).bit_length()
        return self._l1bits

    def degree(self):
        """(degree of the numerator, degree of the denominator)."""
        return len(self.num) - 1, sum(e for _, e in self.exps)

    def __eq__(self, other):
        return (isinstance(other, RatFun) and self.num == other.num
                and self.den == other.den and self.exps == other.exps)

    def __hash__(self):
        return hash((self.num, self.den, self.exps))

    def __repr__(self):
        return f"RatFun(num={self.num!r}, den={self.den!r}, exps={self.exps!r})"

    # -- values ----------------------------------------------------------------------
    def evaluate(self, x):
        """Value at ``x`` (int, Fraction, float, mpf, or numpy array): Horner, then the factors."""
        acc = 0
        for c in reversed(self.num):
            acc = acc * x + c
        den = self.den
        for j, e in self.exps:
            den = den * (x + j) ** e
        if isinstance(acc, (int, Fraction)) and isinstance(den, (int, Fraction)):
            return Fraction(acc) / den
        return acc / den

    def text(self, name="nu"):
        """Plain text num/(den*(nu + j)**e*...) in SymPy's syntax (deterministic)."""
        terms = []
        for i, c in reversed(list(enumerate(self.num))):
            if not c:
                continue
            power = "" if i == 0 else (name if i == 1 else f"{name}**{i}")
            if not power:
                body = str(abs(c))
            elif abs(c) == 1:
                body = power
            else:
                body = f"{abs(c)}*{power}"
            sign = "-" if c < 0 else "+"
            terms.append((sign, body))
        if not terms:
            return "0"
        numer = ("-" if terms[0][0] == "-" else "") + terms[0][1]
        numer += "".join(f" {sg} {b}" for sg, b in terms[1:])
        factors = [str(self.den)] if self.den != 1 else []
        for j, e in self.exps:
            f = f"({name} {'+' if j > 0 else '-'} {abs(j)})"
            factors.append(f if e == 1 else f"{f}**{e}")
        if not factors:
            return numer
        if len(terms) > 1:
            numer = f"({numer})"
        return f"{numer}/({'*'.join(factors)})"

    def to_sympy(self, nu):
        """The value as a SymPy expression in ``nu``, built as SymPy evaluates :meth:`text`.

        The operations are those of the text, in its order (the integer times
        the first factor, then the others, the numerator divided by the
        product), so the result equals ``sympify(self.text())`` and is a fixed
        point of printing and reading back (tested).
        """
        import sympy as sp
        numer = sp.Add(*[sp.Integer(c) * nu**i for i, c in enumerate(self.num) if c])
        if not self.exps and self.den == 1:
            return numer
        denom = sp.Integer(self.den)
        for j, e in self.exps:
            denom = denom * (nu + j) ** e
        return numer / denom

    def scaled(self, factor):
        """This value times the nonzero integer ``factor``."""
        if factor == 0:
            return ZERO
        return RatFun([c * factor for c in self.num], self.den, self.exps)

    def divided_by_linear(self, const, j):
        """This value divided by const*(nu + j) (const a nonzero integer)."""
        num = self.num
        den = self.den * const
        if den < 0:
            den, num = -den, [-c for c in num]
        exps = dict(self.exps)
        exps[j] = exps.get(j, 0) + 1
        return RatFun(num, den, sorted(exps.items()))

    def negated(self):
        return RatFun([-c for c in self.num], self.den, self.exps)


ZERO = RatFun(())
ONE = RatFun((1,))


def reflect(x):
    """x(-nu): num(-nu) / (den * prod (-nu + j)**e) = (-1)**sum(e) num(-nu) / (den * prod (nu - j)**e)."""
    sign = -1 if sum(e for _, e in x.exps) % 2 else 1
    num = [(c if i % 2 == 0 else -c) * sign for i, c in enumerate(x.num)]
    return RatFun(num, x.den, sorted((-j, e) for j, e in x.exps))


# -- Kronecker packing ---------------------------------------------------------------

def _ones(count, width):
    """sum_{i < count} 256**(width*i): the packed polynomial 1 + B + ... + B**(count-1)."""
    return int.from_bytes((b"\x01" + b"\x00" * (width - 1)) * count, "little")


def _pack(num, width):
    """num(2**(8*width)) for integer coefficients with |c| < 2**(8*width-1)."""
    if not num:
        return 0
    half = 1 << (8 * width - 1)
    data = b"".join((c + half).to_bytes(width, "little") for c in num)
    return int.from_bytes(data, "little") - (_ones(len(num), width) << (8 * width - 1))


def _unpack(value, width, count):
    """Coefficients (at most ``count``) of the polynomial packed in ``value`` (signed digits)."""
    shift = 8 * width - 1
    half = 1 << shift
    data = (value + (_ones(count, width) << shift)).to_bytes(count * width, "little")
    out = [int.from_bytes(data[i:i + width], "little") - half for i in range(0, count * width, width)]
    while out and out[-1] == 0:
        out.pop()
    return out


def _linear_product(base, exps):
    """prod (base + j)**e as an integer (the packed polynomial prod (nu + j)**e)."""
    factors = [(base + j) ** e for j, e in exps if e]
    while len(factors) > 1:  # balanced product tree
        factors = [factors[i] * factors[i + 1] if i + 1 < len(factors) else factors[i]
                   for i in range(0, len(factors), 2)]
    return factors[0] if factors else 1


def linear_sum(terms):
    """Exact sum of products: ``terms`` is a list of tuples of RatFun, each tuple a product.

    Returns the (not yet reduced) sum over the least common denominator.
    """
    terms = [t for t in terms if all(not f.is_zero() for f in t)]
    if not terms:
        return ZERO
    # denominator of each product, and their lcm
    prods = []
    for t in terms:
        den = 1
        exps = {}
        deg = 0
        bits = 0
        for f in t:
            den *= f.den
            for j, e in f.exps:
                exps[j] = exps.get(j, 0) + e
            deg += len(f.num) - 1
            bits += f.l1bits()
        prods.append((t, den, exps, deg, bits))
    big_den = 1
    big_exps = {}
    for _, den, exps, _, _ in prods:
        big_den = lcm(big_den, den)
        for j, e in exps.items():
            if e > big_exps.get(j, 0):
                big_exps[j] = e
    # bound on the coefficients of the result -> digit width
    bound = 0
    ndeg = 0
    for t, den, exps, deg, bits in prods:
        cof = [(j, big_exps[j] - exps.get(j, 0)) for j in big_exps]
        cof_bits = sum(e * log2(1 + abs(j)) for j, e in cof)
        cof_deg = sum(e for _, e in cof)
        bound = max(bound, bits + (big_den // den).bit_length() + int(cof_bits) + 2)
        ndeg = max(ndeg, deg + cof_deg)
    bound += len(prods).bit_length() + 2
    width = bound // 8 + 1
    base = 1 << (8 * width)
    total = 0
    for t, den, exps, deg, bits in prods:
        cof = [(j, big_exps[j] - exps.get(j, 0)) for j in sorted(big_exps)]
        # multiply the smaller factors first (Karatsuba is cheapest on balanced sizes)
        factors = sorted([_pack(f.num, width) for f in t] + [_linear_product(base, cof)],
                         key=lambda v: v.bit_length())
        value = big_den // den
        for f in factors:
            value *= f
        total += value
    num = _unpack(total, width, ndeg + 1)
    return RatFun(num, big_den, sorted((j, e) for j, e in big_exps.items() if e))


# -- lowest terms ----------------------------------------------------------------------

_POWERS = {}


def _powers(j, length):
    """(-j)**i mod p for i < length (cached, grown geometrically)."""
    row = _POWERS.get(j)
    if row is None or len(row) < length:
        size = max(length, 2 * (0 if row is None else len(row)), 16)
        row = np.empty(size, dtype=np.int64)
        v, m = 1, (-j) % _PRIME
        for i in range(size):
            row[i] = v
            v = v * m % _PRIME
        _POWERS[j] = row
    return row[:length]


def _root_candidates(num, js):
    """The j in ``js`` for which num(-j) = 0 modulo the prime (a superset of the true roots)."""
    if len(num) > 1000:  # keep the int64 sum below 2**63
        return list(js)
    residues = np.array([c % _PRIME for c in num], dtype=np.int64)
    table = np.stack([_powers(j, len(num)) for j in js])
    values = (table @ residues) % _PRIME
    return [j for j, v in zip(js, values) if v == 0]


def _divide_root(num, j):
    """(quotient, remainder) of num(nu) / (nu + j) by synthetic division."""
    root = -j
    out = [0] * (len(num) - 1)
    acc = 0
    for i in range(len(num) - 1, -1, -1):
        acc = acc * root + num[i]
        if i:
            out[i - 1] = acc
    return out, acc


def reduce(x):
    """``x`` in lowest terms: cancel common factors (nu + j) and the integer content."""
    num = list(x.num)
    if not num:
        return ZERO
    exps = dict(x.exps)
    pending = [j for j, e in exps.items() if e]
    while pending and len(num) > 1:
        hits = _root_candidates(num, pending)
        cancelled = []
        for j in hits:
            quotient, rem = _divide_root(num, j)
            if rem == 0:
                num = quotient
                exps[j] -= 1
                cancelled.append(j)
                if len(num) == 1:
                    break
        pending = [j for j in cancelled if exps[j] > 0]
    den = x.den
    g = den
    for c in num:
        g = gcd(g, c)
        if g == 1:
            break
    if g > 1:
        num = [c // g for c in num]
        den //= g
    return RatFun(num, den, sorted((j, e) for j, e in exps.items() if e))
