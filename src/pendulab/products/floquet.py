"""Product "floquet": exact Floquet exponents and the exact first stable band.

Writes ``floquet.json``: for each requested (theta0, theta1) point the
characteristic exponent lambda, the multipliers and the verdict (000 eqs. 7-10),
and for each requested omega0/omega the exact limits of a/l of the first
stable band for the scene's body (theta0 = -4 (omega0/omega)^2, theta1 =
2 (a/l)/(I/(m l^2)); 000 eqs. 5-6).  All numbers are strings at ``dps`` digits;
the file is byte-identical on every run.
"""

from pendulab.limits import option as _limited

#: Numeric options take type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "points": _limited("floquet.points"),
    "ratios": _limited("floquet.ratios"),
    "dps": _limited("floquet.dps"),
    "method": (str, "hill", "hill, cf or monodromy"),
}
SYSTEMS = ("kapitza",)


def _text(v, what):
    from pendulab.errors import InputError
    if isinstance(v, bool) or not isinstance(v, (str, int, float)):
        raise InputError(f"floquet product: {what} must be a number or a string, got {v!r}")
    return v if isinstance(v, str) else repr(v)


def check_options(options):
    """Every problem of ``options`` found without computing (scene validation calls this).

    The method, each point's shape and numbers and its size limit for the
    method (pendulab.analyses.floquet.SIZE_LIMITS), each ratio's number, and
    the work of them all together (:func:`pendulab.limits.work_problem`).
    One InputError listing every problem, "; "-joined.
    """
    from pendulab import limits
    from pendulab.analyses.floquet import METHODS, SIZE_LIMITS, _check_size, _exact
    from pendulab.errors import InputError
    problems = []
    method = options["method"]
    if method not in METHODS:
        problems.append(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    for i, pt in enumerate(options["points"]):
        try:
            if not isinstance(pt, list) or len(pt) != 2:
                raise InputError(f"points[{i}] must be a [theta0, theta1] pair, got {pt!r}"[:80])
            x0 = _exact(_text(pt[0], f"points[{i}][0]"), f"points[{i}][0]")
            x1 = _exact(_text(pt[1], f"points[{i}][1]"), f"points[{i}][1]")
            if method in METHODS:
                _check_size(x0, x1, SIZE_LIMITS[method], f"method {method!r}",
                            names=(f"points[{i}][0]", f"points[{i}][1]"))
        except InputError as exc:
            problems.append(str(exc).replace("floquet product: ", ""))
    for i, r in enumerate(options["ratios"]):
        try:
            _exact(_text(r, f"ratios[{i}]"), f"ratios[{i}]")
        except InputError as exc:
            problems.append(str(exc).replace("floquet product: ", ""))
    if not problems:
        work = limits.work_problem("floquet", options)
        if work:
            problems.append(work)
    if problems:
        err = InputError("; ".join(problems))
        err.problems = problems
        raise err


def produce(ctx, options):
    import sympy as sp

    from pendulab.analyses.floquet import METHODS, characteristic_exponent, stability_limits
    from pendulab.analyses.floquet_format import number_text, result_record
    from pendulab.errors import InputError
    from pendulab.io import canonical_json

    dps = options["dps"]
    method = options["method"]
    if method not in METHODS:
        raise InputError(f"floquet product: method must be one of {', '.join(METHODS)}, got {method!r}")
    from pendulab import limits
    for key in ("dps", "points", "ratios"):
        limits.check(f"floquet.{key}", options[key], label=f"floquet product: {key}")
    work = limits.work_problem("floquet", options)
    if work:
        raise InputError(f"floquet product: {work}")
    points = []
    for i, pt in enumerate(options["points"]):
        if not isinstance(pt, list) or len(pt) != 2:
            raise InputError(f"floquet product: points[{i}] must be a [theta0, theta1] pair, got {pt!r}")
        points.append((_text(pt[0], f"points[{i}][0]"), _text(pt[1], f"points[{i}][1]")))
    ratios = [_text(r, f"ratios[{i}]") for i, r in enumerate(options["ratios"])]

    # all input is checked before any number is computed
    records = [result_record(characteristic_exponent(t0, t1, dps=dps, method=method), t0, t1)
               for t0, t1 in points]

    system = ctx.get("system")
    ratio_sym = sp.nsimplify(system.inertia_ratio)
    limits = None
    if ratio_sym.is_Rational and ratio_sym > 0:
        inertia = f"{ratio_sym.p}/{ratio_sym.q}"
        limits = []
        for r in ratios:
            lo, up = stability_limits(r, inertia, dps=dps)
            limits.append({"ratio": r, "lower": number_text(lo, dps), "upper": number_text(up, dps)})
    doc = {
        "source": "000_8cba66c4fdf94ac6.txt eqs. 5-10; DLMF 28.2, 28.4",
        "dps": dps,
        "method": method,
        "points": records,
        "body": system.body,
        "I_over_ml2": str(ratio_sym),
        "limits": limits,
        "limits_note": "first stable band a_0(q) < theta0 < b_1(q), q = 2 (a/l)/(I/(m l^2))",
    }
    return {"floquet.json": canonical_json(doc)}
