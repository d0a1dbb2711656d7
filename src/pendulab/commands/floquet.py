"""pendulab floquet --theta0 X --theta1 Y [--dps D] [--method hill|cf|monodromy] [--json]"""

import argparse


def add_parser(sub):
    p = sub.add_parser(
        "floquet", help="characteristic exponent, multipliers and stability of Mathieu's equation",
        description="Floquet exponent lambda of theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0 "
                    "(000 eq. 7), its multipliers exp(+-i pi lambda) and the stable/unstable "
                    "verdict.  X and Y are exact decimals or fractions (\"-0.002\", \"1/5\"), "
                    "read at the working precision.  A negative value that is not a plain "
                    "decimal (\"-1/5\", \"-1e-3\") must be attached with '=': "
                    "--theta0=-1/5.  Size limit: |theta0| + 2|theta1| <= 4e6 (hill), "
                    "3e4 (cf), 5e3 (monodromy).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--theta0", required=True, help="theta0 = -4 omega0^2/omega^2 (000 eq. 5); write --theta0=-1/5 for negative "
                        "fractions")
    p.add_argument("--theta1", required=True, help="theta1 = 2 a l m / I (000 eq. 6); --theta1=-1/5 likewise")
    p.add_argument("--dps", type=int, default=None,
                   help="decimal digits (default: double precision)")
    p.add_argument("--method", choices=("hill", "cf", "monodromy"), default="hill",
                   help="Hill's determinant, continued fractions, or monodromy matrix")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(func=run)
    return p


def run(args):
    from pendulab.analyses.floquet import characteristic_exponent
    from pendulab.analyses.floquet_format import result_record
    from pendulab.io import canonical_json

    res = characteristic_exponent(args.theta0, args.theta1, dps=args.dps, method=args.method)
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
    return 0
