"""Product "series": the perturbation series of 000 sec. 3 and the integer-order series.

Writes, under generated/<scene>/:

* ``series.json`` - for kind "nu": "alpha" (order -> expression in nu), "c" and
  "s" (order -> list of [k, coefficient], meaning coefficient * cos((nu + 2k) tau),
  resp. sin); for each integer kind ("a0", "b1", ...): "coefficients" (power of
  q -> exact rational as text), "radius" (the computed nearest branch point) and
  "radius_source" (which says so, and whether DLMF Table 28.6.1 has the row).  Expressions
  are written in SymPy's syntax straight from the exact coefficients
  (``RatFun.text``), and SymPy reads them back to the same expressions.
* ``series.tex`` - LaTeX (amsmath ``align*``), long coefficients broken across
  lines so that no line is wider than :data:`LINE_WIDTH` characters of math.
* ``series_coefficients.py`` - a Python module of the exact coefficients
  (jinja2 template ``series_coefficients.py.j2``).

Every file is byte-identical on every run.  The functions here are also used
by ``pendulab series`` on the command line.
"""

from pendulab.latex import (  # LINE_WIDTH: widest line of visible math
    LINE_WIDTH, characteristic_series_block, mathieu_series_blocks, ratfun_rows, series_lines,
    series_width,
)

from pendulab.limits import LIMITS as _LIMITS, option as _limited

#: Type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "order": _limited("series.order"),
    "kinds": _limited("series.kinds"),
}
SYSTEMS = ("kapitza",)
#: highest order the product and the command accept (pendulab.limits.LIMITS["series.order"])
MAX_PRODUCT_ORDER = _LIMITS["series.order"][2]


# -- checks ------------------------------------------------------------------------------

def check_request(order, kinds, where="series"):
    """Validate (order, kinds); one InputError listing every problem."""
    from pendulab.analyses.series import _parse_kind
    from pendulab.errors import InputError
    problems = []
    if isinstance(order, bool) or not isinstance(order, int) or not 1 <= order <= MAX_PRODUCT_ORDER:
        problems.append(f"order must be an integer from 1 to {MAX_PRODUCT_ORDER}, got {order!r}")
    if not isinstance(kinds, list) or not kinds:
        problems.append(f"kinds must be a non-empty list, got {kinds!r}")
        kinds = []
    elif len(kinds) > _LIMITS["series.kinds"][2]:
        problems.append(f"kinds must have at most {_LIMITS['series.kinds'][2]} entries, "
                        f"got {len(kinds)}")
    seen = set()
    for kind in kinds:
        if not isinstance(kind, str):
            problems.append(f"each kind must be a string such as 'nu' or 'a0', got {kind!r}"[:80])
            continue
        if kind in seen:
            problems.append(f"kind {kind!r} is listed twice")
        seen.add(kind)
        if kind == "nu":
            continue
        try:
            _parse_kind(kind)
        except InputError as exc:
            problems.append(str(exc) if kind != "" else "kind '' is empty")
    from pendulab.limits import raise_problems
    raise_problems(problems, prefix=f"{where}: " if where else "")


def check_options(options):
    """Scene validation: every problem of the options, one InputError (no prefix)."""
    check_request(options["order"], options["kinds"], where=None)


# -- JSON ----------------------------------------------------------------------------------

def nu_record(order):
    """JSON data of the non-integer series at ``order`` (000 eqs. 20-22)."""
    from pendulab.analyses.series import mathieu_series
    s = mathieu_series(order)
    # RatFun.text: SymPy syntax written straight from the exact data (numerator over an integer
    # times the linear factors), which SymPy reads back to the same expression as to_sympy builds.
    # Building and printing SymPy expressions instead costs about 30 s at order 40.
    rows = {str(n): [[k, v.text()] for k, v in row] for n, row in s.c_raw.items()}
    return {
        "kind": "nu",
        "order": order,
        "equation": "Derivative(theta, tau, 2) + (theta0 + 2*theta1*cos(2*tau))*theta = 0",
        "theta0": "nu**2 + Sum(alpha[n]*theta1**n)",
        "theta_c": "cos(nu*tau) + Sum(theta1**n*Sum(c[n][k]*cos((nu + 2*k)*tau)))",
        "theta_s": "sin(nu*tau) + Sum(theta1**n*Sum(s[n][k]*sin((nu + 2*k)*tau)))",
        "source": "000 eqs. 20-27; DLMF 28.15.1-28.15.2 with a = theta0, q = -theta1",
        "alpha": {str(n): a.text() for n, a in s.alpha_raw.items()},
        "c": rows,
        "s": rows,
    }


