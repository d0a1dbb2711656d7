"""pendulab latex series|eom|stability|zeros|quarter-periods [...]

Prints one LaTeX fragment to standard output and nothing else, as the
products print it into generated/<scene>/ (the products' own printers, run on
a scene built in memory from the options, through the same validation and
pipeline stages as a scene file).  The fragment's header comment names the
packages it needs (:func:`pendulab.latex.packages_needed`: amsmath, booktabs)
and the command that made it, every option written out.
"""

import argparse

#: the scene keys these commands fill and the option that gives each
_OPTION_OF = {"parameters.drive": "--drive", "parameters.body": "--body",
              "parameters.angle": "--angle", "parameters.inertia": "--inertia",
              "parameters.length": "--length", "parameters.mass": "--mass",
              "products.series.order": "--order", "products.series.kinds": "--kind",
              "products.stability.points": "--points",
              "products.stability.max_ratio": "--max-ratio",
              "products.stability.methods": "--methods",
              "products.stability": "--methods",
              "products.quarter_periods": "--length"}

#: the zeros of at most this many orders stand side by side (the table's width)
MAX_ORDERS = 4


def add_parser(sub):
    from pendulab.limits import (BESSEL_ZERO_WORK, LIMITS, QUARTER_PERIOD_WORK, argument,
                                 describe)
    p = sub.add_parser(
        "latex", help="print one LaTeX fragment (series, eom, stability, zeros, quarter-periods)",
        description="Print one LaTeX fragment, as the products write them into generated/, "
                    "to standard output and nothing else.  Its header comment names the "
                    "packages it needs (amsmath, booktabs) and the command that made it.  "
                    "Every fragment compiles in a bare article with those packages "
                    "(tests/test_latex_command.py).")
    what = p.add_subparsers(dest="what", metavar="WHAT")
    what.required = True

    s = what.add_parser("series", help="000 eqs. 20-24 series, or a_m(q), b_m(q) (DLMF 28.6)",
                        description="The perturbation series of Mathieu's equation "
                                    "(000 eqs. 20-24, kind 'nu': theta0 = nu^2 + sum "
                                    "alpha_n theta1^n and the coefficients C_n,k) or the "
                                    "characteristic values a_m(q), b_m(q) (kinds a0, b1, ...), "
                                    "as series.tex.")
    argument(s, "--order", "series.order", required=True, metavar="N",
             text=f"highest power of theta1 (of q for a0, b1, ...); kind nu at most "
                  f"{LIMITS['latex.nu_order'][2]}")
    s.add_argument("--kind", action="append", metavar="KIND",
                   help="nu, or a<m> / b<m> such as a0, b1; repeat for several "
                        f"(at most {LIMITS['series.kinds'][2]}; default: nu)")
    s.set_defaults(func=run_series)

    e = what.add_parser("eom", help="the derivation: Lagrangian, equation of motion, canonical form",
                        description="The derivation's steps as equations.tex prints them: "
                                    "000 eqs. 2-7 for a body on a driven pivot (kapitza), "
                                    "002 eqs. 3-7 and the Bessel solution for a string of "
                                    "length L(t) (variable-length).")
    e.add_argument("system", choices=("kapitza", "variable-length"), metavar="SYSTEM",
                   help="kapitza or variable-length")
    e.add_argument("--body", choices=("rod", "point", "explicit"),
                   help="kapitza: rod (I = 4 m l^2/3), point (I = m l^2) or explicit "
                        "(I from --inertia) (default: rod)")
    e.add_argument("--inertia", metavar="EXPR",
                   help="kapitza, --body explicit: I about the pivot, I >= m l^2")
    e.add_argument("--drive", metavar="EXPR",
                   help="kapitza: pivot height y0(t) (default: a*cos(omega*t))")
    e.add_argument("--angle", choices=("up", "down"),
                   help="kapitza: theta from the upward or downward vertical (default: up)")
    e.add_argument("--length", metavar="EXPR",
                   help="variable-length: L(t) (default: L0 + v0*t)")
    e.add_argument("--mass", metavar="EXPR", help="variable-length: the mass (default: m)")
    e.set_defaults(func=run_eom)

    t = what.add_parser("stability", help="table of the limits of a/l by every method",
                        description="The limits of a/l between which the inverted body on a "
                                    "vertically driven pivot is stable, on a grid of "
                                    "omega0/omega, by each method (000 eqs. 12, 19, 28 and "
                                    "Floquet), as stability.tex.  The work of the points and "
                                    "methods together is bounded as the stability product's.")
    t.add_argument("--body", choices=("rod", "point"), default="rod",
                   help="rod: I/(m l^2) = 4/3; point: 1")
    argument(t, "--points", "stability.points", default=str(LIMITS["stability.points"][3]),
             metavar="P")
    argument(t, "--max-ratio", "stability.max_ratio",
             default=LIMITS["stability.max_ratio"][3], metavar="R")
    t.add_argument("--methods", metavar="M,M,...",
                   default=",".join(LIMITS["stability.methods"][3]),
                   help="comma-separated: exact, eq12, eq19, eq19-corrected, eq28, series:N, "
                        f"integer-series:N ({describe('stability.methods')})")
    t.set_defaults(func=run_stability)

    z = what.add_parser("zeros", help="table of the certified zeros j_nu,k of J_nu",
                        description="The first K positive zeros of J_nu for each order nu, "
                                    "side by side, as bessel_zeros.tex; every zero certified "
                                    "(interval Newton, Sturm windows) to D digits, of which the "
                                    "table prints at most 12.  K x D x (number of orders) is at "
                                    f"most {BESSEL_ZERO_WORK} (a sixth of it with a "
                                    "non-integer order).")
    argument(z, "--nu", "bessel.order", action="append", metavar="NU",
             text=f"an order nu (1, 2.5, 1/3); repeat for up to {MAX_ORDERS} (default: 1 and 2)")
    argument(z, "--count", "bessel.zeros", default=str(LIMITS["bessel.zeros"][3]), metavar="K")
    argument(z, "--dps", "bessel.dps", default=str(LIMITS["bessel.dps"][3]), metavar="D")
    z.set_defaults(func=run_zeros)

    q = what.add_parser("quarter-periods", help="table of 002's quarter periods",
                        description="inward and outward quarter periods of the string "
                                    "L(t) = L0 + v0 t (002, differences of squares of zeros "
                                    "of J1 and J2, unit |dL/dt|/(4g)), as "
                                    "bessel_quarter_periods.tex; a shortening string "
                                    "(--length 'L0 - v0*t') gets its own.  K x D is at most "
                                    f"{QUARTER_PERIOD_WORK}.")
    argument(q, "--count", "quarter_periods.count",
             default=str(LIMITS["quarter_periods.count"][3]), metavar="K")
    argument(q, "--dps", "quarter_periods.dps",
             default=str(LIMITS["quarter_periods.dps"][3]), metavar="D",
             text="significant digits of the computation (the table prints at most 12)")
    q.add_argument("--length", metavar="EXPR", default="L0 + v0*t",
                   help="L(t), of the form L0 + r*t")
    q.set_defaults(func=run_quarter_periods)
    for parser in (p, s, e, t, z, q):
        parser.formatter_class = argparse.ArgumentDefaultsHelpFormatter
    return p


