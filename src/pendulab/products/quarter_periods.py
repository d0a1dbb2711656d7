"""Product "quarter_periods": the variable-length pendulum's quarter periods (002).

Writes ``quarter_periods.json``: the zeros of J1 and J2 and the differences of
their squares (time in units of v0/(4 g)) at the requested precision, the
check of the source's claim that a swing toward equilibrium lasts longer than
the outward swings around it, and the cross-product identity's residual.
"""

from pendulab.io import canonical_json

from pendulab.limits import option as _limited

#: Type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "count": _limited("quarter_periods.count"),
    "dps": _limited("quarter_periods.dps"),
}
SYSTEMS = ("variable-length",)


def produce(ctx, options):
    import mpmath
    from pendulab.analyses.bessel import (check_cross_product_numerically, quarter_periods,
                                          toward_swings_are_longer)
    from pendulab.errors import InputError
    if not ctx.get("system").is_linear_length:
        raise InputError("quarter_periods needs L(t) = L0 + v0*t")
    from pendulab import limits
    for key in ("count", "dps"):
        limits.check(f"quarter_periods.{key}", options[key], label=f"quarter_periods: {key}")
    dps = options["dps"]
    periods = quarter_periods(options["count"], dps)
    verdict = toward_swings_are_longer(periods)

    def s(x):
        return mpmath.nstr(x, dps, strip_zeros=False)
    rows = [{"from": r["from"], "to": r["to"], "direction": r["direction"],
             "z_from": s(r["z_from"]), "z_to": s(r["z_to"]), "duration": s(r["duration"])}
            for r in periods]
    zs = [mpmath.mpf(k) / 4 for k in range(1, 161)]
    residual = check_cross_product_numerically(1, zs, dps=dps)
    doc = {
        "scene": ctx.scene.name,
        "time_unit": "v0/(4*g)",
        "quarter_periods": rows,
        "toward_longer_than_neighbours": all(ok for _, ok in verdict),
        "cross_product_identity": {
            "identity": "besselj(1, z)*bessely(2, z) - besselj(2, z)*bessely(1, z) = -2/(pi*z)",
            "z_range": "0.25..40",
            "max_residual_below": mpmath.nstr(mpmath.mpf(10) ** (-dps + 2), 3),
            "holds": bool(residual < mpmath.mpf(10) ** (-dps + 2)),
        },
        "dps": dps,
    }
    return {"quarter_periods.json": canonical_json(doc)}
