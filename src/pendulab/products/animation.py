"""Product "animation": the driven pivot's pendulum as a short looping GIF.

Writes ``animation.gif``: the pivot, the scene's body (rod or point mass) and a
fading trace of its end, drawn frame by frame from the RK4 trajectory of the
generated kernel for the options' (a/l, omega0/omega) and initial state, with
``frames_per_period`` frames per drive period (:mod:`pendulab.animation`, the
same drawing as ``pendulab animate kapitza``).  The file is the same byte for
byte on every build (a fixed palette, no dithering, no time stamps).  Needs
matplotlib (the "figures" extra).  The variable-length string is animated by
``pendulab animate variable-length`` only.
"""

from pendulab.limits import option as _limited

#: Type, default, range and help from pendulab.limits.LIMITS.
OPTIONS = {
    "a_over_l": _limited("animation.a_over_l"),
    "w0_over_w": _limited("animation.w0_over_w"),
    "theta_init": _limited("animation.theta_init"),
    "omega_init": _limited("animation.omega_init"),
    "periods": _limited("animation.periods"),
    "frames_per_period": _limited("animation.frames_per_period"),
}
SYSTEMS = ("kapitza",)

#: The file written.
FILE = "animation.gif"


def preload(options):
    """Heavy modules this product imports (see :func:`pendulab.build.compute_scenes`)."""
    return ("matplotlib",)


def check_options(options):
    """The frames of the options together (nothing computed)."""
    from pendulab import limits
    limits.raise_problems([p for p in [limits.animation_frames_problem(
        options["periods"] * options["frames_per_period"] + 1)] if p])


def produce(ctx, options):
    import sys

    from pendulab.animation import gif_bytes, pivot_frames, rendered
    from pendulab.errors import InputError, SceneError
    from pendulab.products.experiments import system_spec
    from pendulab.numerics import sweep as S
    from pendulab.numerics.step_check import enforce
    try:
        fpp = options["frames_per_period"]
        steps = fpp * -(-100 // fpp)  # pivot_frames' default RK4 steps per drive period
        enforce(S.make_spec(system_spec(ctx), a_over_l=[options["a_over_l"]],
                            w0_over_w=[options["w0_over_w"]], periods=options["periods"],
                            steps_per_period=steps),
                f"frames_per_period = {fpp} ({steps} RK4 steps per period)",
                warn=lambda line: sys.stderr.write(f"pendulab: {ctx.scene.path}: "
                                                   f"products.animation: {line}\n"))
        frames = pivot_frames(system_spec(ctx), options["a_over_l"], options["w0_over_w"],
                              theta_init=options["theta_init"], omega_init=options["omega_init"],
                              periods=options["periods"],
                              frames_per_period=options["frames_per_period"])
    except InputError as exc:
        raise SceneError(ctx.scene.path, "products.animation", str(exc)) from None
    return {FILE: gif_bytes(rendered(frames))}
