"""Safe reading and deterministic writing of expressions.

Scene files and command lines carry expressions as text.  They are never
handed to ``eval`` (which ``sympy.sympify`` and ``parse_expr`` do): the text is
parsed by :mod:`ast` and the tree is walked against a whitelist, building the
SymPy object node by node.  Attribute access, subscripts, lambdas, keyword
arguments, dunder names and anything else outside plain arithmetic, numbers,
names and whitelisted function calls is refused with an :class:`InputError`.

Decimal literals become exact rationals (``0.1`` -> ``1/10``): results stay
exact until a number is asked for.

``dump_expr`` prints with SymPy's ``StrPrinter`` and ``load_expr`` reads that
text back to an equal expression, with pendulab's own names (``I`` is the
moment of inertia, not the imaginary unit):

>>> from pendulab.symbols import I, m, l
>>> e = 4*m*l**2/3 + I
>>> dump_expr(e)
'I + 4*l**2*m/3'
>>> load_expr(dump_expr(e)) == e
True
>>> parse("__import__('os')")
Traceback (most recent call last):
...
pendulab.errors.InputError: name '__import__' is not allowed (names may not start with '_')
"""

import ast
import re
import sys

import sympy as sp

from pendulab.errors import InputError
from pendulab import symbols as S

#: Longest expression text accepted (a guard against pathological input).
MAX_LENGTH = 4000
#: Deepest nesting of the syntax tree accepted.  A flat sum or product
#: (``a1 + a2 + ... + a70``) and a run of signs (``- - x``) count as one level.
MAX_DEPTH = 60
#: Largest numeric exponent allowed (``t**(10**10)`` would hang the derivation).
MAX_NUMERIC_EXPONENT = 1000
#: Exact numbers in an expression are at most 10**MAX_NUMBER_DIGITS in numerator and
#: denominator (``1e1000`` and ``10**1000`` are the largest; ``1e1001``, ``(10**400)**3``
#: and ``1.5e-1000``, whose denominator is 10**1001, are refused):
#: ``((10**1000)**1000)**1000`` or ``1e999999999`` would hang the parser.  (Python prints
#: no integer of more than 4300 digits unless told to: the ``pendulab`` command is;
#: :func:`dump_expr` and :func:`latex` say so in one line otherwise.)
MAX_NUMBER_DIGITS = 1000
_MAX_NUMBER = 10 ** MAX_NUMBER_DIGITS
#: log2 of the largest number, for estimating a power before it is computed
_MAX_LOG2 = MAX_NUMBER_DIGITS * 3.321928094887362
#: A bound in bits above every number allowed (a quick first test)
MAX_NUMBER_BITS = int(_MAX_LOG2) + 2
#: Highest total derivative order accepted: the orders of nested
#: ``Derivative(Derivative(f, (t, 20)), (t, 20))`` add up (40 here).
MAX_DERIVATIVE_ORDER = 20
#: Most terms an expression may have once multiplied out (estimated from its
#: tree without expanding: ``(a+b+c+d+t)**200`` would have 70 million).
MAX_EXPANDED_TERMS = 2000
#: Largest expression (nodes of its tree) a derivative in an expression may
#: produce, checked one differentiation at a time.
MAX_SIZE = 5000
#: Names that would stand for infinity or NaN (SymPy's and Python's spellings).
NOT_FINITE_NAMES = frozenset({"inf", "Inf", "nan", "NaN", "oo", "zoo", "infinity", "Infinity",
                              "ComplexInfinity"})


def _function_for(name):
    """The undefined function called ``name`` (``theta(t)``, ``L(t)``, ...).

    Functions other than pendulab's own are real (a pivot height ``y0(t)``).
    """
    if name == "theta":
        return S.theta
    if name == "L":
        return S.L
    return sp.Function(name, real=True)


def derivative_order(expr):
    """Total order of the derivatives in ``expr`` (nested ones add up; 0 if none)."""
    best = 0
    for d in expr.atoms(sp.Derivative):
        best = max(best, sum(int(n) for _, n in d.variable_count) + derivative_order(d.expr))
    return best


