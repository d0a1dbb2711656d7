"""The two pendulums animated: frames from the computed motion, drawn and written as GIF or MP4.

Every position drawn is read from the derivation: the driven pivot's pivot and
centre of mass are :func:`pendulab.numerics.model.pivot_geometry` (the
coordinates its Lagrangian is built from, 000 sec. 2.1, in the source's time
tau = Omega t/2, over l), evaluated on the RK4 trajectory of the generated
kernel (:func:`pendulab.numerics.sweep.trajectory`, the one ``pendulab
simulate`` prints); the string's mass is
:func:`pendulab.numerics.model.length_geometry` (002's position with the
scene's L(t)) on the DOP853 motion of
:func:`pendulab.analyses.variable_length_motion.integrate`.

The frame rate follows the motion.  The driven pivot is drawn
``frames_per_period`` times per drive period (pi in tau): the fast motion,
the jiggle at the drive's period, then shows as a small wobble on the slow
swing, as in 000's Fig. 2.  The string is drawn ``frames_per_period`` times
per small-swing period 2 pi sqrt(L(0)/g) at the start (the period shortens
or lengthens as the string does; the frames keep their spacing in t).  The
files play at :data:`FPS` frames a second; :func:`describe` says what one
second of the file shows.

GIF goes through Pillow (matplotlib's own dependency): every frame is drawn
by matplotlib's Agg renderer and mapped to one fixed palette without
dithering, so the file is the same byte for byte on every run.  MP4 needs
``ffmpeg`` on the PATH (H.264, yuv420p), and says so in one line otherwise.
"""

import math
import os
import shutil
import subprocess
from dataclasses import dataclass

from pendulab.errors import InputError

#: Frames per second of the written files.
FPS = 25

#: The written formats, by file extension.
FORMATS = {".gif": "GIF", ".mp4": "MP4"}

#: Size of the drawing in pixels (square).
PIXELS = 320

#: The trace behind the mass covers this many drive periods (swing periods for the string).
TRACE_PERIODS = 1.5


@dataclass(frozen=True)
class Frames:
    """The motion at the frames' times: everything the drawing needs, nothing drawn.

    ``time`` (tau for the driven pivot, t in seconds for the string),
    ``theta``, ``pivot`` and ``mass`` ((n, 2) arrays, y up; over l for the
    driven pivot, in metres for the string); ``body`` is "rod", "point" or
    "string" (the rod is drawn from the pivot through its centre of mass to
    twice that distance, the end of a uniform rod); ``frames_per_period``,
    ``period`` (of the drive, or the first small swing, in ``time``) and
    ``title`` (mathtext) describe it.
    """

    time: object
    theta: object
    pivot: object
    mass: object
    body: str
    frames_per_period: int
    period: float
    title: str
    upright: bool = True


def describe(frames):
    """One line: how many frames, and what one second of the file shows."""
    n = len(frames.time)
    unit = "drive period" if frames.body != "string" else "swing period at the start"
    seconds = frames.frames_per_period / FPS
    return (f"{n} frames, {frames.frames_per_period} per {unit}, at {FPS} frames per second: "
            f"one {unit} lasts {seconds:g} s of the file ({n / FPS:.1f} s in all)")


def _lambdified(geometry, exprs):
    import sympy as sp

    from pendulab.numerics.model import THETA
    return sp.lambdify((geometry.time, THETA, *geometry.params), exprs, modules="numpy")


def _points(fn, time, theta, params):
    import numpy as np
    x, y = fn(time, theta, *params)
    return np.column_stack([np.broadcast_to(np.asarray(x, float), time.shape),
                            np.broadcast_to(np.asarray(y, float), time.shape)])


