"""pendulab sweep [--body rod|point | --inertia-ratio R] --theta-init X --omega-init Y --grid N
   --periods P --steps-per-period S --criterion mean|mean-abs|bounded|floquet [--drive EXPR]
   [--json] [--quiet] [--dask ADDRESS] [--plot FILE]"""

import argparse
import re

#: Option values that are negative numbers ("-0.05", "-1e-3", "-1/5") are values, not options.
NEGATIVE_NUMBER = re.compile(r"^-(\d+(\.\d*)?|\.\d+)([eE][-+]?\d+)?(/\d+)?$")


def body_options(p):
    """--body / --inertia-ratio, shared with ``pendulab simulate``."""
    from pendulab.limits import argument
    body = p.add_mutually_exclusive_group()
    body.add_argument("--body", choices=("rod", "point"),
                      help="rod: I/(m l^2) = 4/3; point mass: 1 (default: rod)")
    argument(body, "--inertia-ratio", "stability.inertia_ratio", metavar="R",
             text="I/(m l^2) of a rigid body (instead of --body)")


def accept_negative_numbers(p):
    # argparse takes "-1e-3" for an option unless told otherwise (no option of ours starts with a digit)
    p._negative_number_matcher = NEGATIVE_NUMBER


def system_spec(args, problems):
    """The SystemSpec of --body / --inertia-ratio (a refused ratio is recorded in ``problems``,
    a :class:`pendulab.limits.Problems`, and gives None)."""
    from pendulab.numerics.sweep import SystemSpec
    if args.inertia_ratio is not None:
        ratio = problems.parse("stability.inertia_ratio", args.inertia_ratio, "--inertia-ratio")
        return None if ratio is None else SystemSpec("explicit", inertia_ratio=ratio)
    return SystemSpec(args.body or "rod")


def drive_option(p, note=""):
    """--drive EXPR, shared by ``sweep``, ``simulate`` and ``animate kapitza``."""
    p.add_argument("--drive", metavar="EXPR",
                   help="pivot displacement y0(t), periodic in t, with amplitude a and "
                        "frequency omega (e.g. 'a*cos(omega*t) + a*cos(2*omega*t)'; default: "
                        "the source's a*cos(omega*t))" + note)


def with_drive(args, system, problems):
    """``system`` with the drive of --drive, parsed once (a refused drive is recorded in
    ``problems`` and leaves ``system`` as it was)."""
    if getattr(args, "drive", None) is not None and system is not None:
        from dataclasses import replace

        from pendulab.exprs import parse
        if problems.call(parse, args.drive, prefix="--drive: ") is not None:
            return replace(system, drive=args.drive)
    return system


def backend_estimate():
    """"c" when the C compiler is found on this machine (the "auto" backend then builds the C
    kernel), else "numpy" (the cost model then takes the NumPy path's speed)."""
    from pendulab.numerics.ckernel import compiler_found
    return "c" if compiler_found() else "numpy"