def _derivative(*args):
    """``Derivative`` with a bounded total order and a bounded result size.

    The order counts the derivatives already inside the expression
    (:data:`MAX_DERIVATIVE_ORDER`); an explicit expression is differentiated
    once per order to check that no step grows beyond :data:`MAX_SIZE`
    nodes (the value returned stays unevaluated, as the user wrote it).
    """
    if not args or isinstance(args[0], sp.Tuple):
        raise InputError("Derivative needs an expression first, then (t, n)")
    total = derivative_order(args[0])
    steps = []
    for spec in args[1:]:
        if isinstance(spec, sp.Tuple):
            if len(spec) != 2 or not isinstance(spec[0], sp.Symbol):
                raise InputError("a derivative is taken as (symbol, order), e.g. (t, 2)")
            var, count = spec
        elif isinstance(spec, sp.Symbol):
            var, count = spec, sp.Integer(1)
        else:
            raise InputError("a derivative is taken with respect to a symbol, e.g. (t, 2)")
        if not (isinstance(count, sp.Integer) and count >= 0):
            raise InputError("the order of a derivative must be a non-negative integer")
        total += int(count)
        if total > MAX_DERIVATIVE_ORDER:
            raise InputError(f"derivatives of total order {total} are too high "
                             f"(limit {MAX_DERIVATIVE_ORDER}, nested ones add up)")
        steps += [var] * int(count)
    value = args[0].doit() if args[0].has(sp.Derivative) else args[0]
    for i, var in enumerate(steps, 1):
        value = sp.diff(value, var)
        if size(value, MAX_SIZE) > MAX_SIZE:
            raise InputError(f"derivative number {i} of {sp.sstr(args[0])[:40]} already has more "
                             f"than {MAX_SIZE} nodes (limit {MAX_SIZE})")
    return sp.Derivative(*args)


def size(expr, cap=None):
    """Number of nodes of ``expr``'s tree; counting stops just past ``cap``."""
    n = 0
    stack = [expr]
    while stack:
        e = stack.pop()
        n += 1
        if cap is not None and n > cap:
            return n
        stack.extend(e.args)
    return n


def expanded_terms(expr, cap=MAX_EXPANDED_TERMS):
    """Estimated number of terms of ``expr`` multiplied out (an upper bound, at most cap+1).

    A sum adds, a product multiplies, a power (b)**n of a b-term sum has
    C(n+b-1, b-1) terms; the arguments of functions are estimated alone.
    Raises :class:`InputError` naming the part whose estimate passes ``cap``.
    """
    from math import comb

    def est(e):
        if e.is_Atom:
            return 1
        if e.is_Add:
            n = sum(est(a) for a in e.args)
        elif e.is_Mul:
            n = 1
            for a in e.args:
                n = min(n * est(a), cap + 1)
        elif e.is_Pow:
            b = est(e.base)
            x = e.exp
            est(x)
            if b > 1 and x.is_Integer:
                k = abs(int(x))
                n = comb(k + b - 1, b - 1) if b <= cap else cap + 1
                if n <= cap and x < 0:
                    n = 1  # a denominator: one factor of each term, multiplied out on its own
            else:
                n = b
        else:
            for a in e.args:
                est(a)
            n = 1
        if n > cap:
            raise InputError(f"{sp.sstr(e)[:40]} would have {_rough(n, cap)} terms "
                             f"when multiplied out (limit {cap})")
        return n
    return est(expr)


def _rough(n, cap):
    if n == cap + 1:
        return f"more than {cap}"
    return f"about {float(n):.2g}" if n < 10**15 else f"about 10^{len(str(n)) - 1}"


def _not_finite(expr):
    """True when ``expr`` contains an infinity or NaN (zoo is what 1/0 gives)."""
    return expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan)


def _bits(x):
    """Size in bits of an exact rational (0 for anything else)."""
    if isinstance(x, sp.Rational):
        return max(int(abs(x.p)).bit_length(), int(x.q).bit_length())
    return 0


def _rationals(expr):
    return [expr] if isinstance(expr, sp.Rational) else list(expr.atoms(sp.Rational))


def _largest_log2(expr):
    """log2 of the largest numerator or denominator of an exact rational in ``expr`` (0 when
    there is none): a power x**y makes numbers of about y times that."""
    import math
    return max((math.log2(n) for a in _rationals(expr) for n in (abs(int(a.p)), int(a.q)) if n > 1),
               default=0.0)