def pivot_frames(system, a_over_l, w0_over_w, theta_init=0.06, omega_init=0.01, periods=20,
                 frames_per_period=16, steps_per_frame=None, step_label=None, warn=None):
    """:class:`Frames` of the driven pivot ``system`` (a :class:`pendulab.numerics.sweep.SystemSpec`).

    The RK4 run takes ``steps_per_frame`` steps between frames (default: the
    fewest that give at least 100 steps per drive period, the simulate
    command's default), so that the frames are steps of the integration and
    nothing is interpolated.  Its step is checked first
    (:func:`pendulab.numerics.step_check.enforce`): an unstable one is refused naming
    ``step_label`` (the option that chose it), a coarse one is passed to ``warn``.
    """
    import numpy as np

    from pendulab.numerics import sweep as S
    from pendulab.numerics.model import pivot_geometry

    from pendulab import limits
    too_many = limits.animation_frames_problem(periods * frames_per_period + 1)
    if too_many:
        raise InputError(too_many)
    if steps_per_frame is None:
        steps_per_frame = -(-100 // frames_per_period)
    spec = S.make_spec(system, a_over_l=[a_over_l], w0_over_w=[w0_over_w],
                       theta_init=theta_init, omega_init=omega_init, periods=periods,
                       steps_per_period=frames_per_period * steps_per_frame)
    from pendulab.numerics.step_check import enforce
    label = step_label or f"frames_per_period = {frames_per_period}"
    enforce(spec, f"{label} ({spec.steps_per_period} RK4 steps per period)", warn=warn)
    fos = S.first_order_system(system)
    with np.errstate(all="ignore"):
        run = S.trajectory(spec)
    keep = slice(None, None, steps_per_frame)
    tau, states = run["tau"][keep], run["states"][keep]
    if not np.all(np.isfinite(states)):
        raise InputError("the trajectory overflowed (theta is no longer finite); use fewer "
                         "periods")
    geometry = pivot_geometry(*S.stages(system))
    _, params = S.cell_arrays(spec, np.arange(1))
    by_name = dict(zip((s.name for s in fos.params), params[0]))
    missing = [s.name for s in geometry.params if s.name not in by_name]
    if missing:
        raise InputError(f"the pivot's position needs {', '.join(missing)}, which the motion "
                         "does not set")
    values = [by_name[s.name] for s in geometry.params]
    theta = states[:, 0]
    pivot = _points(_lambdified(geometry, geometry.pivot), tau, theta, values)
    mass = _points(_lambdified(geometry, geometry.mass), tau, theta, values)
    body = "point" if system.body == "point" else "rod"
    title = (rf"$a/l = {_tex(a_over_l)}$, $\omega_0/\omega = {_tex(w0_over_w)}$, "
             rf"$\theta(0) = {_tex(theta_init)}$")
    period = float(fos.period) if fos.period is not None else math.pi
    return Frames(tau, theta, pivot, mass, body, frames_per_period, period, title,
                  upright=system.angle == "up")


def string_frames(equations, values, theta_0, t_end, frames_per_period=16):
    """:class:`Frames` of the variable-length pendulum of ``equations`` with the numbers ``values``
    ({"g": ..., "L0": ..., "v0": ..., ...}), from theta(0) = ``theta_0`` at rest to ``t_end``."""
    import numpy as np

    from pendulab.analyses import variable_length_motion as vm
    from pendulab.numerics.model import length_geometry, length_system

    fos = length_system(equations)
    length = equations.system.length
    lfun, _ = vm.length_function(length, values)
    l_start = float(lfun(0.0))
    g = float(values.get("g", 9.81))
    period = 2 * math.pi * math.sqrt(l_start / g)
    n = int(math.floor(t_end / period * frames_per_period)) + 1
    from pendulab import limits
    too_many = limits.animation_frames_problem(n)
    if too_many:
        raise InputError(too_many.replace("fewer periods", "a shorter t_end"))
    if n < 2:
        raise InputError(f"t_end = {t_end:g} s is shorter than one frame ({period / frames_per_period:.3g} s)")
    times = np.arange(n) * (period / frames_per_period)
    # before anything is integrated: a string that reaches zero, a pole or L(0)/10^6 within
    # t_end, and more oscillations than DOP853 integrates in about a minute (the swings,
    # counted along L(t) as it changes, and a periodic L(t)'s own periods)
    vm.length_check(length, values, t_end, t_end=t_end)
    swings = _oscillations(lfun, g, t_end)
    if fos.period is not None:
        swings = max(swings, t_end / float(vm.substitute(fos.period, values)))
    if not swings <= limits.MOTION_MAX_PERIODS:
        raise InputError(f"t_end = {t_end:g} s is about {swings:.3g} oscillations of the string "
                         f"(of its swing sqrt(g/L(t)), or of L(t) itself); at most "
                         f"{limits.MOTION_MAX_PERIODS}: ask for a shorter t_end")
    traj = vm.integrate(fos, length, values, t_end, theta_0, t_eval=times)
    geometry = length_geometry(equations)
    missing = [s.name for s in geometry.params if s.name not in values]
    if missing:
        raise InputError(f"L(t) = {length} needs numbers for {', '.join(missing)}")
    params = [float(values[s.name]) for s in geometry.params]
    t = np.asarray(traj.t, float)
    keep = np.isin(t, times)
    t, theta = t[keep], np.asarray(traj.theta, float)[keep]
    mass = _points(_lambdified(geometry, geometry.mass), t, theta, params)
    pivot = np.zeros_like(mass)
    import sympy as sp
    title = rf"$L(t) = {sp.latex(length)}$, $\theta(0) = {_tex(theta_0)}$"
    return Frames(t, theta, pivot, mass, "string", frames_per_period, period, title)


def _oscillations(lfun, g, t_end, points=4001):
    """Swings of a string of length ``lfun(t)`` up to ``t_end``: the integral of
    sqrt(g/L(t))/(2 pi) by the trapezoid rule on ``points`` times (L > 0 there: checked
    before by the length check)."""
    step = t_end / (points - 1)
    rate = [math.sqrt(g / float(lfun(k * step))) for k in range(points)]
    return step * (sum(rate) - (rate[0] + rate[-1]) / 2) / (2 * math.pi)


def _tex(x):
    text = f"{float(x):.4g}"
    if "e" in text:
        mant, exp = text.split("e")
        return rf"{mant}\times 10^{{{int(exp)}}}"
    return text


# ---------------------------------------------------------------------------
# drawing
# ---------------------------------------------------------------------------

#: The fixed palette: white to each of these colours in PALETTE_STEPS steps (the trace fades
#: through them), and the colours themselves.
_INKS = ((0, 0, 0), (31, 119, 180), (214, 39, 40), (127, 127, 127))
PALETTE_STEPS = 24


def _palette():
    from PIL import Image
    colours = []
    for ink in _INKS:
        for k in range(PALETTE_STEPS):
            f = k / (PALETTE_STEPS - 1)
            colours.append(tuple(round(255 + (c - 255) * f) for c in ink))
    flat = [v for c in colours for v in c]
    flat += [255] * (768 - len(flat))
    img = Image.new("P", (1, 1))
    img.putpalette(flat)
    return img


def _extent(frames):
    import numpy as np
    reach = 2.0 if frames.body == "rod" else 1.0
    if frames.body == "string":
        reach = float(np.max(np.hypot(*(frames.mass - frames.pivot).T)))
    ys = frames.pivot[:, 1]
    half = reach * 1.08 + 0.5 * float(ys.max() - ys.min())
    centre = 0.5 * float(ys.max() + ys.min())
    return half, centre


def rendered(frames, progress=None):
    """The frames drawn: a list of RGB PIL images, PIXELS x PIXELS."""
    import numpy as np
    from PIL import Image

    from pendulab.figures import pyplot
    _, plt = pyplot("animation")
    from matplotlib.collections import LineCollection

    half, centre = _extent(frames)
    dpi = 80
    fig = plt.figure(figsize=(PIXELS / dpi, PIXELS / dpi), dpi=dpi)
    try:
        ax = fig.add_axes((0.02, 0.02, 0.96, 0.84))
        ax.set_xlim(-half, half)
        ax.set_ylim(centre - half, centre + half)
        ax.set_aspect("equal")
        ax.set_axis_off()
        fig.text(0.5, 0.955, frames.title, ha="center", va="center", fontsize=7.5)
        clock = fig.text(0.5, 0.885, "", ha="center", va="center", fontsize=7.5, color="0.35")
        blue, red, grey = (np.array(c) / 255 for c in _INKS[1:])
        if frames.body != "string":
            ys = frames.pivot[:, 1]
            ax.plot([0, 0], [ys.min(), ys.max()], color=grey, lw=4, alpha=0.35,
                    solid_capstyle="round")
            up = 1 if frames.upright else -1
            reach = 2.0 if frames.body == "rod" else 1.0
            ax.plot([0, 0], [centre, centre + up * reach * 1.05], color=grey, lw=0.6,
                    ls=(0, (3, 3)))
        else:
            ax.plot([-0.3 * half, 0.3 * half], [0, 0], color="black", lw=1.5)
        trace = LineCollection([], linewidths=1.2)
        ax.add_collection(trace)
        (line,) = ax.plot([], [], color="black", lw=3.0 if frames.body == "rod" else 1.0,
                          solid_capstyle="round")
        (bob,) = ax.plot([], [], "o", color=blue, ms=7 if frames.body != "rod" else 0)
        (pin,) = ax.plot([], [], "s" if frames.body != "string" else "o", color=red, ms=4)
        end = frames.pivot + (2.0 if frames.body == "rod" else 1.0) * (frames.mass - frames.pivot)
        n_trace = max(2, int(TRACE_PERIODS * frames.frames_per_period))
        dynamic = (trace, line, bob, pin, clock)
        for artist in dynamic:
            artist.set_animated(True)
        fig.canvas.draw()
        background = fig.canvas.copy_from_bbox(fig.bbox)
        images = []
        unit = "\u03c4" if frames.body != "string" else "t"
        for k in range(len(frames.time)):
            lo = max(0, k - n_trace)
            seg = np.stack([end[lo:k], end[lo + 1:k + 1]], axis=1) if k > lo else np.empty((0, 2, 2))
            trace.set_segments(seg)
            if len(seg):
                fade = np.linspace(0.0, 0.8, len(seg) + 1)[1:]
                trace.set_colors([(*blue, a) for a in fade])
            line.set_data([frames.pivot[k, 0], end[k, 0]], [frames.pivot[k, 1], end[k, 1]])
            bob.set_data([end[k, 0]], [end[k, 1]])
            pin.set_data([frames.pivot[k, 0]], [frames.pivot[k, 1]])
            # plain text: mathtext would be parsed again for every frame
            clock.set_text(f"{unit} = {frames.time[k]:.2f}" + (" s" if frames.body == "string" else ""))
            fig.canvas.restore_region(background)
            for artist in dynamic:
                fig.draw_artist(artist)
            rgba = np.asarray(fig.canvas.buffer_rgba())
            images.append(Image.fromarray(np.ascontiguousarray(rgba[:, :, :3])))
            if progress is not None:
                progress(1)
        return images
    finally:
        plt.close(fig)


def gif_bytes(images):
    """The images as one looping GIF (fixed palette, no dithering: the same bytes every run)."""
    import io

    from PIL import Image
    pal = _palette()
    frames = [im.quantize(palette=pal, dither=Image.Dither.NONE) for im in images]
    buf = io.BytesIO()
    frames[0].save(buf, format="GIF", save_all=True, append_images=frames[1:],
                   duration=round(1000 / FPS), loop=0, optimize=False)
    return buf.getvalue()


def ffmpeg():
    """The ffmpeg executable on the PATH, or None."""
    return shutil.which("ffmpeg")


def mp4_bytes(images):
    """The images as H.264 MP4 through ffmpeg (InputError in one line where there is none)."""
    import tempfile

    exe = ffmpeg()
    if exe is None:
        raise InputError("MP4 needs ffmpeg on the PATH, and there is none here; write a .gif "
                         "instead (Pillow, no ffmpeg needed)")
    w, h = images[0].size
    with tempfile.TemporaryDirectory(prefix="pendulab-mp4-") as tmp:
        out = os.path.join(tmp, "out.mp4")
        cmd = [exe, "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{w}x{h}", "-r", str(FPS), "-i", "-", "-c:v", "libx264",
               "-pix_fmt", "yuv420p", "-bitexact", "-map_metadata", "-1", out]
        data = b"".join(im.tobytes() for im in images)
        from pendulab.procs import parent_death_signal
        proc = subprocess.run(cmd, input=data, capture_output=True,
                              preexec_fn=parent_death_signal)
        if proc.returncode != 0 or not os.path.exists(out):
            why = proc.stderr.decode(errors="replace").strip().splitlines()
            raise InputError("ffmpeg could not write the MP4" + (f": {why[-1]}" if why else ""))
        with open(out, "rb") as f:
            return f.read()


def encoded(images, suffix):
    """The images in the format of ``suffix`` (".gif" or ".mp4")."""
    if suffix == ".gif":
        return gif_bytes(images)
    if suffix == ".mp4":
        return mp4_bytes(images)
    raise InputError(f"an animation is written as {' or '.join(FORMATS)}, not {suffix or 'no extension'}")
