"""pendulab bessel zeros|quarter-periods|identities ... [--json]"""

import argparse


def add_parser(sub):
    from pendulab.limits import (BESSEL_ZERO_WORK, QUARTER_PERIOD_WORK, WORK_BUDGET_SECONDS,
                                 argument)
    p = sub.add_parser(
        "bessel", help="certified Bessel zeros, 002's quarter periods and identity checks",
        description="High-precision, certified Bessel computations for the variable-length "
                    "pendulum (002_19b336b29bb1f03b.txt).  Every printed digit is proved "
                    "(python-flint ball arithmetic).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    what = p.add_subparsers(dest="what", metavar="WHAT")
    what.required = True
    z = what.add_parser("zeros", help="zeros j_n,1 .. j_n,K of J_n",
                        description="The first K positive zeros of J_n for a real order n >= 0 "
                                    "(up to 300), each certified by an interval Newton step and its "
                                    "index by Sturm windows.  K x dps is at most "
                                    f"{BESSEL_ZERO_WORK} (about a minute).",
                        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    argument(z, "--order", "bessel.order", required=True, metavar="N",
             text="n, a real number (1, 2.5, 1/3)")
    argument(z, "--count", "bessel.zeros", required=True, metavar="K", text="K")
    argument(z, "--dps", "bessel.dps", default="30", text="significant digits")
    z.add_argument("--json", action="store_true", help="print JSON ({\"zeros\": [...]})")
    from pendulab.plots import plot_option
    plot_option(z, "j_n,k against k over McMahon's beta_k = (k + n/2 - 1/4) pi, and j_n,k - "
                   "beta_k with McMahon's expansion, which tends to 0 (DLMF 10.21.19)")
    z.set_defaults(func=run_zeros)
    q = what.add_parser("quarter-periods", help="002's quarter periods (differences of squares of zeros)",
                        description="inward[k] = j_1,k+2^2 - j_2,k+1^2 and outward[k] = j_2,k+2^2 - "
                                    "j_1,k+2^2, k = 0..K-1 (unit v0/(4g)), with the margins of the "
                                    "source's claim; --shortening for L = L0 - v0 t.  "
                                    f"K x dps is at most {QUARTER_PERIOD_WORK}.",
                        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    argument(q, "--count", "quarter_periods.count", required=True, metavar="K", text="K")
    argument(q, "--dps", "quarter_periods.dps", default="30", text="significant digits")
    q.add_argument("--shortening", action="store_true",
                   help="a shortening string: z decreases from j_2,m to 0 (K quarter periods in all)")
    q.add_argument("--json", action="store_true", help="print JSON")
    plot_option(q, "the two margins of the claim against k with their limits 6 -+ pi^2/2 as "
                   "k -> oo (derived from McMahon's expansion, DLMF 10.21.19; drawn for a "
                   "growing string)")
    q.set_defaults(func=run_quarter)
    i = what.add_parser("identities", help="check 002's Bessel identities at any precision",
                        description="Worst relative error of J_n Y_n+1 - J_n+1 Y_n = -2/(pi z), "
                                    "d/dz[z^-n C_n] = -z^-n C_n+1 (C = J, Y) and z W = 2/pi for "
                                    "n = 0..N over log-spaced z in [1e-30, 1e6] and points next to "
                                    "zeros, by arb balls and mpmath (which must agree).  "
                                    "The work of N, the points and the digits together "
                                    f"is bounded (about {WORK_BUDGET_SECONDS} s by the cost "
                                    "model of pendulab.limits).",
                        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    argument(i, "--nmax", "bessel.nmax", required=True, metavar="N", text="N")
    argument(i, "--dps", "bessel.dps", default="30", text="digits")
    argument(i, "--points", "bessel.points", default="60", text="log-spaced points")
    argument(i, "--z", "bessel.z", action="append", default=None,
             text="check at this z instead of the grid (repeatable)")
    i.add_argument("--engine", choices=("both", "arb", "mpmath"), default="both",
                   help="which engines to run")
    i.add_argument("--cross-only", action="store_true",
                   help="check only the cross product (no derivatives; about 3x faster)")
    i.add_argument("--json", action="store_true", help="print JSON")
    i.set_defaults(func=run_identities)
    return p


def run_zeros(args):
    from pendulab import limits
    problems = limits.Problems()
    order = problems.parse("bessel.order", args.order, "--order")
    count = problems.parse("bessel.zeros", args.count, "--count")
    dps = problems.parse("bessel.dps", args.dps, "--dps")
    budget = limits.BESSEL_ZERO_WORK
    dear = order is not None and order != int(order)
    if dear:
        budget //= limits.BESSEL_NON_INTEGER_FACTOR
    if count is not None and dps is not None and count * dps > budget:
        problems.add(f"--count x --dps = {count * dps} is more than {budget} digits in all "
                     f"{'for a non-integer order ' if dear else ''}(about a minute): "
                     "ask for fewer or shorter numbers")
    from pendulab.plots import requested_format
    plot_format = requested_format(args, problems)
    problems.raise_any()

    from pendulab.analyses.bessel_zeros import bessel_zeros
    from pendulab.io import canonical_json
    res = bessel_zeros(args.order, count, dps)
    if plot_format is not None:
        from pendulab import plots
        fig = plots.zeros_figure(res.nu, [float(x) for x in res.strings],
                                 rf"The first {len(res.strings)} positive zeros of $J_\nu$, $\nu = {res.nu}$")
        plots.write(fig, args.plot, plot_format)
    if args.json:
        print(canonical_json({"order": str(res.nu), "dps": res.dps, "zeros": res.strings,
                              "certified": True, "phase_checked": res.phase_checked}), end="")
        return 0
    print(f"zeros of J_{res.nu}, {res.dps} significant digits, every digit certified")
    for k, s in enumerate(res.strings, start=1):
        print(f"j_{res.nu},{k} = {s}")
    return 0


def run_quarter(args):
    from pendulab import limits
    problems = limits.Problems()
    count = problems.parse("quarter_periods.count", args.count, "--count")
    dps = problems.parse("quarter_periods.dps", args.dps, "--dps")
    if count is not None and dps is not None and count * dps > limits.QUARTER_PERIOD_WORK:
        problems.add(f"--count x --dps = {count * dps} is more than {limits.QUARTER_PERIOD_WORK} "
                     "(about a minute): ask for fewer or shorter numbers")
    from pendulab.plots import requested_format
    plot_format = requested_format(args, problems)
    problems.raise_any()

    from pendulab.analyses.bessel_periods import GROWING, SHORTENING, quarter_periods
    from pendulab.io import canonical_json
    from pendulab.products.bessel import quarter_record
    q = quarter_periods(count, dps, SHORTENING if args.shortening else GROWING)
    rec = quarter_record(q)
    if plot_format is not None:
        _plot_margins(args.plot, plot_format, q)
    if args.json:
        print(canonical_json(rec), end="")
        return 0
    print(f"quarter periods, {q.direction} string from {rec['start']}, unit {rec['time_unit']}")
    for k in range(max(len(q.inward), len(q.outward))):
        a = q.inward[k] if k < len(q.inward) else "(none)"
        b = q.outward[k] if k < len(q.outward) else "(none)"
        print(f"{k}: inward {a}   outward {b}")
    compared = len(q.margin_after) + len(q.margin_before)
    verdict = {True: "holds for every k shown" if compared > 1 else
               "holds for the one comparison shown (an inward swing against the outward one "
               "after it; ask for a larger --count for more)",
               False: "does not hold: an outward swing outlasts an inward one",
               None: "not tested: no outward swing beside an inward one among those shown "
                     "(ask for a larger --count)"}[q.claim_holds]
    print(f"claim ({rec['claim']}): {verdict}")
    if q.time_to_zero_length is not None:
        print(f"L reaches 0 at t = {q.time_to_zero_length} (z = 0)")
    return 0


def _plot_margins(path, fmt, q):
    """--plot of quarter-periods: the margins against k and their derived limits."""
    from pendulab import plots
    from pendulab.analyses.bessel_periods import GROWING, margin_limits
    after, before = (None, None)
    if q.direction == GROWING:  # the limits of the growing string's margins (k -> oo)
        after, before, _ = margin_limits()
        after, before = float(after), float(before)
    title = (f"002's claim, {q.direction} string from $z_0 = j_{{2,{q.start}}}$: each margin > 0")
    fig = plots.margins_figure(q.margin_after, q.margin_before, after, before, title)
    plots.write(fig, path, fmt)


def run_identities(args):
    from pendulab import limits
    problems = limits.Problems()
    nmax = problems.parse("bessel.nmax", args.nmax, "--nmax")
    dps = problems.parse("bessel.dps", args.dps, "--dps")
    count = problems.parse("bessel.points", args.points, "--points")
    zs = [problems.parse("bessel.z", z, "--z") for z in args.z or ()]
    most = limits.LIMITS["bessel.points"][2]
    if len(zs) > most:
        problems.add(f"at most {most} --z values (as many as --points), got {len(zs)}")
    if zs:
        count = len(zs)
    if not problems:
        seconds = limits.identities_seconds(nmax, count, dps)
        if seconds > limits.WORK_BUDGET_SECONDS:
            problems.add(f"n = 0..{nmax} at {count} points and {dps} digits would take about "
                         f"{seconds:.0f} s by the cost model of pendulab.limits (limit "
                         f"{limits.WORK_BUDGET_SECONDS} s): ask for fewer --points (or --z "
                         "values), a smaller --nmax or fewer --dps")
    problems.raise_any()

    import mpmath

    from pendulab.analyses.bessel_identities import ENGINES, check_identities, default_grid
    from pendulab.io import canonical_json
    points = zs if zs else default_grid(count)
    engines = ENGINES if args.engine == "both" else (args.engine,)
    from pendulab.analyses.bessel_identities import RULES
    rep = check_identities(nmax, dps, points, engines, ("cross",) if args.cross_only else RULES)
    e = lambda x: mpmath.nstr(x, 3)  # noqa: E731
    rec = {
        "nmax": rep.nmax, "dps": rep.dps, "points": len(rep.points), "engines": list(rep.engines),
        "worst_relative_error": e(rep.worst[0]), "worst_z": rep.worst[1],
        "worst_identity": rep.worst[2], "worst_n": rep.worst[3], "worst_engine": rep.worst[4],
        "in_units_of_10^-dps": e(rep.ratio),
        "by_identity": {f"{eng}/{rule}": {"error": e(v[0]), "z": v[1], "n": v[2]}
                        for (eng, rule), v in sorted(rep.by_rule.items())},
        "arb_balls_contain_exact_values": rep.arb_certified, "engine_agreements": rep.agreements,
    }
    if args.json:
        print(canonical_json(rec), end="")
        return 0
    print(f"identities n = 0..{rep.nmax} at {rep.dps} digits, {len(rep.points)} points, "
          f"engines {', '.join(rep.engines)}")
    for key, v in rec["by_identity"].items():
        print(f"{key:24s} worst {v['error']} at z = {v['z']!r}, n = {v['n']}")
    print(f"worst relative error {rec['worst_relative_error']} = {rec['in_units_of_10^-dps']} x 10^-{rep.dps}")
    return 0
