"""Scene files: what to derive and what to produce (TOML, in derivations/).

A scene is data, never code::

    name = "kapitza-rod"             # optional; default: the file name
    system = "kapitza"               # or "variable-length"
    description = "..."              # optional

    [parameters]                     # all optional
    body = "rod"                     # kapitza: rod | point | explicit
    inertia = "m*l**2 + I0"          # kapitza, body = "explicit" only
    drive = "a*cos(omega*t)"         # kapitza: pivot height y0(t)
    angle = "up"                     # kapitza: up | down
    # length = "L0 + v0*t"           # variable-length: L(t)
    # mass = "m"                     # variable-length

    [values]                         # optional: SI numbers for the scene's symbols
    l = 0.05                         # a number, or an expression of numbers
    omega = "2*pi*86"

    [products.equations]             # one table per product; keys are its options

Every problem found is reported at once, one per line, each naming the file
and the key (:class:`pendulab.errors.SceneError`).  Expressions are parsed by
:func:`pendulab.exprs.parse`, which executes nothing.
"""

import math
import re
import os
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from pendulab.errors import InputError, ParameterError, SceneError

SYSTEMS = ("kapitza", "variable-length")
TOP_KEYS = {"name", "system", "description", "parameters", "products", "values"}
PARAMETERS = {
    "kapitza": {"body": "choice:rod,point,explicit", "inertia": "expr",
                "drive": "expr", "angle": "choice:up,down"},
    "variable-length": {"length": "expr", "mass": "expr"},
}
_SCENE_NAME = re.compile(r"[a-z0-9][a-z0-9_-]{0,63}\Z")


@dataclass(frozen=True)
class Scene:
    """A validated scene.  ``parameters`` hold SymPy objects or strings."""

    path: str
    name: str
    system: str
    description: str = ""
    parameters: dict = field(default_factory=dict)
    products: dict = field(default_factory=dict)
    raw: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)  # [values]: {symbol name: SymPy number}


#: Deepest nesting of tables and lists a scene may have (a scene needs 4:
#: products.floquet.points[i][j]).
MAX_NESTING = 16


class _Problems:
    def __init__(self, path):
        self.path = path
        self.items = []
        self.bad_values = set()  # keys whose value is unusable (NaN, too deep): one problem each

    def add(self, key, problem):
        # one problem per unusable value: nothing more at it, inside it, or about
        # the table that holds it
        if key and any(key == bad or key.startswith(bad + ".") or bad.startswith(key + ".")
                       for bad in self.bad_values):
            return
        self.items.append(SceneError(self.path, key, problem))

    def bad_value(self, where, problem):
        """A problem at ``where`` (a dotted path with list indices) that later checks skip."""
        self.add(where, problem)
        self.bad_values.add(_top(where))

    def raise_if_any(self):
        if len(self.items) == 1:
            raise self.items[0]
        if self.items:
            err = SceneError(self.path, None, f"{len(self.items)} problems")
            err.args = ("\n".join(str(e) for e in self.items),)
            err.problems = self.items
            raise err


def _check_values(data, problems):
    """Report NaN/infinite floats and too deep nesting anywhere in ``data`` (iteratively).

    TOML allows ``nan`` and ``inf``; no quantity of a scene can be either.
    The key of each problem is the dotted path (``products.floquet.points[0][1]``);
    the top-level key is what later checks skip.
    """
    stack = [(data, "", 0)]
    while stack:
        value, where, depth = stack.pop()
        if isinstance(value, float) and not math.isfinite(value):
            problems.bad_value(where, f"is {value!r}: NaN and infinity are not allowed in a "
                                      "scene (give a finite number)")
            continue
        if depth > MAX_NESTING:
            problems.bad_value(where.split("[", 1)[0], f"nested more than {MAX_NESTING} levels deep")
            continue
        if isinstance(value, dict):
            for key, item in value.items():
                if not isinstance(key, str):  # a table given from Python, not read from TOML
                    raise SceneError(problems.path, where or None,
                                     f"keys are names (strings); got {key!r}")
                stack.append((item, f"{where}.{key}" if where else str(key), depth + 1))
        elif isinstance(value, list):
            for i, item in enumerate(value):
                stack.append((item, f"{where}[{i}]", depth + 1))


def _top(where):
    """The key a later check reports for ``where``: up to the first list index, and for
    a table inside a product option (``products.motion.values.eps``) the option itself."""
    head = where.split("[", 1)[0]
    parts = head.split(".")
    return ".".join(parts[:3]) if parts[0] == "products" and len(parts) > 3 else head



def _option_value(kind, value):
    """Check one product option against its declared type; return the value."""
    if kind is bool:
        if not isinstance(value, bool):
            raise TypeError("must be true or false")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError("must be an integer")
        return value
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError("must be a number")
        return value
    if kind is str:
        if not isinstance(value, str):
            raise TypeError("must be a string")
        return value
    if kind is list:
        if not isinstance(value, list):
            raise TypeError("must be a list")
        return value
    if kind is dict:
        if not isinstance(value, dict):
            raise TypeError("must be a table")
        return value
    if callable(kind):
        return kind(value)
    raise TypeError(f"unsupported option type {kind!r}")


