"""pendulab floquet --theta0 THETA0 --theta1 THETA1 [--dps D] [--method arb|hill|cf|monodromy] [--json]"""


#: pendulab.analyses.floquet.SIZE_LIMITS as text (not imported to build the parser; a test
#: checks that they agree)
SIZES = "4e+06 (hill), 30000 (cf), 5000 (monodromy), 30000 (arb)"


def add_parser(sub):
    from pendulab.limits import WORK_BUDGET_SECONDS, argument, describe
    sizes = SIZES
    p = sub.add_parser(
        "floquet", help="characteristic exponent, multipliers and stability of Mathieu's equation",
        description="Floquet exponent lambda of theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0 "
                    "(000 eq. 7), its multipliers exp(+-i pi lambda) and the stable/unstable "
                    "verdict.  theta0 and theta1 are exact decimals or fractions (\"-0.002\", "
                    "\"-1/5\"), read at the working precision.  Size limit: "
                    f"|theta0| + 2|theta1| <= {sizes}; the work of one point is also bounded "
                    f"(about {WORK_BUDGET_SECONDS} s by the cost model of pendulab.limits).")
    argument(p, "--theta0", "floquet.theta0", required=True, metavar="THETA0",
             text="theta0 = -4 omega0^2/omega^2 (000 eq. 5), e.g. -0.002 or -1/5")
    argument(p, "--theta1", "floquet.theta1", required=True, metavar="THETA1",
             text="theta1 = 2 a l m / I (000 eq. 6), e.g. 0.2 or 1/5")
    argument(p, "--dps", "floquet.dps", default=None,
             help=f"decimal digits, {describe('floquet.dps')} (default: double precision)")
    p.add_argument("--method", choices=("arb", "hill", "cf", "monodromy"), default=None,
                   help="arb: every digit proved in ball arithmetic (the default with --dps); "
                        "hill (the default without), cf, monodromy: Hill's determinant, "
                        "continued fractions, monodromy matrix in mpmath")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)
    return p


def run(args):
    from pendulab import limits
    from pendulab.errors import InputError
    problems = limits.Problems()
    problems.parse("floquet.theta0", args.theta0, "--theta0")
    problems.parse("floquet.theta1", args.theta1, "--theta1")
    dps = None if args.dps is None else problems.parse("floquet.dps", args.dps, "--dps")
    problems.raise_any()

    from pendulab.analyses.floquet import SIZE_LIMITS, _check_size, _exact, characteristic_exponent
    from pendulab.analyses.floquet_format import result_record
    from pendulab.io import canonical_json
    if args.method is None:
        from pendulab.analyses.floquet._exponent import default_method
        args.method = default_method(_exact(args.theta0, "theta0"), _exact(args.theta1, "theta1"),
                                     dps)
    # the method's size limit first (its own message), then the work
    _check_size(_exact(args.theta0, "theta0"), _exact(args.theta1, "theta1"),
                SIZE_LIMITS[args.method], f"method {args.method!r}")
    work = limits.work_problem("floquet", {"points": [[args.theta0, args.theta1]], "ratios": [],
                                           "dps": dps, "method": args.method},
                               what="this point")
    if work:
        raise InputError(work)
    res = characteristic_exponent(args.theta0, args.theta1, dps=dps, method=args.method)
    rec = result_record(res, args.theta0, args.theta1)
    if args.json:
        print(canonical_json(rec), end="")
        return 0
    verdict = "stable" if rec["stable"] else "unstable"
    if rec["on_boundary"]:
        verdict += " (on a stability boundary to all the working precision)"
    digits = "double precision" if rec["dps"] is None else f"{rec['dps']} digits"
    print(f"theta0 = {rec['theta0']}, theta1 = {rec['theta1']}  ({rec['method']}, {digits}, "
          f"depth {rec['depth']})")
    print(f"lambda      = {rec['lambda']}")
    print(f"multipliers = {rec['multipliers'][0]}, {rec['multipliers'][1]}")
    print(f"verdict     = {verdict}")
    cert = rec.get("certified_digits")
    if cert:
        said = f"{cert} significant digits of lambda proved (ball arithmetic)"
    elif rec["method"] == "arb":
        said = "no (proved in ball arithmetic, then rounded to a double; --dps 17 keeps the proof)"
    else:
        said = "no (not a ball-arithmetic result)"
    print("certified   = " + said)
    return 0
