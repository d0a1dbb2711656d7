"""Product "quarter_periods": the variable-length pendulum's quarter periods (002).

Writes ``quarter_periods.json``: the certified zeros of J1 and J2 used and the
quarter periods in time order (differences of squares, unit |dL/dt|/(4 g)),
for a growing or a shortening string as the canonical stage's rate says, with
the margins and the verdict of the source's claim that a swing toward
equilibrium lasts longer than the outward swings around it.  The same numbers
appear in the "bessel" product, which also checks the identities.
"""

from pendulab.io import canonical_json

from pendulab.limits import option as _limited

#: Type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "count": _limited("quarter_periods.count"),
    "dps": _limited("quarter_periods.dps"),
}
SYSTEMS = ("variable-length",)


def check_options(options):
    """The work of count and dps together, checked at scene validation (pendulab.limits)."""
    from pendulab import limits
    from pendulab.errors import InputError
    work = limits.work_problem("quarter_periods", options)
    if work:
        raise InputError(work)


def produce(ctx, options):
    from pendulab.analyses.bessel_periods import quarter_periods
    from pendulab.errors import InputError
    from pendulab import limits
    from pendulab.products.bessel import direction_from_stage, quarter_record
    for key in ("count", "dps"):
        limits.check(f"quarter_periods.{key}", options[key], label=f"quarter_periods: {key}")
    work = limits.work_problem("quarter_periods", options)
    if work:
        raise InputError(f"quarter_periods product: {work}")
    direction = direction_from_stage(ctx)
    q = quarter_periods(options["count"], options["dps"], direction)
    doc = {
        "scene": ctx.scene.name,
        "dps": options["dps"],
        "zeros_J1": q.zeros_j1,
        "zeros_J2": q.zeros_j2,
        **quarter_record(q),
    }
    return {"quarter_periods.json": canonical_json(doc)}