def validate_options(module, given, where, problems, system=None):
    """Fill defaults, check types and ranges; options with default ``None`` are required.

    The range of an option ``key`` of product ``name`` is the entry
    ``name.key`` of :data:`pendulab.limits.LIMITS`, when there is one.  A product whose
    systems take different options has ``options_for(system)``; the others have ``OPTIONS``.
    """
    from pendulab import limits
    spec = getattr(module, "OPTIONS", {})
    per_system = getattr(module, "options_for", None)
    if per_system is not None and system is not None:
        spec = per_system(system)
    product = module.__name__.rsplit(".", 1)[-1]
    options, refused = {}, set()
    for key in sorted(set(given) - set(spec)):
        other = " for a " + system + " scene" if key in getattr(module, "OPTIONS", {}) else ""
        problems.add(f"{where}.{key}",
                     f"unknown option{other} (known: {', '.join(sorted(spec)) or 'none'})")
    for key, (kind, default, _help) in sorted(spec.items()):
        if key in given:
            try:
                options[key] = _option_value(kind, given[key])
                if f"{product}.{key}" in limits.LIMITS:
                    limits.check(f"{product}.{key}", options[key], label="")
            except (TypeError, ValueError) as exc:
                problems.add(f"{where}.{key}", str(exc))
                refused.add(key)
        elif default is None:
            problems.add(f"{where}.{key}", "missing (this product needs it)")
            refused.add(key)
        else:
            options[key] = default
    checker = getattr(module, "check_options", None)
    if checker is not None and getattr(module, "REPORTS_ALL", False):
        # the product reports the rest of its problems beside those found here
        try:
            checker(options, reported=refused)
        except InputError as exc:
            for problem in getattr(exc, "problems", [str(exc)]):
                problems.add(where, problem)
    elif checker is not None and set(options) == set(spec) and not any(
            (e.key or "").startswith(where) for e in problems.items):
        # the product's own checks of values and of the options together, before any work
        try:
            checker(options)
        except InputError as exc:
            for problem in getattr(exc, "problems", [str(exc)]):
                problems.add(where, problem)
    return options


def parse_scene(data, path="<scene>"):
    """Validate the TOML table ``data`` of a scene read from ``path``."""
    from pendulab.exprs import parse
    from pendulab.pipeline import PRODUCTS, product_module

    problems = _Problems(path)
    if not isinstance(data, dict):
        raise SceneError(path, None, "a scene is a TOML table")
    _check_values(data, problems)
    for key in sorted(set(data) - TOP_KEYS):
        problems.add(key, f"unknown key (known: {', '.join(sorted(TOP_KEYS))})")
    system = data.get("system")
    if system is None:
        problems.add("system", f"missing (one of {', '.join(SYSTEMS)})")
    elif not isinstance(system, str) or system not in SYSTEMS:
        problems.add("system", f"must be one of {', '.join(SYSTEMS)}; got {system!r}")
        system = None
    name = data.get("name", Path(path).stem)
    if not isinstance(name, str) or not _SCENE_NAME.match(name):
        whence = "" if "name" in data else (" (from the file name, as the scene gives no "
                                            "name: give one with name = \"...\")")
        problems.add("name", "must be 1-64 characters of a-z, 0-9, '-' and '_', starting "
                             f"with a letter or digit; got {name!r}{whence}")
    description = data.get("description", "")
    if not isinstance(description, str):
        problems.add("description", "must be a string")

    values = {}
    params = data.get("parameters", {})
    parsed = {}
    if not isinstance(params, dict):
        problems.add("parameters", "must be a table")
        params = {}
    allowed = PARAMETERS.get(system, {})
    for key, value in sorted(params.items()):
        where = f"parameters.{key}"
        if system in PARAMETERS and key not in allowed:
            problems.add(where, f"unknown parameter for {system} (known: {', '.join(sorted(allowed))})")
            continue
        kind = allowed.get(key, "")
        if kind.startswith("choice:"):
            choices = kind.split(":", 1)[1].split(",")
            if value not in choices:
                problems.add(where, f"must be one of {', '.join(choices)}; got {value!r}")
            else:
                parsed[key] = value
        elif kind == "expr":
            if isinstance(value, bool) or not isinstance(value, (str, int, float)):
                problems.add(where, "must be an expression (a string) or a number")
                continue
            try:
                parsed[key] = parse(str(value))
            except InputError as exc:
                problems.add(where, str(exc))
    if system == "kapitza":
        if "inertia" in parsed and parsed.get("body", "rod") != "explicit":
            problems.add("parameters.inertia", "given, but body is not 'explicit'")
    built = None
    if system in PARAMETERS and not any(e.key == "system" or (e.key or "").startswith("parameters")
                                        for e in problems.items):
        # Let the system itself judge the values (positivity, time dependence ...).
        from pendulab.pipeline import _stage_system

        class _Probe:
            pass
        probe = _Probe()
        probe.scene = Scene(str(path), name, system, description, parsed, {}, data)
        try:
            built = _stage_system(probe)
        except ParameterError as exc:
            for key, problem in exc.problems:
                problems.add(f"parameters.{key}", problem)
        except InputError as exc:
            problems.add("parameters", str(exc))
        else:
            values = _values(data.get("values", {}), built, problems)

    products = data.get("products")
    chosen = {}
    if products is None:
        problems.add("products", "missing: name at least one product, e.g. [products.equations]")
    elif not isinstance(products, dict) or not products:
        problems.add("products", "must be a table of product tables, e.g. [products.equations]")
    else:
        for pname, given in sorted(products.items()):
            where = f"products.{pname}"
            if pname not in PRODUCTS:
                problems.add(where, f"unknown product (known: {', '.join(sorted(PRODUCTS))})")
                continue
            if given is True:
                given = {}
            if not isinstance(given, dict):
                problems.add(where, "must be a table of options (or true)")
                continue
            try:
                module = product_module(pname)
            except ImportError:
                problems.add(where, "this product is not available in this version")
                continue
            systems = getattr(module, "SYSTEMS", SYSTEMS)
            if system in SYSTEMS and system not in systems:
                problems.add(where, f"not available for system {system!r}")
                continue
            chosen[pname] = validate_options(module, given, where, problems, system)
    if (built is not None and system == "variable-length" and "quarter_periods" in chosen
            and not built.is_linear_length):
        # L0 + v0 t reaching zero is the shortening string, whose quarter periods
        # the product gives up to that moment (pendulab.analyses.bessel_periods)
        found = built.length_zero
        if found is not None and found[1]:
            from pendulab.systems import length_zero_note
            problems.add("products.quarter_periods",
                         "needs a string that stays longer than zero for all t >= 0, but "
                         + length_zero_note(built).split(":", 1)[0])
    problems.raise_if_any()
    return Scene(str(path), name, system, description, parsed, chosen, data, values)