# -- shared ----------------------------------------------------------------------------------

def _emit(command, fragment, about=()):
    """Write the header (packages, command, ``about`` lines) and ``fragment`` without its
    own leading comment lines to standard output."""
    import sys

    from pendulab import __version__
    from pendulab.latex import packages_needed
    from pendulab.products.notes import strip_banner
    body = strip_banner(fragment) + "\n"
    needs = packages_needed(body)
    head = [f"% made by: {command}   (pendulab {__version__}); do not edit",
            "% needs: " + (", ".join(f"\\usepackage{{{p}}}" for p in needs) or "no package")
            + " (in an article)"]
    head += [f"% {line}" for line in about]
    sys.stdout.write("\n".join(head) + "\n" + body)
    return 0


def _scene(data):
    """The scene ``data`` parsed as a scene file is; its problems as one line naming the
    options (an InputError)."""
    from pendulab.errors import InputError, SceneError
    from pendulab.scene import parse_scene
    try:
        return parse_scene(data, path="command line")
    except SceneError as exc:
        raise InputError("; ".join(_as_options(line) for line in str(exc).splitlines())) from None


def _as_options(line):
    """A scene problem ("command line: parameters.drive: ...") named by its option."""
    head = "command line: "
    if line.startswith(head):
        line = line[len(head):]
    for key in sorted(_OPTION_OF, key=len, reverse=True):
        if line.startswith(key + ":") or line.startswith(key + "."):
            return _OPTION_OF[key] + line[len(key):]
    return line


