"""pendulab stability [--body rod|point | --inertia-ratio R] --ratio W0_OVER_W [--method M] [--json]
   [--plot FILE]"""

#: ratios omega0/omega at which --plot computes the limits (0 to the top, evenly)
PLOT_POINTS = 81
#: the smallest top of the plotted ratios (the range is 0 .. max(2 W0_OVER_W, this))
PLOT_MIN_TOP = 0.5


def add_parser(sub):
    p = sub.add_parser(
        "stability", help="limits of a/l for the inverted pendulum",
        description="Lower and upper limits of a/l between which the inverted position of a "
                    "body on a vertically driven pivot is stable, for omega0/omega = W0_OVER_W, "
                    "by the exact Floquet curves or by the source's approximations "
                    "(000_8cba66c4fdf94ac6.txt eqs. 12, 19, 28).")
    from pendulab.limits import argument, describe
    body = p.add_mutually_exclusive_group()
    body.add_argument("--body", choices=("rod", "point"),
                      help="rod: I/(m l^2) = 4/3; point: 1 (default: rod)")
    argument(body, "--inertia-ratio", "stability.inertia_ratio", metavar="I_OVER_ML2",
             text="I/(m l^2) (I = m l^2 + I0, I0 >= 0; instead of --body)")
    argument(p, "--ratio", "stability.ratio", metavar="W0_OVER_W", required=True,
             text="omega0/omega")
    p.add_argument("--method", default="exact", metavar="METHOD",
                   help="exact, eq12, eq19, eq19-corrected, eq28, series:N "
                        f"(N {describe('stability.series_order')}) or integer-series:N "
                        f"(the a_0, b_1 series, N {describe('stability.integer_series_order')})")
    p.add_argument("--json", action="store_true", help="print a JSON record")
    from pendulab.plots import plot_option
    plot_option(p, f"the method's lower and upper limits of a/l against omega0/omega on "
                   f"{PLOT_POINTS} ratios from 0 to twice W0_OVER_W (at least to "
                   f"{PLOT_MIN_TOP}), the stable band between them shaded and W0_OVER_W marked")
    p.set_defaults(func=run)
    return p


def _format(value):
    return "none" if value is None else repr(value)


def run(args):
    import sys
    from fractions import Fraction

    from pendulab import limits as L
    from pendulab.analyses.stability import parse_method, report
    from pendulab.io import canonical_json

    problems = L.Problems()
    body = None if args.inertia_ratio is not None else (args.body or "rod")
    if body is None:
        inertia = problems.parse("stability.inertia_ratio", args.inertia_ratio, "--inertia-ratio")
    ratio = problems.parse("stability.ratio", args.ratio, "--ratio")
    problems.call(parse_method, args.method, prefix="--method: ")
    from pendulab.plots import requested_format
    plot_format = requested_format(args, problems)
    problems.raise_any()  # before SymPy is imported: a usage error answers at once
    if body is not None:
        from pendulab import symbols as S
        from pendulab.systems import BODIES
        exact_inertia = Fraction(str(BODIES[body] / (S.m * S.l**2)))
        inertia = float(exact_inertia)  # I/(m l^2) of the systems' own table
    else:
        exact_inertia = L.fraction(args.inertia_ratio)
    # the digits of a band too narrow for doubles are those of the numbers as typed
    found = report(ratio, inertia, args.method, exact_ratio=L.fraction(args.ratio),
                   exact_inertia_ratio=exact_inertia)
    lower, upper = found["lower"], found["upper"]
    record = {"lower": lower, "upper": upper, "method": args.method, "ratio": ratio,
              "body": body, "inertia_ratio": inertia}
    if found["why"]:
        record["why"] = found["why"]
    if "band" in found:
        record["band"] = found["band"]
    note = _note(found)
    if note:
        record["note"] = note
    if plot_format is not None:
        _plot(args.plot, plot_format, record)
    if args.json:
        sys.stdout.write(canonical_json(record))
    else:
        for key in ("method", "body", "inertia_ratio", "ratio", "lower", "upper"):
            if key == "body" and record[key] is None:  # --inertia-ratio: no named body
                print(f"body: custom, I/(m l^2) = {args.inertia_ratio.strip()}")
                continue
            print(f"{key}: {_format(record[key]) if key in ('lower', 'upper') else record[key]}")
        band = found.get("band")
        if band:
            proved = "certified " if band["certified_digits"] else ""
            if band["lower"] is not None:
                print(f"band at {band['digits']} {proved}digits: {band['lower']} to "
                      f"{band['upper']} (relative width {band['relative_width']:.3g})")
            else:
                print(f"band at {band['digits']} {proved}digits: both ends are "
                      f"{band['both_ends']}")
        if note:
            print(f"note: {note}")
    return 0


def _note(found):
    """Why each limit is missing, one clause per limit ("" when neither is)."""
    why = found["why"]
    if "band" in found:  # one reason for both: the band is narrower than a double resolves
        return f"lower and upper none: {why['lower']}"
    said = [f"{name} none: {why[name]}" for name in ("lower", "upper") if name in why]
    return "; ".join(said + ([found["closes"]] if "closes" in found else []))


def plot_ratios(ratio):
    """The ratios of --plot: PLOT_POINTS from 0 to max(2 ratio, PLOT_MIN_TOP), capped at the
    largest ratio the command takes, with ``ratio`` itself among them."""
    from pendulab.limits import LIMITS
    top = min(max(2 * ratio, PLOT_MIN_TOP), float(LIMITS["stability.ratio"][2]))
    values = [top * k / (PLOT_POINTS - 1) for k in range(PLOT_POINTS)]
    return sorted(set(values) | {ratio})


def _plot(path, fmt, record):
    """--plot: the limits by the same method over :func:`plot_ratios`."""
    from pendulab import plots
    from pendulab.analyses.stability import limits
    ratios = plot_ratios(record["ratio"])
    pairs = [limits(w, record["inertia_ratio"], record["method"]) for w in ratios]
    who = record["body"] or f"I/(m l²) = {record['inertia_ratio']:g}"
    title = f"Inverted pendulum ({who}): limits of a/l, {plots.method_name(record['method'])}"
    fig = plots.stability_figure(ratios, [p[0] for p in pairs], [p[1] for p in pairs], record["ratio"],
                                 (record["lower"], record["upper"]), record["method"], title)
    plots.write(fig, path, fmt)
