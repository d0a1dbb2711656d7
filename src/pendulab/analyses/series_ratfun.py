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
Inside the engine the numerator is a python-flint ``fmpz_poly`` (attribute
``poly``); the tuple ``num`` is made from it on first access.

Sums take the least common multiple of the denominators (the exponents' maximum,
no polynomial gcd); products add exponents.  :func:`linear_sum` forms a whole
sum of products over that common denominator, each product times its cofactor
prod (nu + j)**(E_j - e_j), with FLINT's polynomial multiplication (Kronecker
substitution and FFT in GMP integers; CPython's own big-integer product, used
before, is Karatsuba and was the cost at high order).  Lowest terms are
restored per coefficient by :func:`reduce`: a factor (nu + j) cancels exactly
while the numerator vanishes at nu = -j (exact evaluation, then exact division
by nu + j), and the integer content is divided out.  The result is the same
unique representation (lowest terms, den > 0) as before, so every printed
coefficient is unchanged.
"""

from fractions import Fraction
from math import gcd, lcm

__all__ = ["RatFun", "ZERO", "ONE", "linear_sum", "reduce", "reflect"]

class RatFun:
    """num(nu) / (den * prod (nu + j)**e) with integer data; immutable by convention.

    ``num`` is the tuple of Python integers (lowest degree first); inside the
    engine the numerator is held as a python-flint ``fmpz_poly`` (``poly``) and
    the tuple is made from it on first access.
    """

    __slots__ = ("_num", "_poly", "den", "exps")

    def __init__(self, num, den=1, exps=(), poly=None):
        self._num = None if num is None else tuple(num)
        self._poly = poly
        self.den = den
        self.exps = tuple(exps)

    @classmethod
    def from_poly(cls, poly, den=1, exps=()):
        """The value poly(nu) / (den * prod (nu + j)**e) for an ``fmpz_poly`` numerator."""
        return cls(None, den, exps, poly)

    @property
    def num(self):
        if self._num is None:
            self._num = tuple(int(c) for c in self._poly.coeffs())
        return self._num

    def __reduce__(self):
        # pickled as the plain data (fmpz_poly itself does not pickle)
        return (RatFun, (self.num, self.den, self.exps))

    @property
    def poly(self):
        if self._poly is None:
            from flint import fmpz_poly  # imported on first use: `import pendulab...series` stays light
            self._poly = fmpz_poly(list(self._num))
        return self._poly

    # -- inspection ------------------------------------------------------------------
    def is_zero(self):
        if self._num is not None:
            return not self._num
        return self._poly.is_zero()

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
        return RatFun.from_poly(self.poly * factor, self.den, self.exps)

    def divided_by_linear(self, const, j):
        """This value divided by const*(nu + j) (const a nonzero integer)."""
        poly = self.poly
        den = self.den * const
        if den < 0:
            den, poly = -den, -poly
        exps = dict(self.exps)
        exps[j] = exps.get(j, 0) + 1
        return RatFun.from_poly(poly, den, sorted(exps.items()))

    def negated(self):
        return RatFun.from_poly(-self.poly, self.den, self.exps)


ZERO = RatFun(())
ONE = RatFun((1,))


def reflect(x):
    """x(-nu): num(-nu) / (den * prod (-nu + j)**e) = (-1)**sum(e) num(-nu) / (den * prod (nu - j)**e)."""
    sign = -1 if sum(e for _, e in x.exps) % 2 else 1
    exps = sorted((-j, e) for j, e in x.exps)
    if x._num is None:  # engine-internal value: stay in flint
        from flint import fmpz_poly
        poly = x._poly(fmpz_poly([0, -1]))
        return RatFun.from_poly(-poly if sign < 0 else poly, x.den, exps)
    num = [(c if i % 2 == 0 else -c) * sign for i, c in enumerate(x.num)]
    return RatFun(num, x.den, exps)


# -- sums of products (python-flint) -----------------------------------------------------

_LINEAR = {}


def _linear_power(j, e):
    """(nu + j)**e as an fmpz_poly (cached)."""
    key = (j, e)
    value = _LINEAR.get(key)
    if value is None:
        from flint import fmpz_poly
        value = _LINEAR[key] = fmpz_poly([j, 1]) ** e
    return value


def _cofactor(exps):
    """prod (nu + j)**e as an fmpz_poly, by a balanced product tree."""
    factors = [_linear_power(j, e) for j, e in exps if e]
    if not factors:
        return None
    while len(factors) > 1:
        factors = [factors[i] * factors[i + 1] if i + 1 < len(factors) else factors[i]
                   for i in range(0, len(factors), 2)]
    return factors[0]


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
        for f in t:
            den *= f.den
            for j, e in f.exps:
                exps[j] = exps.get(j, 0) + e
        prods.append((t, den, exps))
    big_den = 1
    big_exps = {}
    for _, den, exps in prods:
        big_den = lcm(big_den, den)
        for j, e in exps.items():
            if e > big_exps.get(j, 0):
                big_exps[j] = e
    total = None
    for t, den, exps in prods:
        cof = _cofactor([(j, big_exps[j] - exps.get(j, 0)) for j in sorted(big_exps)])
        factors = [f.poly for f in t] + ([cof] if cof is not None else [])
        # multiply the shorter factors first
        factors.sort(key=lambda p: p.length())
        value = factors[0] * (big_den // den)
        for f in factors[1:]:
            value = value * f
        total = value if total is None else total + value
    if total.is_zero():
        return ZERO
    return RatFun.from_poly(total, big_den, sorted((j, e) for j, e in big_exps.items() if e))


# -- lowest terms ----------------------------------------------------------------------

def reduce(x):
    """``x`` in lowest terms: cancel common factors (nu + j) and the integer content."""
    if x.is_zero():
        return ZERO
    poly = x.poly
    exps = dict(x.exps)
    for j in sorted(exps):
        # a factor (nu + j) of the denominator cancels while the numerator vanishes at nu = -j
        while exps[j] and poly.degree() > 0 and poly(-j) == 0:
            poly, rem = divmod(poly, _linear_power(j, 1))
            exps[j] -= 1
    den = x.den
    g = gcd(int(poly.content()), den)
    if g > 1:
        poly = poly // g
        den //= g
    return RatFun.from_poly(poly, den, sorted((j, e) for j, e in exps.items() if e))