def _quote(text):
    import shlex
    return shlex.quote(str(text))


# -- the fragments ---------------------------------------------------------------------------

def run_series(args):
    from pendulab import limits
    problems = limits.Problems()
    order = problems.parse("series.order", args.order, "--order")
    kinds = args.kind or ["nu"]
    top = limits.LIMITS["latex.nu_order"][2]
    if order is not None and "nu" in kinds and order > top:
        problems.add(f"--order {order} of kind nu: its LaTeX goes to order {top} (about 560 "
                     f"pages there; the integer kinds go to {limits.LIMITS['series.order'][2]})")
    elif order is not None:
        from pendulab.products.series import check_request
        problems.call(check_request, order, kinds, where="--kind")
    problems.raise_any()  # before any series is computed

    from pendulab.products import series as product
    scene = _scene({"name": "latex", "system": "kapitza",
                    "products": {"series": {"order": order, "kinds": kinds}}})
    options = scene.products["series"]  # validated as a scene's; the series read no stage
    fragment = product.latex_text(options["kinds"], options["order"])
    command = "pendulab latex series --order " + str(order) + "".join(
        f" --kind {_quote(k)}" for k in kinds)
    return _emit(command, fragment, [
        "Mathieu's equation (000 eq. 7): theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0; "
        "DLMF: a = theta0, q = -theta1."])


def run_eom(args):
    from pendulab.errors import InputError
    kapitza = args.system == "kapitza"
    own = ("body", "inertia", "drive", "angle") if kapitza else ("length", "mass")
    other = [f"--{k}" for k in ("body", "inertia", "drive", "angle", "length", "mass")
             if k not in own and getattr(args, k) is not None]
    if other:
        raise InputError(f"{', '.join(other)} {'does' if len(other) == 1 else 'do'} not apply "
                         f"to {args.system} (its options: {', '.join('--' + k for k in own)})")
    params = {k: getattr(args, k) for k in own if getattr(args, k) is not None}
    if kapitza and args.inertia is not None and args.body != "explicit":
        raise InputError("--inertia needs --body explicit")
    scene = _scene({"name": "latex", "system": args.system, "parameters": params,
                    "products": {"equations": {}}})
    from pendulab.pipeline import Context
    from pendulab.products.equations import STEP_NAMES, align_block, latex_steps
    fragment = align_block(latex_steps(Context(scene)), STEP_NAMES)
    command = f"pendulab latex eom {args.system}" + "".join(
        f" --{k} {_quote(v)}" for k, v in params.items())
    return _emit(command, fragment)


def run_stability(args):
    from pendulab import limits
    problems = limits.Problems()
    points = problems.parse("stability.points", args.points, "--points")
    max_ratio = problems.parse("stability.max_ratio", args.max_ratio, "--max-ratio")
    methods = [m.strip() for m in args.methods.split(",")]
    problems.call(limits.check, "stability.methods", methods, "--methods")
    problems.raise_any()
    from pendulab.analyses.stability import parse_method
    for method in methods:
        problems.call(parse_method, method, prefix="--methods: ")
    opts = {"points": points, "max_ratio": max_ratio, "methods": methods, "figure": False}
    if not problems:  # the work of the points and methods together, as the product bounds it
        work = limits.work_problem("stability", opts)
        if work:
            problems.add(f"--points and --methods: {work}")
    problems.raise_any()
    scene = _scene({"name": "latex", "system": "kapitza", "parameters": {"body": args.body},
                    "products": {"stability": opts}})
    from pendulab.pipeline import Context
    from pendulab.products import stability as product
    fragment = product.produce(Context(scene), scene.products["stability"])["stability.tex"]
    command = (f"pendulab latex stability --body {args.body} --points {points} "
               f"--max-ratio {_quote(max_ratio)} --methods {_quote(','.join(methods))}")
    return _emit(command, fragment)


