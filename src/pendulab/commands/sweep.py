"""pendulab sweep [--body rod|point | --inertia-ratio R] --theta-init X --omega-init Y --grid N
   --periods P --steps-per-period S --criterion mean|mean-abs|bounded|floquet [--drive EXPR]
   [--json] [--quiet] [--dask ADDRESS]"""

import argparse
import re

#: Option values that are negative numbers ("-0.05", "-1e-3", "-1/5") are values, not options.
NEGATIVE_NUMBER = re.compile(r"^-(\d+(\.\d*)?|\.\d+)([eE][-+]?\d+)?(/\d+)?$")


def body_options(p):
    """--body / --inertia-ratio, shared with ``pendulab simulate``."""
    body = p.add_mutually_exclusive_group()
    body.add_argument("--body", choices=("rod", "point"),
                      help="rod: I/(m l^2) = 4/3; point mass: 1 (default: rod)")
    body.add_argument("--inertia-ratio", metavar="R",
                      help="I/(m l^2) of a rigid body, a number >= 1 (instead of --body)")


def accept_negative_numbers(p):
    # argparse takes "-1e-3" for an option unless told otherwise (no option of ours starts with a digit)
    p._negative_number_matcher = NEGATIVE_NUMBER


def number(text, name):
    """A finite float from the command-line text ``text`` (decimals or fractions)."""
    from fractions import Fraction

    from pendulab.errors import InputError
    try:
        value = float(Fraction(text.strip())) if "/" in text else float(text)
    except (ValueError, ZeroDivisionError):
        raise InputError(f"{name} must be a number, got {text!r}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise InputError(f"{name} must be a finite number, got {text!r}")
    return value


def whole(text, name, minimum):
    from pendulab.errors import InputError
    try:
        value = int(text)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a whole number, got {text!r}") from None
    if value < minimum:
        raise InputError(f"{name} must be at least {minimum}, got {value}")
    return value


def system_spec(args, problems):
    """The SystemSpec of --body / --inertia-ratio (problems are appended, not raised)."""
    from pendulab.analyses.stability import check_inertia_ratio
    from pendulab.errors import InputError
    from pendulab.numerics.sweep import SystemSpec
    if args.inertia_ratio is not None:
        try:
            ratio = check_inertia_ratio(number(args.inertia_ratio, "--inertia-ratio"))
        except InputError as exc:
            problems.append(f"--inertia-ratio: {exc}" if not str(exc).startswith("--") else str(exc))
            return None
        return SystemSpec("explicit", inertia_ratio=float(ratio))
    return SystemSpec(args.body or "rod")


def add_parser(sub):
    from pendulab.numerics.sweep import CRITERIA
    p = sub.add_parser(
        "sweep", help="stability map of the inverted pendulum over (a/l, omega0/omega)",
        description="Integrate the full equation of motion in tau (000 sec. 4) with fixed-step "
                    "RK4 for N x N pairs, a/l and omega0/omega each on linspace(0, 1, N), and "
                    "count the pairs whose inverted position is stable by the criterion: "
                    "mean (|mean theta| < 0.1), mean-abs (mean |theta| < 0.1), bounded "
                    "(|theta| < pi/2 throughout) or floquet (exact linear verdict, no "
                    "integration).  Initial angle and rate are theta(0) and dtheta/dtau(0).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(p)
    body_options(p)
    p.add_argument("--drive", metavar="EXPR",
                   help="pivot displacement y0(t), periodic in t (e.g. 'a*cos(omega*t) + "
                        "a*cos(2*omega*t)'; default: the source's a*cos(omega*t)); a non-Mathieu "
                        "drive takes the floquet verdict from the monodromy matrix")
    p.add_argument("--theta-init", default="0.06", metavar="X", help="theta(0) in rad")
    p.add_argument("--omega-init", default="0.01", metavar="Y", help="dtheta/dtau at tau = 0")
    p.add_argument("--grid", default="10", metavar="N", help="N values of a/l and of omega0/omega")
    p.add_argument("--periods", default="300", metavar="P", help="drive periods integrated")
    p.add_argument("--steps-per-period", default="100", metavar="S", help="RK4 steps per drive period")
    p.add_argument("--criterion", default="mean", metavar="C",
                   help=f"stability criterion: {', '.join(CRITERIA)}")
    p.add_argument("--prune", action="store_true",
                   help="integrate only the cells whose verdict the Floquet map may not give "
                        "(docs/experiments.md); the rest take the Floquet verdict")
    p.add_argument("--linear", action="store_true", help="integrate the linearised equation (000 eq. 7)")
    p.add_argument("--dask", metavar="ADDRESS", help="run the chunks on this dask.distributed scheduler")
    p.add_argument("--processes", metavar="K",
                   help="local worker processes (default: automatic; 1 runs in this process)")
    p.add_argument("--json", action="store_true", help="print a JSON record (keys count, stable, ...)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)
    return p


def run(args):
    import sys

    from pendulab.errors import InputError
    from pendulab.io import canonical_json
    from pendulab.numerics import sweep as S

    problems = []

    def collect(fn, *a):
        try:
            return fn(*a)
        except InputError as exc:
            problems.append(str(exc))

    system = system_spec(args, problems)
    if getattr(args, "drive", None) is not None and system is not None:
        from dataclasses import replace

        from pendulab.exprs import parse
        try:
            parse(args.drive)
            system = replace(system, drive=args.drive)
        except InputError as exc:
            problems.append(f"--drive: {exc}")
    th = collect(number, args.theta_init, "--theta-init")
    om = collect(number, args.omega_init, "--omega-init")
    grid = collect(whole, args.grid, "--grid", 1)
    periods = collect(whole, args.periods, "--periods", 1)
    steps = collect(whole, args.steps_per_period, "--steps-per-period", 1)
    workers = collect(whole, args.processes, "--processes", 1) if args.processes is not None else None
    if args.criterion not in S.CRITERIA:
        problems.append(f"--criterion must be one of {', '.join(S.CRITERIA)}, got {args.criterion!r}")
    if args.prune and args.criterion == "floquet":
        problems.append("--prune applies to mean, mean-abs and bounded (floquet integrates nothing)")
    if args.dask is not None and args.processes is not None:
        problems.append("give --dask or --processes, not both")
    if problems:
        raise InputError("; ".join(problems))
    spec = S.make_spec(system, grid, theta_init=th, omega_init=om, periods=periods,
                       steps_per_period=steps, criterion=args.criterion, linear=args.linear)
    executor = "auto" if workers is None else ("serial" if workers == 1 else "processes")
    kwargs = dict(executor=executor, workers=workers, dask=args.dask, quiet=args.quiet)
    result = S.pruned_sweep(spec, **kwargs) if args.prune else S.sweep(spec, **kwargs)
    record = result.record()
    record["cells"] = spec.cells
    if args.json:
        sys.stdout.write(canonical_json(record))
        return 0
    print(f"body {record['body']}, criterion {spec.criterion}, theta(0) = {th!r}, "
          f"theta'(0) = {om!r}, {grid} x {grid} grid, {periods} periods x {steps} steps")
    print(f"stable: {record['count']} of {spec.cells}  "
          f"({result.simulated} trajectories integrated, {result.seconds:.2f} s, {result.executor})")
    for a, w in record["stable"]:
        print(f"  a/l = {a!r}, omega0/omega = {w!r}")
    return 0
