"""Product "floquet": exact Floquet exponents and the exact first stable band.

Writes ``floquet.json``: for each requested (theta0, theta1) point the
characteristic exponent lambda, the multipliers and the verdict (000 eqs. 7-10),
and for each requested omega0/omega the exact limits of a/l of the first
stable band for the scene's body (theta0 = -4 (omega0/omega)^2, theta1 =
2 (a/l)/(I/(m l^2)); 000 eqs. 5-6).  All numbers are strings at ``dps`` digits;
the file is byte-identical on every run.
"""

OPTIONS = {
    "points": (list, [["-0.002", "0.2"]],
               "[theta0, theta1] pairs (strings such as \"-0.002\" or \"1/5\", or numbers)"),
    "ratios": (list, ["0", "0.05", "0.1", "0.2"], "omega0/omega values for the exact limits of a/l"),
    "dps": (int, 30, "decimal digits of every number written"),
    "method": (str, "hill", "hill, cf or monodromy"),
}
SYSTEMS = ("kapitza",)


def _text(v, what):
    from pendulab.errors import InputError
    if isinstance(v, bool) or not isinstance(v, (str, int, float)):
        raise InputError(f"floquet product: {what} must be a number or a string, got {v!r}")
    return v if isinstance(v, str) else repr(v)


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
    if not 1 <= dps <= 1000:
        raise InputError(f"floquet product: dps must be between 1 and 1000, got {dps}")
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