def run_zeros(args):
    from pendulab import limits
    problems = limits.Problems()
    given = args.nu or ["1", "2"]
    for nu in given:
        problems.parse("bessel.order", nu, "--nu")
    if len(given) > MAX_ORDERS:
        problems.add(f"--nu is given {len(given)} times; at most {MAX_ORDERS} orders stand "
                     "side by side")
    count = problems.parse("bessel.zeros", args.count, "--count")
    dps = problems.parse("bessel.dps", args.dps, "--dps")
    if not problems:
        from pendulab.analyses.bessel_zeros import parse_order
        exact = [parse_order(nu, "--nu") for nu in given]
        if len(set(exact)) < len(exact):
            problems.add("--nu: an order is given twice")
        # the work of each order, as ``pendulab bessel zeros`` counts it
        work = sum(count * dps * (1 if nu.denominator == 1 else limits.BESSEL_NON_INTEGER_FACTOR)
                   for nu in exact)
        if work > limits.BESSEL_ZERO_WORK:
            problems.add(f"--count x --dps x orders = {work} is more than "
                         f"{limits.BESSEL_ZERO_WORK} digits in all (a non-integer order "
                         f"counts {limits.BESSEL_NON_INTEGER_FACTOR} times; about a minute): "
                         "ask for fewer or shorter numbers")
    problems.raise_any()
    from pendulab.analyses.bessel_zeros import bessel_zeros
    from pendulab.products.bessel import zeros_table
    sets = [bessel_zeros(nu, count, dps) for nu in exact]
    fragment = zeros_table(sets, dps, "latex")
    command = "pendulab latex zeros" + "".join(f" --nu {_quote(nu)}" for nu in given) \
        + f" --count {count} --dps {dps}"
    return _emit(command, fragment, ["Zeros of J_nu, certified by arb (python-flint): interval "
                                     "Newton and Sturm windows (docs/bessel.md)."])


def run_quarter_periods(args):
    from pendulab import limits
    problems = limits.Problems()
    count = problems.parse("quarter_periods.count", args.count, "--count")
    dps = problems.parse("quarter_periods.dps", args.dps, "--dps")
    if not problems:
        work = limits.work_problem("quarter_periods", {"count": count, "dps": dps})
        if work:
            problems.add(work.replace("count x dps", "--count x --dps", 1))
    problems.raise_any()
    scene = _scene({"name": "latex", "system": "variable-length",
                    "parameters": {"length": args.length},
                    "products": {"quarter_periods": {"count": count, "dps": dps}}})
    from pendulab.analyses.bessel_periods import quarter_periods
    from pendulab.errors import InputError
    from pendulab.pipeline import Context
    from pendulab.products.bessel import direction_from_stage, quarter_periods_table
    try:
        direction = direction_from_stage(Context(scene))
    except InputError as exc:
        raise InputError("--length: " + str(exc).replace("the bessel product needs", "the quarter periods need"))\
            from None
    options = scene.products["quarter_periods"]
    q = quarter_periods(options["count"], options["dps"], direction)
    fragment = quarter_periods_table(q, dps, "latex")
    command = (f"pendulab latex quarter-periods --count {count} --dps {dps} "
               f"--length {_quote(args.length)}")
    return _emit(command, fragment, [
        "002: differences of squares of the zeros of J1 and J2 (unit |dL/dt|/(4g)); "
        f"{q.direction} string."])