def _check_size(value):
    """``value``, or an InputError when a number in it passes 10**MAX_NUMBER_DIGITS (numerator
    or denominator)."""
    for a in _rationals(value):
        if abs(int(a.p)) > _MAX_NUMBER or int(a.q) > _MAX_NUMBER:
            raise InputError(f"a number in the expression is larger than 10**{MAX_NUMBER_DIGITS} "
                             "(in its numerator or denominator)")
    return value


#: A decimal literal's parts: digits (with a point) and exponent
_DECIMAL = re.compile(r"([0-9_]*\.?[0-9_]*)(?:[eE]([+-]?[0-9_]+))?\Z")


_FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "cot": sp.cot,
    "sec": sp.sec, "csc": sp.csc,
    "asin": sp.asin, "acos": sp.acos, "atan": sp.atan, "atan2": sp.atan2,
    "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh,
    "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt, "Abs": sp.Abs,
    "sign": sp.sign, "Heaviside": sp.Heaviside,
    "besselj": sp.besselj, "bessely": sp.bessely,
    "Derivative": _derivative, "Rational": sp.Rational,
    "Integer": sp.Integer,
}
_CONSTANTS = {"pi": sp.pi}
#: SymPy names of things that are not expressions (refused even as function names).
NOT_EXPRESSIONS = {
    **dict.fromkeys(("Eq", "Ne", "Lt", "Le", "Gt", "Ge", "Equality", "Unequality"),
                    "a relation"),
    **dict.fromkeys(("And", "Or", "Not", "Xor", "Implies", "ITE"), "a logical operation"),
    **dict.fromkeys(("Tuple", "Matrix", "FiniteSet", "Interval", "Dict"), "a container"),
    **dict.fromkeys(("Piecewise", "Lambda", "Symbol", "Function", "sympify", "S"),
                    "SymPy machinery"),
}
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def _check_name(name):
    if name.startswith("_"):
        raise InputError(f"name {name!r} is not allowed (names may not start with '_')")
    if not _NAME.match(name):
        raise InputError(f"name {name!r} is not allowed")