def _values(table, system, problems):
    """The [values] table: {name: finite real SymPy number}; names must be the system's symbols."""
    import math

    import sympy as sp

    from pendulab import symbols as S
    from pendulab.exprs import parse

    if not isinstance(table, dict):
        problems.add("values", "must be a table of numbers, e.g. l = 0.05")
        return {}
    if not table:
        return {}  # nothing to check against the system's symbols (which cost its Lagrangian)
    known = set().union(*(sp.sympify(e).free_symbols for e in (
        system.lagrangian, getattr(system, "drive", 0), getattr(system, "length", 0),
        getattr(system, "mass", 0))))
    if system.name == "kapitza":  # I is the body's inertia; omega0^2 = m g l/I (000 eq. 3)
        known = (known - {S.I}) | sp.sympify(system.inertia).free_symbols | {S.omega0}
    known = {x.name for x in known - {S.t}}
    out = {}
    for key, value in sorted(table.items()):
        where = f"values.{key}"
        if key not in known:
            problems.add(where, f"not a symbol of this scene's system (known: {', '.join(sorted(known))})")
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            problems.add(where, "must be a number or an expression string")
            continue
        if isinstance(value, float) and not math.isfinite(value):
            problems.add(where, f"must be finite, got {value!r}")
            continue
        try:
            num = parse(str(value)) if isinstance(value, str) else sp.nsimplify(value, rational=True)
        except InputError as exc:
            problems.add(where, str(exc))
            continue
        if not (num.is_number and num.is_real and num.is_finite and num.is_positive):
            problems.add(where, f"must evaluate to a finite positive number, got {value!r}")
            continue
        out[key] = num
    return out


def load_scene(path):
    """Read and validate the scene file at ``path``."""
    if not isinstance(path, (str, os.PathLike)) or not str(path).strip():
        raise InputError(f"a scene file is named by a non-empty path, got {path!r}")
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(path, None, "no such scene file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(path, None, f"cannot read: {exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        hint = " (the file starts with a byte-order mark: save it as UTF-8 without one)" \
            if text.startswith("\ufeff") else ""
        raise SceneError(path, None, f"not valid TOML: {exc}{hint}") from None
    except ValueError:  # an integer longer than Python's int() limit (sys.get_int_max_str_digits)
        raise SceneError(path, None, "has an integer of more than "
                                     f"{sys.get_int_max_str_digits()} digits (a scene's numbers "
                                     "are far smaller)") from None
    except (RecursionError, MemoryError):
        raise SceneError(path, None, "not valid TOML here: nested too deeply "
                                     f"(a scene needs at most {MAX_NESTING} levels)") from None
    return parse_scene(data, path)