def add_parser(sub):
    from pendulab.limits import WORK_BUDGET_SECONDS, argument
    from pendulab.numerics.sweep import CRITERIA
    p = sub.add_parser(
        "sweep", help="stability map of the inverted pendulum over (a/l, omega0/omega)",
        description="Integrate the full equation of motion in tau (000 sec. 4) with fixed-step "
                    "RK4 for N x N pairs, a/l and omega0/omega each on linspace(0, 1, N), and "
                    "count the pairs whose inverted position is stable by the criterion: "
                    "mean (|mean theta| < 0.1), mean-abs (mean |theta| < 0.1), bounded "
                    "(|theta| < pi/2 throughout) or floquet (exact linear verdict, no "
                    "integration).  Initial angle and rate are theta(0) and dtheta/dtau(0).  The work "
                    f"of all cells together is bounded (about {WORK_BUDGET_SECONDS} s by the "
                    "cost model of pendulab.limits).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(p)
    body_options(p)
    drive_option(p, "; a non-Mathieu drive takes the floquet verdict from the monodromy matrix")
    argument(p, "--theta-init", "sweep.theta_init", default="0.06", metavar="X")
    argument(p, "--omega-init", "sweep.omega_init", default="0.01", metavar="Y")
    argument(p, "--grid", "experiments.grid", default="10", metavar="N",
             text="N values of a/l and of omega0/omega")
    argument(p, "--periods", "experiments.periods", default="300", metavar="P",
             text="drive periods integrated")
    argument(p, "--steps-per-period", "experiments.steps_per_period", default="100", metavar="S")
    p.add_argument("--criterion", default="mean", metavar="C",
                   help=f"stability criterion: {', '.join(CRITERIA)}")
    p.add_argument("--prune", action="store_true",
                   help="integrate only the cells whose verdict the Floquet map may not give "
                        "(docs/experiments.md); the rest take the Floquet verdict")
    p.add_argument("--linear", action="store_true", help="integrate the linearised equation (000 eq. 7)")
    p.add_argument("--dask", metavar="ADDRESS", help="run the chunks on this dask.distributed scheduler")
    argument(p, "--processes", "sweep.processes", metavar="K",
             text="local worker processes (default: automatic; 1 runs in this process)")
    p.add_argument("--json", action="store_true", help="print a JSON record (keys count, stable, ...)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    from pendulab.plots import plot_option
    plot_option(p, "the map: stable cells as open circles over the Floquet-stable region (shaded), "
                   "its edge (the exact limits, dashed) and eq. 28's limits, as the experiments "
                   "product draws Figs. 3-4")
    p.set_defaults(func=run)
    return p


def run(args):
    import sys

    from pendulab import limits
    from pendulab.io import canonical_json
    from pendulab.numerics import sweep as S

    problems = limits.Problems()
    system = system_spec(args, problems)
    system = with_drive(args, system, problems)
    th = problems.parse("sweep.theta_init", args.theta_init, "--theta-init")
    om = problems.parse("sweep.omega_init", args.omega_init, "--omega-init")
    grid = problems.parse("experiments.grid", args.grid, "--grid")
    periods = problems.parse("experiments.periods", args.periods, "--periods")
    steps = problems.parse("experiments.steps_per_period", args.steps_per_period,
                           "--steps-per-period")
    workers = None
    if args.processes is not None:
        workers = problems.parse("sweep.processes", args.processes, "--processes")
    if args.criterion not in S.CRITERIA:
        problems.add(f"--criterion must be one of {', '.join(S.CRITERIA)}, got {args.criterion!r}")
    if args.prune and args.criterion == "floquet":
        problems.add("--prune applies to mean, mean-abs and bounded (floquet integrates nothing)")
    if args.dask is not None and args.processes is not None:
        problems.add("give --dask or --processes, not both")
    from pendulab.plots import requested_format
    plot_format = requested_format(args, problems)
    if not problems:
        work = limits.sweep_problem(grid * grid, periods * steps, backend_estimate(),
                                    args.criterion, drive=args.drive is not None)
        if work:
            problems.add(work)
        if args.prune and S.stages(system)[1].kind != "mathieu":
            problems.add("--prune: the drive gives a Hill equation, and pruning needs Mathieu's "
                         "(theta0, theta1) (its Floquet exponents choose the cells integrated): "
                         "leave out --prune")
    problems.raise_any()
    spec = S.make_spec(system, grid, theta_init=th, omega_init=om, periods=periods,
                       steps_per_period=steps, criterion=args.criterion, linear=args.linear)
    said = []
    if spec.criterion != "floquet":  # the floquet criterion integrates nothing
        from pendulab.numerics.step_check import enforce
        # an unstable step is refused before any cell runs; a coarse one is said
        enforce(spec, f"--steps-per-period {steps}", warn=said.append)
    executor = "auto" if workers is None else ("serial" if workers == 1 else "processes")
    kwargs = dict(executor=executor, workers=workers, dask=args.dask, quiet=args.quiet)
    result = S.pruned_sweep(spec, **kwargs) if args.prune else S.sweep(spec, **kwargs)
    record = result.record()
    record["cells"] = spec.cells
    if said:
        record["step_warning"] = said[0]
    for line in said:
        sys.stderr.write(f"pendulab: {line}\n")
    if plot_format is not None:
        _plot(args.plot, plot_format, system, spec, result, record)
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


def _plot(path, fmt, system, spec, result, record):
    """--plot: the map of ``result`` drawn as the experiments product draws its maps."""
    from pendulab import plots
    from pendulab.numerics import sweep as S
    from pendulab.products.experiments import initial_title, map_limits
    mathieu = S.stages(system)[1].kind == "mathieu"
    # a Hill drive's region is the Floquet map on the sweep's own grid: the floquet
    # criterion's result itself
    known = result.stable[0] if not mathieu and spec.criterion == "floquet" else None
    limits, region = map_limits(system, mathieu, spec.w0_over_w, known)
    th, om = spec.initial[0]
    run = "" if spec.criterion == "floquet" else f" ({spec.periods} periods × {spec.steps_per_period} steps)"
    title = initial_title(th, om, len(spec.a_over_l), limits, extra=f", {record['body']}")
    fig = plots.sweep_figure(spec.a_over_l, spec.w0_over_w, result.stable[0], spec.criterion,
                             record["count"], limits, region, title, run)
    plots.write(fig, path, fmt)