class _Builder:
    def __init__(self, namespace, functions_allowed):
        self.namespace = namespace
        self.functions_allowed = functions_allowed

    def build(self, node, depth=0):
        if depth > MAX_DEPTH:
            raise InputError(f"expression is nested too deeply (limit {MAX_DEPTH} levels of "
                             "parentheses and function calls)")
        method = getattr(self, "_" + type(node).__name__, None)
        if method is None:
            raise InputError(f"{_describe(node)} is not allowed in an expression")
        return method(node, depth + 1)

    def _Expression(self, node, d):
        return self.build(node.body, d)

    def _Constant(self, node, d):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"constant {v!r} is not a number")
        if isinstance(v, int):
            if v.bit_length() > MAX_NUMBER_BITS or v > _MAX_NUMBER:
                text = ast.get_source_segment(self.source, node) or "an integer"
                raise InputError(f"the number {text[:20]}... is larger than "
                                 f"10**{MAX_NUMBER_DIGITS}")
            return sp.Integer(v)
        text = (ast.get_source_segment(self.source, node) or repr(v)).replace("_", "")
        found = _DECIMAL.match(text)
        if found is None or (found.group(2) is not None
                             and abs(int(found.group(2))) > MAX_NUMBER_DIGITS):
            raise InputError(f"the number {text[:30]} is out of range (numbers from "
                             f"10**-{MAX_NUMBER_DIGITS} to 10**{MAX_NUMBER_DIGITS})")
        return _check_size(sp.Rational(text))

    def _Name(self, node, d):
        name = node.id
        _check_name(name)
        if name in NOT_FINITE_NAMES:
            raise InputError(f"name {name!r} is not allowed: infinity and NaN are not values "
                             "(give a finite number or a symbol)")
        if name in _CONSTANTS:
            return _CONSTANTS[name]
        if name in self.namespace:
            return self.namespace[name]
        if name in _FUNCTIONS:
            raise InputError(f"function {name!r} used without arguments")
        if name == "theta":
            raise InputError("'theta' is the angle, a function: write theta(t)")
        # Symbols a user introduces (the b of a drive a*cos(omega*t) + b*sin(omega*t))
        # are real: every quantity of these pendulums is.
        return sp.Symbol(name, real=True)

    def _Tuple(self, node, d):
        raise InputError("a tuple is not an expression (only Derivative takes (t, n))")

    def _UnaryOp(self, node, d):
        # A run of signs (- - - x) is one level, walked without recursion.
        negate = False
        while isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.USub):
                negate = not negate
            elif not isinstance(node.op, ast.UAdd):
                raise InputError(f"operator {type(node.op).__name__} is not allowed")
            node = node.operand
        v = self.build(node, d)
        return -v if negate else v

    def _BinOp(self, node, d):
        op = node.op
        # Folded left to right with the binary operators, exactly as Python would
        # (2*(nu - 1) distributes to 2*nu - 2 only as a binary product).
        if isinstance(op, (ast.Add, ast.Sub)):
            (_, value), *rest = self._chain(node, d, ast.Add, ast.Sub)
            for sign, term in rest:
                value = value + term if sign > 0 else value - term
            return value
        if isinstance(op, (ast.Mult, ast.Div)):
            (_, value), *rest = self._chain(node, d, ast.Mult, ast.Div)
            for sign, factor in rest:
                if sign < 0:
                    if factor == 0:
                        raise InputError("division by zero in expression")
                    value = value / factor
                else:
                    value = value * factor
                _check_size(value.as_coeff_Mul()[0])  # numbers multiply into the coefficient
            return value
        x = self.build(node.left, d)
        y = self.build(node.right, d)
        if isinstance(op, ast.BitXor):
            raise InputError("'^' is not a power here (it binds looser than '*'); write '**'")
        if isinstance(op, ast.Pow):
            if y.is_number and y.is_real and abs(y) > MAX_NUMERIC_EXPONENT:
                raise InputError(f"numeric exponent {y} is too large (limit {MAX_NUMERIC_EXPONENT})")
            if y.is_number and _largest_log2(x) * abs(float(sp.re(y))) > _MAX_LOG2 + 1e-9:
                base = ast.get_source_segment(self.source, node.left) or "the base"
                base = base if re.fullmatch(r"[\w.]+", base) else f"({base})"
                raise InputError(f"the power {base[:30]}**{y} is too large a number (larger "
                                 f"than 10**{MAX_NUMBER_DIGITS})")
            if x == 0 and y.is_number and y.is_negative:
                raise InputError(f"division by zero in expression (0**{y})")
            return x ** y
        raise InputError(f"operator {type(op).__name__} is not allowed")

    def _chain(self, node, d, plus, minus):
        """Operands of a left-nested chain a + b - c ... as (sign, value), without recursion."""
        rights = []
        while isinstance(node, ast.BinOp) and isinstance(node.op, (plus, minus)):
            rights.append((-1 if isinstance(node.op, minus) else 1, node.right))
            node = node.left
        out = [(1, self.build(node, d))]
        for sign, right in reversed(rights):
            out.append((sign, self.build(right, d)))
        return out

    def _Call(self, node, d):
        if node.keywords:
            raise InputError("keyword arguments are not allowed in an expression")
        if not isinstance(node.func, ast.Name):
            raise InputError(f"{_describe(node.func)} is not allowed in an expression")
        name = node.func.id
        _check_name(name)
        if name in NOT_EXPRESSIONS and name not in _FUNCTIONS:  # said before its arguments are read
            raise InputError(f"{name}(...) is not allowed: {NOT_EXPRESSIONS[name]}, not an "
                             "expression")
        args = []
        for a in node.args:
            if name == "Derivative" and args and isinstance(a, ast.Tuple):
                args.append(sp.Tuple(*[self.build(e, d + 1) for e in a.elts]))
            else:
                args.append(self.build(a, d))
        text = (ast.get_source_segment(self.source, node) or name)[:60]
        if name in ("theta", "L") and self.functions_allowed and len(args) == 1:
            return _function_for(name)(*args)
        if name in _FUNCTIONS:
            if name == "Rational" and len(args) == 2 and args[1] == 0:
                raise InputError(f"division by zero in {text}")
            if name == "Integer" and not (len(args) == 1 and args[0].is_Integer):
                raise InputError(f"{text}: Integer takes one whole number")
            try:
                value = _FUNCTIONS[name](*args)
            except InputError:
                raise
            except (TypeError, ValueError, ArithmeticError) as exc:
                raise InputError(f"bad arguments to {name}: {exc}") from None
            if not isinstance(value, sp.Expr):
                raise InputError(f"{text} is not an expression")
            if _not_finite(value):
                raise InputError(f"{text} is not finite (it is {sp.sstr(value)[:20]}: a division "
                                 "by zero or a pole)")
            return value
        if name in self.namespace or name in _CONSTANTS:
            raise InputError(f"{name!r} is a symbol, not a function")
        if name in NOT_EXPRESSIONS:
            raise InputError(f"{name}(...) is not allowed: {NOT_EXPRESSIONS[name]}, not an "
                             "expression")
        if not self.functions_allowed:
            raise InputError(f"unknown function {name!r}")
        if not args:
            raise InputError(f"function {name!r} called without arguments")
        return _function_for(name)(*args)


