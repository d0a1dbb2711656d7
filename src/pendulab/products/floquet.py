"""Product "floquet": exact Floquet exponents and the exact first stable band.

Writes ``floquet.json``: for each requested (theta0, theta1) point the
characteristic exponent lambda, the multipliers and the verdict (000 eqs. 7-10;
these are points of Mathieu's plane, whatever the drive), and for each
requested omega0/omega the exact limits of a/l of the first stable band for
the scene's body and drive.  theta0 and theta1 come from the scene's own
derivation (:func:`pendulab.analyses.stability.scene_map`; for the source's
drive theta0 = -4 (omega0/omega)^2, theta1 = 2 (a/l)/(I/(m l^2)), 000 eqs.
5-6); a Hill drive gets its limits from the monodromy verdict along a/l
(double precision, :func:`pendulab.analyses.stability.hill_limits`); a
non-periodic drive is refused.  With scene ``[values]`` the file also holds
``scene_point``, the scene's own (theta0, theta1) and verdict.  All numbers
are strings at ``dps`` digits; the file is byte-identical on every run.
"""

from pendulab.limits import option as _limited

#: Numeric options take type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "points": _limited("floquet.points"),
    "ratios": _limited("floquet.ratios"),
    "dps": _limited("floquet.dps"),
    "method": (str, "auto", "auto (arb, every digit proved, where |theta0| + 2|theta1| <= 3e4; "
                            "hill beyond), arb, hill, cf or monodromy"),
}
SYSTEMS = ("kapitza",)


def _text(v, what):
    from pendulab.errors import InputError
    if isinstance(v, bool) or not isinstance(v, (str, int, float)):
        raise InputError(f"floquet product: {what} must be a number or a string, got {v!r}")
    return v if isinstance(v, str) else repr(v)


def _exact_text(text):
    from fractions import Fraction
    return float(Fraction(text)) if "/" in text else float(text)


def _drive_record(pmap):
    """What a drive other than the source's a cos(omega t) maps to (for the JSON)."""
    from pendulab.exprs import dump_expr
    out = {"drive": dump_expr(pmap.drive), "kind": pmap.kind}
    if pmap.kind == "mathieu":
        out["theta0"] = dump_expr(pmap.theta0)
        out["theta1"] = dump_expr(pmap.theta1)
        out["limits_note"] = (f"first stable band a_0(q) < theta0 < b_1(|q|), theta0 = "
                              f"{pmap.theta0}, |q| = theta1 = {pmap.theta1}")
    else:
        out["coefficient"] = dump_expr(pmap.form.coefficient)
        out["limits_note"] = ("first stable interval of a/l (Hill's equation): the Floquet "
                              "verdict |tr M| < 2 of the monodromy matrix (DOP853, rtol 1e-13) "
                              "on a/l = 0, 0.005, ..., 2, each end refined by Brent's method; "
                              "double precision")
    return out


def scene_point(ctx, pmap, dps, method):
    """The scene's own point: its [values] put into the derivation, and the verdict there."""
    import mpmath
    import sympy as sp

    from pendulab.analyses.floquet import characteristic_exponent
    from pendulab.analyses.floquet_format import number_text, result_record
    from pendulab.errors import InputError
    from pendulab.numerics.model import mathieu_parameters, pivot_system
    from pendulab.numerics.monodromy import floquet_verdict

    values = {str(k): v for k, v in ctx.scene.values.items()}
    eqs, form = ctx.get("equations"), ctx.get("canonical")
    if pmap.kind == "mathieu":
        th0, th1 = mathieu_parameters(eqs, form, values=values, groups=False)
        left = sorted(str(x) for x in (th0.free_symbols | th1.free_symbols))
        if left:
            return {"note": f"the scene's values leave {', '.join(left)} free: no point"}
        with mpmath.workdps(dps + 40):
            x0, x1 = (mpmath.mpf(sp.N(v, dps + 40)) for v in (th0, th1))
            t0, t1 = number_text(x0, dps), number_text(x1, dps)
        rec = result_record(characteristic_exponent(x0, x1, dps=dps, method=method), t0, t1)
        return rec
    fos = pivot_system(eqs, form, values=values, groups=False)
    if fos.params:
        return {"note": f"the scene's values leave {', '.join(s.name for s in fos.params)} "
                        "free: no point"}
    try:
        v = floquet_verdict(fos, {}, dps=dps, method="mp")
    except InputError as exc:
        return {"note": str(exc)}
    return {"trace": number_text(v.trace, dps), "stable": bool(v.stable),
            "on_boundary": bool(v.on_boundary), "method": "monodromy (mp Taylor)", "dps": dps}


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
    from pendulab.analyses.floquet._exponent import default_method
    method = options["method"]
    if method not in METHODS + ("auto",):
        problems.append(f"method must be auto or one of {', '.join(METHODS)}, got {method!r}")
    for i, pt in enumerate(options["points"]):
        try:
            if not isinstance(pt, list) or len(pt) != 2:
                raise InputError(f"points[{i}] must be a [theta0, theta1] pair, got {pt!r}"[:80])
            x0 = _exact(_text(pt[0], f"points[{i}][0]"), f"points[{i}][0]")
            x1 = _exact(_text(pt[1], f"points[{i}][1]"), f"points[{i}][1]")
            used = default_method(x0, x1, options["dps"]) if method == "auto" else method
            if used in METHODS:
                _check_size(x0, x1, SIZE_LIMITS[used], f"method {used!r}",
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
    limits.raise_problems(problems)


def produce(ctx, options):
    import sympy as sp

    from pendulab.analyses.floquet import METHODS, characteristic_exponent, map_limits
    from pendulab.analyses.stability import hill_limits, scene_map
    from pendulab.analyses.floquet_format import number_text, result_record
    from pendulab.errors import InputError
    from pendulab.io import canonical_json

    dps = options["dps"]
    method = options["method"]
    if method not in METHODS + ("auto",):
        raise InputError(f"floquet product: method must be auto or one of {', '.join(METHODS)}, "
                         f"got {method!r}")
    route = None if method == "auto" else method  # None: the API's own rule, point by point
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
    records = [result_record(characteristic_exponent(t0, t1, dps=dps, method=route), t0, t1)
               for t0, t1 in points]

    system = ctx.get("system")
    ratio_sym = sp.nsimplify(system.inertia_ratio)
    pmap = scene_map(ctx)
    if pmap.kind == "linear":
        pmap.refuse("floquet product", "Floquet exponents or limits of a/l")
    limits = None
    if pmap.kind == "hill" and ratio_sym.is_number:
        limits = []
        for r in ratios:
            lo, up = hill_limits(pmap, _exact_text(r))
            limits.append({"ratio": r, "lower": None if lo is None else number_text(lo, None),
                           "upper": None if up is None else number_text(up, None)})
    elif ratio_sym.is_Rational and ratio_sym > 0:
        limits = []
        for r in ratios:
            lim = map_limits(pmap, {"w0_over_w": r}, dps=dps, what=f"floquet limits at {r}")
            limits.append({"ratio": r, "lower": number_text(lim[0], dps),
                           "upper": number_text(lim[1], dps),
                           "certified_digits": getattr(lim, "certified_digits", None)})
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
    if not pmap.is_source_map(ratio_sym):
        doc.update(_drive_record(pmap))
    values = getattr(ctx.scene, "values", None)
    if values:
        doc["scene_point"] = scene_point(ctx, pmap, dps, route)
    return {"floquet.json": canonical_json(doc)}
