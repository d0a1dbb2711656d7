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

import sympy as sp

from pendulab.errors import InputError
from pendulab import symbols as S

#: Longest expression text accepted (a guard against pathological input).
MAX_LENGTH = 4000
#: Deepest nesting of the syntax tree accepted.
MAX_DEPTH = 60
#: Largest numeric exponent allowed (``t**(10**10)`` would hang the derivation).
MAX_NUMERIC_EXPONENT = 1000
#: Largest exact number (in bits) a power of numbers may produce
#: (``((10**1000)**1000)**1000`` would otherwise hang the parser).
MAX_NUMBER_BITS = 100_000
#: Highest derivative order accepted in ``Derivative(f, (t, n))``.
MAX_DERIVATIVE_ORDER = 20


def _function_for(name):
    """The undefined function called ``name`` (``theta(t)``, ``L(t)``, ...).

    Functions other than pendulab's own are real (a pivot height ``y0(t)``).
    """
    if name == "theta":
        return S.theta
    if name == "L":
        return S.L
    return sp.Function(name, real=True)


def _derivative(*args):
    """``Derivative`` with a bounded order (a huge order would hang the derivation)."""
    total = 0
    for spec in args[1:]:
        count = spec[1] if isinstance(spec, sp.Tuple) and len(spec) == 2 else sp.Integer(1)
        if not (isinstance(count, sp.Integer) and count >= 0):
            raise InputError("the order of a derivative must be a non-negative integer")
        total += int(count)
    if total > MAX_DERIVATIVE_ORDER:
        raise InputError(f"derivative of order {total} is too high (limit {MAX_DERIVATIVE_ORDER})")
    return sp.Derivative(*args)


def _bits(x):
    """Size in bits of an exact rational (0 for anything else)."""
    if isinstance(x, sp.Rational):
        return max(int(abs(x.p)).bit_length(), int(x.q).bit_length())
    return 0


_FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "cot": sp.cot,
    "sec": sp.sec, "csc": sp.csc,
    "asin": sp.asin, "acos": sp.acos, "atan": sp.atan, "atan2": sp.atan2,
    "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh,
    "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt, "Abs": sp.Abs,
    "sign": sp.sign, "Heaviside": sp.Heaviside,
    "besselj": sp.besselj, "bessely": sp.bessely,
    "Derivative": _derivative, "Rational": sp.Rational,
    "Integer": sp.Integer, "Eq": sp.Eq, "Tuple": sp.Tuple,
}
_CONSTANTS = {"pi": sp.pi}
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
            raise InputError("expression is nested too deeply")
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
            return sp.Integer(v)
        text = ast.get_source_segment(self.source, node) or repr(v)
        return sp.Rational(text.replace("_", ""))

    def _Name(self, node, d):
        name = node.id
        _check_name(name)
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
        return sp.Tuple(*[self.build(e, d) for e in node.elts])

    def _UnaryOp(self, node, d):
        v = self.build(node.operand, d)
        if isinstance(node.op, ast.USub):
            return -v
        if isinstance(node.op, ast.UAdd):
            return v
        raise InputError(f"operator {type(node.op).__name__} is not allowed")

    def _BinOp(self, node, d):
        x = self.build(node.left, d)
        y = self.build(node.right, d)
        op = node.op
        if isinstance(op, ast.Add):
            return x + y
        if isinstance(op, ast.Sub):
            return x - y
        if isinstance(op, ast.Mult):
            return x * y
        if isinstance(op, ast.Div):
            if y == 0:
                raise InputError("division by zero in expression")
            return x / y
        if isinstance(op, ast.BitXor):
            raise InputError("'^' is not a power here (it binds looser than '*'); write '**'")
        if isinstance(op, ast.Pow):
            if y.is_number and y.is_real and abs(y) > MAX_NUMERIC_EXPONENT:
                raise InputError(f"numeric exponent {y} is too large (limit {MAX_NUMERIC_EXPONENT})")
            if y.is_number and _bits(x) * abs(sp.re(y)) > MAX_NUMBER_BITS:
                raise InputError(f"the power {sp.sstr(x)[:20]}**{y} is too large a number "
                                 f"(limit {MAX_NUMBER_BITS} bits)")
            return x ** y
        raise InputError(f"operator {type(op).__name__} is not allowed")

    def _Call(self, node, d):
        if node.keywords:
            raise InputError("keyword arguments are not allowed in an expression")
        if not isinstance(node.func, ast.Name):
            raise InputError(f"{_describe(node.func)} is not allowed in an expression")
        name = node.func.id
        _check_name(name)
        args = [self.build(a, d) for a in node.args]
        if name in ("theta", "L") and self.functions_allowed and len(args) == 1:
            return _function_for(name)(*args)
        if name in _FUNCTIONS:
            try:
                return _FUNCTIONS[name](*args)
            except (TypeError, ValueError) as exc:
                raise InputError(f"bad arguments to {name}: {exc}") from None
        if name in self.namespace or name in _CONSTANTS:
            raise InputError(f"{name!r} is a symbol, not a function")
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
    builder = _Builder(S.NAMESPACE if namespace is None else namespace, functions)
    builder.source = text.strip()
    try:
        return builder.build(tree)
    except RecursionError:
        raise InputError("expression is nested too deeply") from None


def dump_expr(expr):
    """Deterministic text of ``expr`` (SymPy's StrPrinter) that :func:`load_expr` reads back."""
    return sp.sstr(expr, order=None)


def load_expr(text):
    """Read text written by :func:`dump_expr` (or by a user) back into SymPy.

    Names are pendulab's symbols (``I`` is the moment of inertia, ``E`` and
    ``gamma`` would be plain symbols); no code is executed.
    """
    return parse(text)


def latex(expr, **settings):
    """LaTeX of ``expr`` with pendulab's symbol names (``theta0`` -> ``\\theta_{0}``)."""
    return sp.latex(expr, **settings)