def _describe(node):
    kinds = {
        "Attribute": "attribute access", "Subscript": "subscripting",
        "Lambda": "lambda", "Compare": "comparison", "BoolOp": "boolean operator",
        "ListComp": "comprehension", "GeneratorExp": "generator", "Starred": "star",
        "JoinedStr": "f-string", "NamedExpr": "assignment", "List": "list",
        "Dict": "dict", "Set": "set", "IfExp": "conditional",
    }
    return kinds.get(type(node).__name__, type(node).__name__)


def parse(text, namespace=None, *, functions=True):
    """Parse expression ``text`` into SymPy without executing it.

    ``namespace`` maps names to SymPy objects (default: pendulab's symbols,
    :data:`pendulab.symbols.NAMESPACE`); other names become plain symbols.
    ``functions`` allows calls of unknown names (``theta(t)``) as undefined
    functions.  Raises :class:`InputError` with a one-line message.
    """
    if not isinstance(text, str):
        raise InputError(f"expected an expression as text, got {type(text).__name__}")
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:  # bytes of a command line that are not UTF-8 (surrogate escapes)
        raise InputError(f"expression {text.encode('utf-8', 'replace').decode()[:40]!r} has bytes "
                         "that are not UTF-8 text") from None
    if not text.strip():
        raise InputError("empty expression")
    if len(text) > MAX_LENGTH:
        raise InputError(f"expression longer than {MAX_LENGTH} characters")
    if "\n" in text.strip():
        raise InputError("expression spans several lines")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise InputError(f"cannot parse {text.strip()!r}: {exc.msg}") from None
    except (RecursionError, MemoryError):
        raise InputError("expression is nested too deeply (Python's parser gave up)") from None
    builder = _Builder(S.NAMESPACE if namespace is None else namespace, functions)
    builder.source = text.strip()
    try:
        value = builder.build(tree)
    except RecursionError:
        raise InputError(f"expression is nested too deeply (limit {MAX_DEPTH} levels)") from None
    if not isinstance(value, sp.Expr) or isinstance(value, sp.Tuple):
        raise InputError(f"{text.strip()[:40]!r} is not an expression")
    _check_size(value)
    if value.has(sp.I) or any(e.is_number and e.is_real is False
                              for e in sp.preorder_traversal(value)):
        raise InputError(f"expression {text.strip()[:40]!r} is not real (the imaginary unit "
                         "or a complex value: a root or logarithm of a negative number, or "
                         "asin/acos beyond 1?)")
    if _not_finite(value):
        raise InputError(f"expression is not finite: {sp.sstr(value)[:40]} (zoo is 1/0: "
                         "a division by zero)")
    expanded_terms(value)
    return value


def _printed(printer, expr, **settings):
    try:
        return printer(expr, **settings)
    except ValueError as exc:
        if "int_max_str_digits" not in str(exc):
            raise
        raise InputError("a number in the result has more than "
                         f"{sys.get_int_max_str_digits()} digits, more than Python prints by "
                         "default (sys.set_int_max_str_digits; the pendulab command lifts "
                         "the limit)") from None


def dump_expr(expr):
    """Deterministic text of ``expr`` (SymPy's StrPrinter) that :func:`load_expr` reads back."""
    return _printed(sp.sstr, expr, order=None)


def load_expr(text):
    """Read text written by :func:`dump_expr` (or by a user) back into SymPy.

    Names are pendulab's symbols (``I`` is the moment of inertia, ``E`` and
    ``gamma`` would be plain symbols); no code is executed.
    """
    return parse(text)


