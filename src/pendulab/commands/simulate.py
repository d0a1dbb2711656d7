"""pendulab simulate [--body rod|point | --inertia-ratio R] --a-over-l A --w0-over-w W
   --theta-init X --omega-init Y [--periods P] [--steps-per-period S] [--every K] [--linear]
   [--reference] [--json | --csv]"""

import argparse


def add_parser(sub):
    from pendulab.commands.sweep import accept_negative_numbers, body_options
    p = sub.add_parser(
        "simulate", help="one trajectory of the driven pivot in tau (RK4)",
        description="Integrate the full equation of motion in the source's time tau = omega t/2 "
                    "(000 sec. 4) with fixed-step RK4 from theta(0), dtheta/dtau(0), for "
                    "a/l and omega0/omega; print tau, theta, dtheta/dtau every K steps and the "
                    "run's statistics (signed mean of theta, mean |theta|, max |theta|).  "
                    "--reference adds SciPy's DOP853 (rtol 1e-13) at the same times and the "
                    "largest difference.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(p)
    body_options(p)
    p.add_argument("--a-over-l", required=True, metavar="A", help="pivot amplitude over l, a/l")
    p.add_argument("--w0-over-w", required=True, metavar="W", help="omega0/omega")
    p.add_argument("--theta-init", default="0.06", metavar="X", help="theta(0) in rad")
    p.add_argument("--omega-init", default="0.01", metavar="Y", help="dtheta/dtau at tau = 0")
    p.add_argument("--periods", default="10", metavar="P", help="drive periods (pi in tau each)")
    p.add_argument("--steps-per-period", default="100", metavar="S", help="RK4 steps per drive period")
    p.add_argument("--every", default="10", metavar="K", help="print every K-th step")
    p.add_argument("--linear", action="store_true", help="the linearised equation (000 eq. 7)")
    p.add_argument("--reference", action="store_true", help="compare with DOP853 at rtol 1e-13")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true", help="print a JSON record")
    out.add_argument("--csv", action="store_true", help="print CSV: tau,theta,dtheta[,theta_ref]")
    p.set_defaults(func=run)
    return p


def run(args):
    import io
    import sys

    import numpy as np

    from pendulab.commands.sweep import number, system_spec, whole
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
    a = collect(number, args.a_over_l, "--a-over-l")
    w = collect(number, args.w0_over_w, "--w0-over-w")
    th = collect(number, args.theta_init, "--theta-init")
    om = collect(number, args.omega_init, "--omega-init")
    periods = collect(whole, args.periods, "--periods", 1)
    steps = collect(whole, args.steps_per_period, "--steps-per-period", 1)
    every = collect(whole, args.every, "--every", 1)
    for name, v in (("--a-over-l", a), ("--w0-over-w", w)):
        if v is not None and v < 0:
            problems.append(f"{name} must be >= 0, got {v!r}")
    if periods is not None and steps is not None and periods * steps > 10**7:
        problems.append(f"--periods x --steps-per-period must be at most 1e7, got {periods * steps}")
    elif (args.reference and periods is not None and steps is not None
          and periods * steps > 10**6):
        # DOP853 at rtol 1e-13 takes about 10 s per 1e5 periods of the drive
        problems.append("with --reference, --periods x --steps-per-period must be at most 1e6 "
                        f"(DOP853 at rtol 1e-13 is slow over long runs), got {periods * steps}")
    if problems:
        raise InputError("; ".join(problems))
    spec = S.make_spec(system, a_over_l=[a], w0_over_w=[w], theta_init=th, omega_init=om,
                       periods=periods, steps_per_period=steps, linear=args.linear)
    run = S.trajectory(spec, reference=args.reference)
    keep = slice(None, None, every)
    tau, states = run["tau"][keep], run["states"][keep]
    ref = run["reference"][keep] if args.reference else None
    record = {"body": system.describe(), "a_over_l": a, "w0_over_w": w, "theta_init": th,
              "omega_init": om, "periods": periods, "steps_per_period": steps, "linear": args.linear,
              "every": every, "backend": run["backend"],
              "mean_theta": run["mean_theta"], "mean_abs_theta": run["mean_abs_theta"],
              "max_abs_theta": run["max_abs_theta"],
              "tau": tau.tolist(), "theta": states[:, 0].tolist(), "dtheta": states[:, 1].tolist()}
    if args.reference:
        record["theta_reference"] = ref[:, 0].tolist()
        record["max_error_theta"] = run["max_error_theta"]
    if not all(np.isfinite(states).ravel()):
        raise InputError("the trajectory overflowed (theta is no longer finite); "
                         "use fewer periods or more steps per period")
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
        buf.write(f"mean theta = {run['mean_theta']!r}, mean |theta| = {run['mean_abs_theta']!r}, "
                  f"max |theta| = {run['max_abs_theta']!r}\n")
        if args.reference:
            buf.write(f"largest |theta - theta_DOP853| = {run['max_error_theta']!r}\n")
        buf.write(f"{'tau':>12} {'theta':>22} {'dtheta/dtau':>22}\n")
        for k in range(len(tau)):
            buf.write(f"{tau[k]:12.6f} {states[k, 0]:22.15e} {states[k, 1]:22.15e}\n")
    sys.stdout.write(buf.getvalue())
    return 0