def integer_record(kind, order):
    """JSON data of a_m(q) or b_m(q) at ``order`` (DLMF 28.6)."""
    from pendulab.analyses.series import characteristic_series
    s = characteristic_series(kind, order)
    return {
        "kind": kind,
        "order": order,
        "equation": "Derivative(w, z, 2) + (a - 2*q*cos(2*z))*w = 0 (DLMF 28.2.1); a = theta0, q = -theta1",
        "coefficients": {str(p): str(c) for p, c in s.coefficients.items()},
        "radius": s.radius,
        "radius_source": s.radius_source,
    }


def record(kind, order):
    return nu_record(order) if kind == "nu" else integer_record(kind, order)


# -- LaTeX ------------------------------------------------------------------------------------

# The printer itself is pendulab.latex's (series_width, ratfun_rows, the blocks), shared with
# the series objects' _repr_latex_; the names below are kept for the callers of this module.
_visible = series_width
_lines = series_lines
_latex_ratfun = ratfun_rows


def latex_text(kinds, order):
    """The LaTeX fragment of series.tex for ``kinds`` at ``order`` (needs amsmath)."""
    from pendulab.analyses.series import characteristic_series, mathieu_series
    out = [
        "% Generated by pendulab (pendulab.products.series); do not edit.",
        "% Needs \\usepackage{amsmath}.  Mathieu's equation (000 eq. 7):",
        "% theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0; DLMF: a = theta0, q = -theta1.",
        "% Long coefficients may break across pages inside this group only.",
        "\\begingroup\\allowdisplaybreaks",
        "",
    ]
    for kind in kinds:
        if kind == "nu":
            s = mathieu_series(order)
            out.append(f"% 000 eqs. 20-22 to order {order}: theta0 = nu^2 + sum alpha_n theta1^n,")
            out.append("% c_n = sum_k C_{n,k} cos((nu+2k) tau), s_n = sum_k C_{n,k} sin((nu+2k) tau)")
            out.extend(mathieu_series_blocks(s))
        else:
            s = characteristic_series(kind, order)
            letter, m = kind[0], kind[1:]
            out.append(f"% DLMF 28.6: {letter}_{m}(q) to q^{order}; radius of convergence "
                       f"{s.radius} ({s.radius_source})")
            out.append(characteristic_series_block(s))
        out.append("")
    out.append("\\endgroup")
    out.append("")
    return "\n".join(out)


# -- generated Python module ---------------------------------------------------------------

def python_module_text(kinds, order, origin):
    """series_coefficients.py: exact data filled into the jinja2 template."""
    import jinja2

    from pendulab import __version__
    from pendulab.analyses.series import characteristic_series, mathieu_series

    def raw(v):
        return (tuple(v.num), v.den, tuple(v.exps))

    alpha, c, chars, radius = {}, {}, {}, {}
    if "nu" in kinds:
        s = mathieu_series(order)
        alpha = {n: raw(a) for n, a in s.alpha_raw.items()}
        c = {n: {k: raw(v) for k, v in row} for n, row in s.c_raw.items()}
    for kind in kinds:
        if kind != "nu":
            cs = characteristic_series(kind, order)
            chars[kind] = {p: f"Fraction({str(v)!r})" for p, v in cs.coefficients.items()}
            radius[kind] = cs.radius

    def literal(d):
        if not d:
            return "{}"
        return "{\n" + "".join(f"    {k!r}: {v!r},\n" for k, v in d.items()) + "}"

    char_text = "{}" if not chars else "{\n" + "".join(
        f"    {kind!r}: {{" + ", ".join(f"{p}: {v}" for p, v in vals.items()) + "},\n"
        for kind, vals in chars.items()) + "}"
    env = jinja2.Environment(loader=jinja2.PackageLoader("pendulab", "templates"),
                             keep_trailing_newline=True, undefined=jinja2.StrictUndefined,
                             autoescape=False)
    template = env.get_template("series_coefficients.py.j2")
    return template.render(version=__version__, origin=origin, order=order,
                           alpha=literal(alpha), c=literal(c), characteristic=char_text,
                           radius=literal(radius))


# -- the product ---------------------------------------------------------------------------------

def produce(ctx, options):
    from pendulab.io import canonical_json
    order, kinds = options["order"], options["kinds"]
    check_request(order, kinds, where="series product")
    kinds = list(kinds)
    data = {"order": order, "kinds": kinds, "series": {k: record(k, order) for k in kinds}}
    origin = f"scene {ctx.scene.name!r}" if hasattr(ctx.scene, "name") else "a scene"
    return {
        "series.json": canonical_json(data),
        "series.tex": latex_text(kinds, order),
        "series_coefficients.py": python_module_text(kinds, order, origin),
    }