def latex(expr, **settings):
    """LaTeX of ``expr`` with pendulab's symbol names (``theta0`` -> ``\\theta_{0}``)."""
    return _printed(sp.latex, expr, **settings)


# ---------------------------------------------------------------------------
# Trigonometric polynomials, directly
# ---------------------------------------------------------------------------

#: Most distinct frequencies a trigonometric polynomial may have (a drive
#: a1 cos(omega t) + ... + aN cos(N omega t) has N; its coefficient in the
#: equation N as well, cos(omega t)**N has N + 1 with the constant).
from pendulab.limits import MAX_HARMONICS  # noqa: E402  (kept with the option ranges)


class TooManyHarmonics(InputError):
    """A trigonometric polynomial with more than :data:`MAX_HARMONICS` frequencies."""


def _linear_rate(arg, var):
    """(r, p) with arg = r*var + p, r != 0 free of var; None when arg is not of that form."""
    arg = sp.expand(arg)
    r = arg.coeff(var, 1)
    p = arg.coeff(var, 0)
    if r == 0 or r.has(var) or p.has(var) or sp.expand(arg - r * var - p) != 0:
        return None
    return r, p


def _is_trig_shaped(e, var):
    """Cheap test: is ``e`` a polynomial in sin/cos of linear functions of ``var``?"""
    if not e.has(var):
        return True
    if e.is_Add or e.is_Mul:
        return all(_is_trig_shaped(a, var) for a in e.args)
    if e.is_Pow:
        return (e.exp.is_Integer and e.exp >= 0 and not e.exp.has(var)
                and _is_trig_shaped(e.base, var))
    if isinstance(e, (sp.sin, sp.cos)):
        return _linear_rate(e.args[0], var) is not None
    return False


def _times(x, y, limit):
    out = {}
    for rx, cx in x.items():
        for ry, cy in y.items():
            r = rx + ry
            out[r] = out.get(r, 0) + cx * cy
            if len(out) > limit:
                raise TooManyHarmonics(f"more than {MAX_HARMONICS} frequencies "
                                       f"(limit {MAX_HARMONICS} harmonics)")
    return out


def trig_spectrum(expr, var, limit=None):
    """``expr`` as sum_r c_r exp(i r var): {r: c_r}, or None when it is not of that form.

    ``expr`` must be a polynomial in sin and cos of ``r*var + p`` (r, p free of
    ``var``) with coefficients free of ``var``; the rates r are kept as they
    are (``omega``, ``2*omega``, numbers).  The work is the product of the
    spectra of the factors, with no rewrite to exponentials and no
    simplification: for a Fourier drive of N harmonics it is O(N^2) small
    multiplications.  ``c_r`` are unexpanded SymPy expressions (expand them).
    Raises :class:`TooManyHarmonics` past ``limit`` rates (default
    2*MAX_HARMONICS + 1).
    """
    limit = 2 * MAX_HARMONICS + 1 if limit is None else limit
    if not _is_trig_shaped(expr, var):
        return None
    half = sp.Rational(1, 2)

    def spec(e):
        if not e.has(var):
            return {sp.Integer(0): e}
        if e.is_Add:
            out = {}
            for a in e.args:
                for r, c in spec(a).items():
                    out[r] = out.get(r, 0) + c
            if len(out) > limit:
                raise TooManyHarmonics(f"more than {MAX_HARMONICS} frequencies "
                                       f"(limit {MAX_HARMONICS} harmonics)")
            return out
        if e.is_Mul:
            out = {sp.Integer(0): sp.Integer(1)}
            for a in e.args:
                out = _times(out, spec(a), limit)
            return out
        if e.is_Pow:
            base, n = spec(e.base), int(e.exp)
            out = {sp.Integer(0): sp.Integer(1)}
            while n:  # binary powering
                if n & 1:
                    out = _times(out, base, limit)
                n >>= 1
                if n:
                    base = _times(base, base, limit)
            return out
        r, p = _linear_rate(e.args[0], var)
        up = half if p == 0 else half * sp.exp(sp.I * p)
        down = half if p == 0 else half * sp.exp(-sp.I * p)
        if isinstance(e, sp.cos):
            return {r: up, -r: down}
        return {r: -sp.I * up, -r: sp.I * down}

    return spec(expr)
