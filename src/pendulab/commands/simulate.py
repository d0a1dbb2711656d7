"""pendulab simulate [--body rod|point | --inertia-ratio R] --a-over-l A --w0-over-w W
   --theta-init X --omega-init Y [--periods P] [--steps-per-period S] [--every K] [--linear]
   [--drive EXPR] [--reference] [--json | --csv] [--plot FILE]"""

import argparse


def add_parser(sub):
    from pendulab.commands.sweep import accept_negative_numbers, body_options, drive_option
    from pendulab.limits import argument
    p = sub.add_parser(
        "simulate", help="one trajectory of the driven pivot in tau (RK4)",
        description="Integrate the full equation of motion in the source's time tau = omega t/2 "
                    "(000 sec. 4) with fixed-step RK4 from theta(0), dtheta/dtau(0), for "
                    "a/l and omega0/omega; print tau, theta, dtheta/dtau every K steps and the "
                    "run's statistics (signed mean of theta, mean |theta|, max |theta|).  "
                    "--reference adds SciPy's DOP853 (rtol 1e-13) at the same times and the "
                    "largest difference.  The work of the options together is bounded (RK4 steps, "
                    "printed rows, and the reference's estimated DOP853 evaluations; see "
                    "docs/scenes.md, \"Limits\").",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(p)
    body_options(p)
    drive_option(p)
    argument(p, "--a-over-l", "simulate.a_over_l", required=True, metavar="A")
    argument(p, "--w0-over-w", "stability.ratio", required=True, metavar="W", text="omega0/omega")
    argument(p, "--theta-init", "sweep.theta_init", default="0.06", metavar="X")
    argument(p, "--omega-init", "sweep.omega_init", default="0.01", metavar="Y")
    argument(p, "--periods", "experiments.periods", default="10", metavar="P",
             text="drive periods (pi in tau each)")
    argument(p, "--steps-per-period", "experiments.steps_per_period", default="100", metavar="S")
    argument(p, "--every", "simulate.every", default="10", metavar="K")
    p.add_argument("--linear", action="store_true", help="the linearised equation (000 eq. 7)")
    p.add_argument("--reference", action="store_true", help="compare with DOP853 at rtol 1e-13")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true", help="print a JSON record")
    out.add_argument("--csv", action="store_true", help="print CSV: tau,theta,dtheta[,theta_ref]")
    from pendulab.plots import plot_option
    plot_option(p, "theta against tau (the printed rows, every K steps) over the pivot's "
                   "y0/a, and with --reference |RK4 - DOP853| of theta")
    p.set_defaults(func=run)
    return p


def run(args):
    import io
    import sys

    from pendulab import limits
    from pendulab.commands.sweep import backend_estimate, system_spec, with_drive
    from pendulab.errors import InputError
    from pendulab.io import canonical_json
    from pendulab.numerics import sweep as S

    problems = limits.Problems()
    system = with_drive(args, system_spec(args, problems), problems)
    a = problems.parse("simulate.a_over_l", args.a_over_l, "--a-over-l")
    w = problems.parse("stability.ratio", args.w0_over_w, "--w0-over-w")
    th = problems.parse("sweep.theta_init", args.theta_init, "--theta-init")
    om = problems.parse("sweep.omega_init", args.omega_init, "--omega-init")
    periods = problems.parse("experiments.periods", args.periods, "--periods")
    steps = problems.parse("experiments.steps_per_period", args.steps_per_period,
                           "--steps-per-period")
    every = problems.parse("simulate.every", args.every, "--every")
    from pendulab.plots import requested_format
    plot_format = requested_format(args, problems)
    if not problems:
        size = None
        if args.reference:
            # the DOP853 work is estimated from Mathieu's (theta0, theta1); another drive has no
            # such pair, and its reference is bounded by the evaluation cap alone
            size = 0.0
            if S.stages(system)[1].kind == "mathieu":
                theta0, theta1 = S.mathieu_pair(system)(a, w)
                size = abs(float(theta0)) + 2 * abs(float(theta1))
        for text in limits.simulate_problems(periods, steps, every, size, backend_estimate(),
                                              rate=om):
            problems.add(text)
    problems.raise_any()
    spec = S.make_spec(system, a_over_l=[a], w0_over_w=[w], theta_init=th, omega_init=om,
                       periods=periods, steps_per_period=steps, linear=args.linear)
    from pendulab.numerics.step_check import enforce
    said = []  # an unstable step is refused here, before any integration; a coarse one is said
    enforce(spec, f"--steps-per-period {steps}", warn=said.append)
    import warnings

    import numpy as np
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        # an overflowing run is refused below in one line, without NumPy's or SciPy's warnings
        warnings.simplefilter("ignore", RuntimeWarning)
        run = S.trajectory(spec, reference=args.reference,
                           max_evaluations=limits.REFERENCE_MAX_EVALUATIONS)
    keep = slice(None, None, every)
    tau, states = run["tau"][keep], run["states"][keep]
    ref = run["reference"][keep] if args.reference else None
    if not np.all(np.isfinite(states)) or (ref is not None and not np.all(np.isfinite(ref))):
        raise InputError("the trajectory overflowed (theta is no longer finite); "
                         "use fewer periods or more steps per period")
    record = {"body": system.describe(), "a_over_l": a, "w0_over_w": w, "theta_init": th,
              "omega_init": om, "periods": periods, "steps_per_period": steps, "linear": args.linear,
              "every": every, "backend": run["backend"], "drive": system.drive,
              "mean_theta": run["mean_theta"], "mean_abs_theta": run["mean_abs_theta"],
              "max_abs_theta": run["max_abs_theta"],
              "tau": tau.tolist(), "theta": states[:, 0].tolist(), "dtheta": states[:, 1].tolist()}
    fundamental = None
    if system.drive is not None:
        # time is tau = Omega t/2 in the drive's own fundamental Omega (a period is pi in tau)
        fundamental = str(S.stages(system)[1].frequency)
        record["drive_fundamental"] = fundamental
    if said:
        record["step_warning"] = said[0]
    if args.reference:
        record["theta_reference"] = ref[:, 0].tolist()
        record["max_error_theta"] = run["max_error_theta"]
    if plot_format is not None:
        _plot(args.plot, plot_format, system, record, args.reference)
    buf = io.StringIO()
    if args.json:
        buf.write(canonical_json(record))
    elif args.csv:
        buf.write("tau,theta,dtheta" + (",theta_reference" if ref is not None else "") + "\n")
        for k in range(len(tau)):
            row = [tau[k], states[k, 0], states[k, 1]] + ([ref[k, 0]] if ref is not None else [])
            buf.write(",".join(repr(float(v)) for v in row) + "\n")
    else:
        buf.write(f"body {record['body']}, a/l = {a!r}, omega0/omega = {w!r}, theta(0) = {th!r}, "
                  f"theta'(0) = {om!r}, {periods} periods x {steps} steps ({run['backend']})\n")
        if system.drive is not None:
            note = ("" if fundamental == "omega" else
                    f"; the periods and tau = Omega t/2 are those of its fundamental "
                    f"Omega = {fundamental}")
            buf.write(f"drive y0(t) = {system.drive}{note}\n")
        buf.write(f"mean theta = {run['mean_theta']!r}, mean |theta| = {run['mean_abs_theta']!r}, "
                  f"max |theta| = {run['max_abs_theta']!r}\n")
        if args.reference:
            buf.write(f"largest |theta - theta_DOP853| = {run['max_error_theta']!r}\n")
        buf.write(f"{'tau':>12} {'theta':>22} {'dtheta/dtau':>22}\n")
        for k in range(len(tau)):
            buf.write(f"{tau[k]:12.6f} {states[k, 0]:22.15e} {states[k, 1]:22.15e}\n")
    for line in said:
        sys.stderr.write(f"pendulab: {line}\n")
    sys.stdout.write(buf.getvalue())
    return 0


#: points per drive period (pi in tau) at which --plot draws the pivot's y0/a
PIVOT_POINTS = 48


def _plot(path, fmt, system, record, reference):
    """--plot: theta of the printed rows over the pivot's y0/a (from the derived drive), and
    |theta - theta_DOP853| of those rows with --reference."""
    import numpy as np

    from pendulab import plots
    from pendulab.numerics.experiments import pivot_height
    tau = np.asarray(record["tau"])
    theta = np.asarray(record["theta"])
    fine = np.linspace(float(tau[0]), float(tau[-1]), PIVOT_POINTS * record["periods"] + 1)
    pivot = np.broadcast_to(np.asarray(pivot_height(system)(fine), dtype=float), fine.shape)
    error = np.abs(theta - np.asarray(record["theta_reference"])) if reference else None
    drive = "y₀ = a·cos(ωt)" if system.drive is None else f"y₀ = {system.drive}"
    title = (f"{record['body']}, a/l = {record['a_over_l']:g}, ω₀/ω = {record['w0_over_w']:g}, "
             f"θ(0) = {plots.minus(record['theta_init'], 'g')}, "
             f"dθ/dτ(0) = {plots.minus(record['omega_init'], 'g')}; {drive}"
             + (" (linearised)" if record["linear"] else ""))
    plots.write(plots.simulate_figure(tau, theta, fine, pivot, error, title), path, fmt)
