"""pendulab animate kapitza|variable-length [...] --out FILE.gif|FILE.mp4"""

import argparse


def add_parser(sub):
    from pendulab.commands.sweep import accept_negative_numbers, body_options
    from pendulab.commands.sweep import drive_option
    from pendulab.limits import argument
    p = sub.add_parser(
        "animate", help="the pendulum animated, written as GIF or MP4",
        description="Draw the pendulum frame by frame from its computed motion and write the "
                    "film: GIF (through Pillow, always there with matplotlib) or MP4 (through "
                    "ffmpeg, where it is on the PATH).  Needs matplotlib (the figures extra).")
    systems = p.add_subparsers(dest="system", metavar="SYSTEM")
    systems.required = True
    k = systems.add_parser(
        "kapitza", help="rigid body on a vertically driven pivot (000)",
        description="The rigid body on a vertically driven pivot (000_8cba66c4fdf94ac6.txt): "
                    "the pivot, the rod (or point mass) and a fading trace of its end, from "
                    "the RK4 trajectory of the generated kernel (the one `pendulab simulate` "
                    "prints), in the source's time tau = omega t/2.  The frames are RK4 steps, "
                    "FPP per drive period (pi in tau), played at 25 per second, so that the "
                    "fast motion at the drive's period shows on the slow swing; the command "
                    "says what one second of the file shows.  Upright and stable for "
                    "(a/l, omega0/omega) = (0.1, 0.02), the defaults; falling for (0.1, 0.2).",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(k)
    body_options(k)
    drive_option(k)
    argument(k, "--a-over-l", "animation.a_over_l", default="0.1", metavar="A")
    argument(k, "--w0-over-w", "animation.w0_over_w", default="0.02", metavar="W",
             text="omega0/omega")
    argument(k, "--theta-init", "animation.theta_init", default="0.3", metavar="X")
    argument(k, "--omega-init", "animation.omega_init", default="0", metavar="Y")
    argument(k, "--periods", "animation.periods", default="20", metavar="N")
    argument(k, "--frames-per-period", "animation.frames_per_period", default="16",
             metavar="FPP")
    _out(k)
    k.set_defaults(func=run)
    v = systems.add_parser(
        "variable-length", help="point mass on a string of length L(t) (002)",
        description="The point mass on a string of varying length (002_19b336b29bb1f03b.txt), "
                    "growing (L0 + v0*t) or shortening (L0 - v0*t), from its DOP853 motion; "
                    "FPP frames per small swing 2 pi sqrt(L(0)/g) at the start, played at 25 "
                    "per second.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    accept_negative_numbers(v)
    v.add_argument("--length", metavar="EXPR", default="L0 + v0*t",
                   help="string length L(t) in L0, v0 and t (L0 - v0*t shortens it)")
    argument(v, "--L0", "animation.L0", default="1", metavar="L0")
    argument(v, "--v0", "animation.v0", default="0.02", metavar="V0")
    argument(v, "--g", "animation.g", default="9.81", metavar="G")
    argument(v, "--theta-0", "animation.theta_0", default="0.3", metavar="X")
    argument(v, "--t-end", "animation.t_end", default="20", metavar="T")
    argument(v, "--frames-per-period", "animation.frames_per_period", default="16",
             metavar="FPP")
    _out(v)
    v.set_defaults(func=run)
    return p


def _out(p):
    p.add_argument("--out", required=True, metavar="FILE",
                   help="the film to write: FILE.gif or FILE.mp4 (MP4 needs ffmpeg)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def out_problem(text):
    """The one-line problem of the --out file name ``text``, or None (nothing is created)."""
    import os
    from pathlib import Path

    from pendulab.animation import FORMATS
    from pendulab.build import check_out_root
    from pendulab.errors import InputError
    if not text or not text.strip():
        return "--out is empty: name a file ending in .gif or .mp4"
    path = Path(text)
    if path.suffix.lower() not in FORMATS:
        return (f"--out {text}: an animation is written as {' or '.join(FORMATS)} "
                f"(by the extension), not {path.suffix or 'a name without one'}")
    if os.path.isdir(path):
        return f"--out {text} is a directory; name a file"
    try:
        check_out_root(str(path.parent) if str(path.parent) else ".", "--out's directory")
    except InputError as exc:
        return str(exc)
    return None


def run(args):
    import sys

    from pendulab import limits
    from pendulab.animation import describe, encoded, ffmpeg, rendered
    from pendulab.io import write_text_atomic

    problems = limits.Problems()
    bad_out = out_problem(args.out)
    if bad_out:
        problems.add(bad_out)
    elif args.out.lower().endswith(".mp4") and ffmpeg() is None:
        problems.add(f"--out {args.out}: MP4 needs ffmpeg on the PATH, and there is none here; "
                     "write a .gif instead")
    fpp = problems.parse("animation.frames_per_period", args.frames_per_period,
                         "--frames-per-period")
    make = _kapitza(args, problems, fpp) if args.system == "kapitza" else _string(args, problems, fpp)
    problems.raise_any()
    from pendulab.figures import pyplot
    pyplot("animation")  # the one-line refusal without matplotlib, before any work
    frames = make()
    progress = _progress(len(frames.time), args.quiet)
    try:
        images = rendered(frames, progress=progress.update if progress else None)
    finally:
        if progress:
            progress.close()
    data = encoded(images, "." + args.out.rsplit(".", 1)[1].lower())
    write_text_atomic(args.out, data)
    sys.stderr.write(f"wrote {args.out} ({len(data) / 1e6:.2f} MB): {describe(frames)}\n")
    return 0


def _progress(total, quiet):
    import sys
    if quiet or not getattr(sys.stderr, "isatty", lambda: False)():
        return None
    from tqdm import tqdm
    return tqdm(total=total, desc="frames", unit="frame", file=sys.stderr, delay=2.0,
                leave=False, dynamic_ncols=True)


def _kapitza(args, problems, fpp):
    from pendulab import limits
    from pendulab.commands.sweep import system_spec, with_drive

    system = with_drive(args, system_spec(args, problems), problems)
    a = problems.parse("animation.a_over_l", args.a_over_l, "--a-over-l")
    w = problems.parse("animation.w0_over_w", args.w0_over_w, "--w0-over-w")
    th = problems.parse("animation.theta_init", args.theta_init, "--theta-init")
    om = problems.parse("animation.omega_init", args.omega_init, "--omega-init")
    periods = problems.parse("animation.periods", args.periods, "--periods")
    if periods is not None and fpp is not None:
        too_many = limits.animation_frames_problem(periods * fpp + 1)
        if too_many:
            problems.add(too_many)

    def make():
        import sys

        from pendulab.animation import pivot_frames
        # its RK4 step is refused if unstable before any frame is drawn
        return pivot_frames(system, a, w, theta_init=th, omega_init=om, periods=periods,
                            frames_per_period=fpp, step_label=f"--frames-per-period {fpp}",
                            warn=lambda line: sys.stderr.write(f"pendulab: {line}\n"))
    return make


def _string(args, problems, fpp):
    import math

    from pendulab import limits
    from pendulab.exprs import parse

    length = problems.call(parse, args.length, prefix="--length: ")
    values = {}
    for flag, name in (("--L0", "L0"), ("--v0", "v0"), ("--g", "g")):
        values[name] = problems.parse(f"animation.{name}", getattr(args, name), flag)
    th = problems.parse("animation.theta_0", args.theta_0, "--theta-0")
    if th == 0:
        problems.add("--theta-0 must not be 0 (theta = 0 stays at rest)")
    t_end = problems.parse("animation.t_end", args.t_end, "--t-end")
    if None not in (t_end, fpp, values["L0"], values["g"]):
        period = 2 * math.pi * math.sqrt(values["L0"] / values["g"])
        too_many = limits.animation_frames_problem(int(t_end / period * fpp) + 1)
        if too_many:
            problems.add(too_many.replace("fewer periods", "a shorter --t-end"))

    def make():
        from pendulab.animation import string_frames
        from pendulab.equations import derive
        from pendulab.errors import InputError, ParameterError
        from pendulab.systems import VariableLength
        try:
            system = VariableLength(length=length)
        except ParameterError as exc:
            raise InputError(f"--length: {exc}") from None
        return string_frames(derive(system), values, th, t_end, frames_per_period=fpp)
    return make
