"""Large-argument expansions of J_nu, derived: McMahon's zeros and the phase.

Everything here is derived by the code from Hankel's expansion (DLMF 10.17.3)

    J_nu(x) ~ sqrt(2/(pi x)) (P(nu, x) cos w - Q(nu, x) sin w),  w = x - nu pi/2 - pi/4,
    P ~ sum_k (-1)^k a_2k(nu) x^-2k,  Q ~ sum_k (-1)^k a_2k+1(nu) x^-(2k+1),
    a_k(nu) = (mu - 1^2)(mu - 3^2)...(mu - (2k-1)^2) / (k! 8^k),  mu = 4 nu^2  (DLMF 10.17.1).

Writing P cos w - Q sin w = R cos(w + phi), tan phi = Q/P:

* the phase (DLMF 10.18.18 as a series): theta_nu(x) = w + phi(x), with
  J_nu = M cos theta_nu and Y_nu = M sin theta_nu, theta_nu increasing from
  -pi/2 at x = 0+; the k-th positive zero of J_nu is where theta_nu = (k - 1/2) pi.
  :func:`phase_coefficients` gives phi as a series in 1/x.
* McMahon's expansion (DLMF 10.21.19): j_nu,k = beta - phi(j_nu,k) with
  beta = (k + nu/2 - 1/4) pi; reverting the series gives
  j_nu,k ~ beta + sum_j c_j(mu) beta^-(2j-1).  :func:`mcmahon_coefficients`
  returns the c_j as exact polynomials in mu (python-flint fmpq_poly); the
  tests compare them with the coefficients printed in DLMF 10.21.19.

The series arithmetic is truncated power series in s = 1/beta (or 1/x) whose
coefficients are exact polynomials in mu, so the derivation takes
milliseconds where SymPy's ``series`` takes minutes.
:func:`quarter_period_asymptotics` then uses SymPy on the derived expansion
for the large-k behaviour of 002's quarter periods.
"""

from functools import lru_cache

from flint import fmpq, fmpq_poly

_MU = fmpq_poly([0, 1])

#: how many McMahon terms are derived (powers beta^-1 .. beta^-(2*TERMS-1))
TERMS = 10


@lru_cache(maxsize=None)
def hankel_coefficient(k):
    """a_k(nu) of DLMF 10.17.1 as an exact polynomial in mu = 4 nu^2 (formed once per k: the
    series reversion of :func:`mcmahon_coefficients` asks for each about 500 times)."""
    num = fmpq_poly([1])
    fact = 1
    for j in range(1, k + 1):
        num *= _MU - (2 * j - 1) ** 2
        fact *= j
    return num / (fact * 8 ** k)


# -- truncated power series with coefficients in Q[mu] -------------------------------------

def _zero(n):
    return [fmpq_poly(0) for _ in range(n + 1)]


def _mul(a, b, n):
    out = _zero(n)
    for i, ai in enumerate(a[:n + 1]):
        if ai == 0:
            continue
        for j in range(n + 1 - i):
            if b[j] != 0:
                out[i + j] += ai * b[j]
    return out


def _inv(a, n):
    """1/a for a series with a[0] = 1."""
    if a[0] != 1:
        raise ValueError("series inverse needs a leading 1")
    b = [fmpq_poly(1)] + _zero(n - 1)
    for m in range(1, n + 1):
        acc = fmpq_poly(0)
        for j in range(1, m + 1):
            if a[j] != 0 and b[m - j] != 0:
                acc += a[j] * b[m - j]
        b[m] = -acc
    return b


