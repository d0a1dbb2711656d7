"""Product "animation": the pendulum of the scene as a short looping GIF.

Writes ``animation.gif``, drawn frame by frame (:mod:`pendulab.animation`, the same drawing as
``pendulab animate``) from the computed motion:

* Kapitza scenes: the pivot, the scene's body (rod or point mass) and a fading trace of its
  end, from the RK4 trajectory of the generated kernel for the options' (a/l, omega0/omega)
  and initial state, with ``frames_per_period`` frames per drive period;
* variable-length scenes: the point mass on the string of the scene's L(t), from the DOP853
  motion of the derived equation, from theta(0) = ``theta_0`` at rest to ``t_end`` seconds,
  ``frames_per_period`` frames per small swing 2 pi sqrt(L(0)/g) at the start.

Each system takes its own options (:func:`options_for`); :data:`OPTIONS` lists them all.
The file is the same byte for byte on every build (a fixed palette, no dithering, no time
stamps).  Needs matplotlib (the "figures" extra).
"""

from pendulab.limits import option as _limited

#: The options of a Kapitza scene (type, default, range and help from pendulab.limits.LIMITS).
PIVOT_OPTIONS = {
    "a_over_l": _limited("animation.a_over_l"),
    "w0_over_w": _limited("animation.w0_over_w"),
    "theta_init": _limited("animation.theta_init"),
    "omega_init": _limited("animation.omega_init"),
    "periods": _limited("animation.periods"),
    "frames_per_period": _limited("animation.frames_per_period"),
}
#: The options of a variable-length scene.
STRING_OPTIONS = {
    "L0": _limited("animation.L0"),
    "v0": _limited("animation.v0"),
    "g": _limited("animation.g"),
    "theta_0": _limited("animation.theta_0"),
    "t_end": _limited("animation.t_end"),
    "frames_per_period": _limited("animation.frames_per_period"),
    "values": (dict, {}, "numbers for the other symbols of L(t), e.g. {eps = 0.05, Omega = 6.26}"),
}
#: Every option of either system.
OPTIONS = {**PIVOT_OPTIONS, **STRING_OPTIONS}
SYSTEMS = ("kapitza", "variable-length")

#: The file written.
FILE = "animation.gif"


def options_for(system):
    """The options a scene of ``system`` may give this product."""
    return STRING_OPTIONS if system == "variable-length" else PIVOT_OPTIONS


def preload(options):
    """Heavy modules this product imports (see :func:`pendulab.build.compute_scenes`)."""
    return ("matplotlib",)


def check_options(options):
    """The frames of the options together, and the string's options (nothing computed)."""
    import math

    from pendulab import limits
    if "periods" in options:
        frames = options["periods"] * options["frames_per_period"] + 1
        limits.raise_problems([p for p in [limits.animation_frames_problem(frames)] if p])
        return
    from pendulab.products.motion import _values_problems
    problems = _values_problems(options["values"])
    if options["theta_0"] == 0:
        problems.append("theta_0: must not be 0 (theta = 0 stays at rest)")
    period = 2 * math.pi * math.sqrt(options["L0"] / options["g"])
    too_many = limits.animation_frames_problem(
        int(options["t_end"] / period * options["frames_per_period"]) + 1)
    if too_many:
        problems.append(too_many.replace("fewer periods", "a shorter t_end"))
    limits.raise_problems(problems)


def produce(ctx, options):
    import sys

    from pendulab.animation import gif_bytes, pivot_frames, rendered, string_frames
    from pendulab.errors import InputError, SceneError
    try:
        if ctx.scene.system == "variable-length":
            from pendulab.numerics.model import length_system
            from pendulab.products.motion import _numbers
            equations = ctx.get("equations")
            values = _numbers(length_system(equations), equations.system.length,
                              {**options, "values": options["values"]})
            frames = string_frames(equations, values, options["theta_0"], options["t_end"],
                                   frames_per_period=options["frames_per_period"])
        else:
            from pendulab.products.experiments import system_spec
            frames = pivot_frames(system_spec(ctx), options["a_over_l"], options["w0_over_w"],
                                  theta_init=options["theta_init"],
                                  omega_init=options["omega_init"], periods=options["periods"],
                                  frames_per_period=options["frames_per_period"],
                                  warn=lambda line: sys.stderr.write(
                                      f"pendulab: {ctx.scene.path}: products.animation: {line}\n"))
    except InputError as exc:
        raise SceneError(ctx.scene.path, "products.animation", str(exc)) from None
    return {FILE: gif_bytes(rendered(frames))}