def _phi_of(y, n, terms):
    """arctan(Q/P) with P, Q the Hankel series evaluated at the series y (y[0] = 0)."""
    P, Q = _zero(n), _zero(n)
    power = [fmpq_poly(1)] + _zero(n - 1)
    for k in range(n + 1):
        term = [c * hankel_coefficient(k) * (-1) ** (k // 2) for c in power]
        target = P if k % 2 == 0 else Q
        for i in range(n + 1):
            target[i] += term[i]
        power = _mul(power, y, n)
    w = _mul(Q, _inv(P, n), n)
    w2 = _mul(w, w, n)
    out, wp = _zero(n), w
    for m in range(terms + 1):
        for i in range(n + 1):
            out[i] += wp[i] * fmpq((-1) ** m, 2 * m + 1)
        wp = _mul(wp, w2, n)
    return out


@lru_cache(maxsize=None)
def phase_coefficients(terms=TERMS):
    """phi(x) = theta_nu(x) - x + (nu/2 + 1/4) pi as sum_j d_j(mu) x^-j, j = 0 .. 2*terms+1.

    Returns a tuple of fmpq_poly in mu (index j = power of 1/x); only odd j are
    non-zero.  DLMF 10.18.18 prints the first terms: (mu-1)/(2 (4x)) + ...
    """
    n = 2 * terms + 1
    y = [fmpq_poly(0), fmpq_poly(1)] + _zero(n - 2)
    return tuple(_phi_of(y, n, terms))


@lru_cache(maxsize=None)
def mcmahon_coefficients(terms=TERMS):
    """c_j(mu) of j_nu,k ~ beta + sum_j c_j beta^-(2j-1), j = 1..terms (DLMF 10.21.19).

    Derived by reverting x = beta - phi(x) (see the module docstring) with
    fixed-point iteration on truncated series in s = 1/beta: pass i makes the
    coefficients of s^1 .. s^2i final (delta has no s^0, and y = s/(1 + s delta)
    needs delta only to s^(m-2) for its s^m), so pass i is computed truncated
    after s^2i, and only the last pass at the full order 2 terms + 1.  The
    coefficients are the same exact rationals as those of full-order passes
    throughout (tests/test_bessel_zeros.py compares the two), in a quarter of the time.
    Returns a tuple of fmpq_poly in mu, entry j-1 for c_j.
    """
    n = 2 * terms + 1
    delta = _zero(n)  # x - beta as a series in s
    for i in range(1, terms + 1):
        m = n if i == terms else min(n, 2 * i)  # pass i fixes s^1 .. s^2i
        one_s_delta = [fmpq_poly(1)] + delta[:m]  # 1 + s*delta
        y = [fmpq_poly(0)] + _inv(one_s_delta, m)[:m]  # 1/x = s/(1 + s delta)
        delta = [-c for c in _phi_of(y, m, terms)] + _zero(n - m - 1)
    if any(delta[j] != 0 for j in range(0, n + 1, 2)):
        raise ArithmeticError("McMahon reversion produced even powers")  # cannot happen
    return tuple(delta[2 * j - 1] for j in range(1, terms + 1))


def poly_at(poly, mu):
    """Evaluate an fmpq_poly at the rational mu exactly (an fmpq)."""
    acc = fmpq(0)
    for c in reversed(poly.coeffs()):
        acc = acc * mu + c
    return acc


def to_sympy(poly, symbol):
    """An fmpq_poly in mu as a SymPy polynomial in ``symbol``."""
    import sympy as sp
    return sum(sp.Rational(int(c.p), int(c.q)) * symbol ** i for i, c in enumerate(poly.coeffs()))


def mcmahon_sympy(nu, k, terms=6):
    """McMahon's j_nu,k as a SymPy expression in the symbol (or number) ``k`` (derived)."""
    import sympy as sp
    mu = 4 * sp.sympify(nu) ** 2
    beta = (k + sp.sympify(nu) / 2 - sp.Rational(1, 4)) * sp.pi
    coeffs = mcmahon_coefficients()[:terms]
    return beta + sum(to_sympy(c, mu) * beta ** -(2 * j - 1) for j, c in enumerate(coeffs, start=1))


def _scaled_zero(nu, shift, u, order):
    """u * j_{nu, 1/u + shift} from McMahon's expansion, as a polynomial in u to u^(order+2).

    With beta = pi (1 + a u)/u, a = shift + nu/2 - 1/4, every beta^-(2j-1) is
    (u/pi)^(2j-1) (1 + a u)^-(2j-1), expanded by the binomial series.
    """
    import sympy as sp
    nu = sp.sympify(nu)
    a = shift + nu / 2 - sp.Rational(1, 4)
    mu = 4 * nu ** 2
    top = order + 2
    out = sp.pi * (1 + a * u)
    for j, c in enumerate(mcmahon_coefficients(), start=1):
        m0 = 2 * j
        if m0 > top:
            break
        binom = sum(sp.binomial(-(2 * j - 1), m) * (a * u) ** m for m in range(top - m0 + 1))
        out += to_sympy(c, mu) * sp.pi ** -(2 * j - 1) * u ** m0 * binom
    return sp.expand(out)


def _square_ring():
    """The exact ring Q[U, P, R] of :func:`_scaled_square` (P = pi, R = 1/pi)."""
    import sympy as sp
    from sympy.polys.rings import ring
    return ring("U,P,R", sp.QQ)


def _scaled_square_poly(nu, shift, order):
    """(u j_{nu, 1/u + shift})^2 to u^(order+2) as an element of :func:`_square_ring` (U = u)."""
    import sympy as sp
    top = order + 2
    ring_, U, P, R = _square_ring()
    nu = sp.Rational(nu)
    a = sp.QQ.convert(shift + nu / 2 - sp.Rational(1, 4))
    mu = fmpq(int((4 * nu ** 2).p), int((4 * nu ** 2).q))

    def truncate(poly):
        return ring_({m: c for m, c in poly.terms() if m[0] <= top})
    au = a * U
    out = P * (1 + au)
    for j, c in enumerate(mcmahon_coefficients(), start=1):
        m0 = 2 * j
        if m0 > top:
            break
        cj = poly_at(c, mu)
        binom = sum((int(sp.binomial(-(2 * j - 1), m)) * au ** m for m in range(top - m0 + 1)),
                    ring_.zero)
        out += sp.QQ(int(cj.p), int(cj.q)) * R ** (2 * j - 1) * U ** m0 * binom
    return truncate(out * out)


def _scaled_square(nu, shift, u, order):
    """(u j_{nu, 1/u + shift})^2 to u^(order+2): :func:`_scaled_zero` squared and truncated.

    The same polynomial, computed in the exact ring Q[u, P, R] with P = pi and
    R = 1/pi (SymPy's sparse polynomials; P R = 1 is applied when the terms
    are written out) instead of expanding SymPy expressions: a tenth of the time.
    """
    import sympy as sp
    sq = _scaled_square_poly(nu, shift, order)
    return sp.expand(sp.Add(*(_coefficient(m, c) * u ** m[0] for m, c in sq.terms())))


def _coefficient(monomial, c):
    """The SymPy number c pi^(p - r) of a term c U^i P^p R^r of :func:`_square_ring` (P R = 1)."""
    import sympy as sp
    return sp.Rational(int(c.numerator), int(c.denominator)) * sp.pi ** (monomial[1] - monomial[2])


def _in_k(poly, k, limit=True):
    """k^2 poly(U = 1/k) written out (P R = 1), and its limit as k -> oo (None if not ``limit``).

    The expression is a finite sum c pi^e k^p; its terms are gathered by the power p of k.
    With no positive power left the limit is the sum of the k^0 terms (every other term
    tends to 0); otherwise SymPy's ``limit`` decides it.
    """
    import sympy as sp
    by_power = {}
    for m, c in poly.terms():
        by_power.setdefault(2 - m[0], []).append(_coefficient(m, c))
    expr = sp.Add(*(c * k ** p for p, cs in by_power.items() for c in cs))
    if not limit:
        return expr, None
    growing = [p for p, cs in by_power.items() if p > 0 and sp.Add(*cs) != 0]
    return expr, sp.limit(expr, k, sp.oo) if growing else sp.Add(*by_power.get(0, []))


def quarter_period_asymptotics(order=4):
    """Large-k behaviour of 002's quarter periods, derived from McMahon's expansion.

    inward[k] = j_{1,k+2}^2 - j_{2,k+1}^2 and outward[k] = j_{2,k+2}^2 - j_{1,k+2}^2
    (unit v0/(4 g)); the margins are after[k] = inward[k] - outward[k] (the
    outward swing after the inward one) and before[k] = inward[k] - outward[k-1].
    Returns a dict of SymPy expressions in the positive symbol ``k`` (key "k"):
    each quantity expanded in powers of 1/k down to k^-order, and the limits
    of the two margins as k -> oo.  Nothing is typed in: the expansions come
    from :func:`mcmahon_coefficients`, the reversion of Hankel's expansion.

    The sums and differences are taken in the exact ring of :func:`_scaled_square_poly`
    and written out in k once (:func:`_in_k`); tests/test_bessel_periods.py
    compares the result with SymPy's own route (substitution, ``expand``, ``limit``).
    """
    import sympy as sp
    k = sp.Symbol("k", positive=True)

    squares = {}

    def square(nu, shift):  # u^2 j_{nu,k+shift}^2, truncated (each (nu, shift) expanded once)
        if (nu, shift) not in squares:
            squares[nu, shift] = _scaled_square_poly(nu, shift, order)
        return squares[nu, shift]

    inward = square(1, 2) - square(2, 1)
    outward = square(2, 2) - square(1, 2)
    outward_before = square(2, 1) - square(1, 1)
    out = {"inward": _in_k(inward, k, limit=False)[0], "outward": _in_k(outward, k, limit=False)[0]}
    out["margin_after"], out["limit_margin_after"] = _in_k(inward - outward, k)
    out["margin_before"], out["limit_margin_before"] = _in_k(inward - outward_before, k)
    out["k"] = k
    return out
