"""The drawing that the products' figures and the commands' ``--plot FILE`` share.

One function per kind of mark, each drawing on a matplotlib ``Axes`` it is given, so that a
figure of a product (:mod:`pendulab.products.experiments`) and a plot from a command look
alike:

* :func:`draw_region` - the Floquet-stable region shaded, its edge dashed (the exact limits);
* :func:`draw_cells` - the stable cells of a map as open circles (as in 000's Figs. 3-4);
* :func:`draw_limits` - lower and upper limits of a/l against omega0/omega;
* :func:`draw_exact_entry` - the legend's entry of the region's edge;
* :func:`draw_map_panel` - one panel of a stability map: the four above together;
* :func:`draw_theta`, :func:`draw_pivot`, :func:`draw_error`, :func:`log_ticks` - a
  trajectory, the pivot's motion, an error on a logarithmic axis with 10⁻² labels.

The commands' figures (:func:`sweep_figure`, :func:`simulate_figure`,
:func:`stability_figure`, :func:`zeros_figure`, :func:`margins_figure`) are built from them;
:func:`check_target` checks the file name of ``--plot`` (and that matplotlib is there)
before anything is computed, and :func:`write` writes the file in one rename.

This module imports matplotlib only inside its functions (the CLI's start-up stays light).
"""

import os

from pendulab.errors import InputError

#: file extension -> format of ``--plot``
FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}
#: resolution of a PNG written by ``--plot`` (that of the products' PNG figures)
DPI = 150

#: Panel titles of the maps, plain Unicode text (DejaVu Sans has the glyphs; no mathtext parse per figure).
LABELS = {"mean": "|⟨θ⟩| < 0.1", "mean-abs": "⟨|θ|⟩ < 0.1", "bounded": "|θ| < π/2", "floquet": "Floquet (linear)"}
#: The same titles typeset as mathematics (``labels = "math"`` of the experiments product).
MATH_LABELS = {"mean": r"$|\langle\theta\rangle| < 0.1$", "mean-abs": r"$\langle|\theta|\rangle < 0.1$",
               "bounded": r"$|\theta| < \pi/2$", "floquet": "Floquet (linear)"}
#: Axis and legend labels as plain Unicode text ...
TEXT = {"a/l": "a/l", "w0/w": "ω₀/ω", "theta(tau)": "θ(τ)", "tau": "τ", "theta": "θ",
        "error": "|series − RK4|", "pivot": "pivot y₀/a", "theta0": "θ₀", "theta1": "θ₁",
        "theta(0)": "θ(0)", "dtheta(0)": "dθ/dτ(0)", "math": False}
#: ... and typeset as mathematics (Computer Modern, as the lecture notes include them).
MATH = {"a/l": "$a/l$", "w0/w": r"$\omega_0/\omega$", "theta(tau)": r"$\theta(\tau)$", "tau": r"$\tau$",
        "theta": r"$\theta$", "error": r"$|$series $-$ RK4$|$", "pivot": r"pivot $y_0/a$",
        "theta0": r"$\theta_0$", "theta1": r"$\theta_1$", "theta(0)": r"$\theta(0)$",
        "dtheta(0)": r"$\theta'(0)$", "math": True}

#: rc settings of every figure (the products' and the commands'). ps.fonttype too: matplotlib's
#: PDF backend sizes its font subsets by it, and at its default (3) puts the characters above
#: U+00FF (θ, ω, −) in a second copy of DejaVu Sans in every PDF
RC = {"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 8, "savefig.dpi": 150,
      "pdf.fonttype": 42, "ps.fonttype": 42, "path.simplify": False}
#: besides, for an SVG of a command: the same ids on every run, text as paths (no font needed)
SVG_RC = {"svg.hashsalt": "pendulab", "svg.fonttype": "path"}


def minus(x, spec):
    """``format(x, spec)`` with a true minus sign (U+2212), as mathtext writes it."""
    return format(x, spec).replace("-", "\u2212")


# ---------------------------------------------------------------------------
# the marks
# ---------------------------------------------------------------------------

def draw_region(ax, shaded, edge):
    """The Floquet-stable region (a matplotlib Path) shaded light grey and its edge (the exact
    limits) dashed in C0, as contourf (no antialiasing, below the lines) and contour would
    draw them.  add_artist, not add_patch, which walks every segment for the data limits."""
    from matplotlib.patches import PathPatch
    ax.add_artist(PathPatch(shaded, facecolor="0.85", edgecolor="none", linewidth=0,
                            antialiased=False, zorder=1))
    ax.add_artist(PathPatch(edge, fill=False, edgecolor="C0", linestyle="--", linewidth=1.0,
                            zorder=2))


def draw_cells(ax, a, w, stable, ms):
    """The stable cells of a map (``stable``: bool array, rows omega0/omega = ``w``, columns
    a/l = ``a``) as open black circles of size ``ms``."""
    import numpy as np
    ii, jj = np.nonzero(stable)
    return ax.plot(a[jj], w[ii], "o", mfc="none", mec="k", ms=ms, mew=0.4, ls="none")


def cell_size(n):
    """The circles' size for an n x n map: smaller as the cells get denser."""
    return max(0.6, min(4.0, 220.0 / max(n, 1)))


def draw_limits(ax, w, lower, upper, label, color="C3", styles=("-", "-"), labels=None, lw=1.0):
    """Lower and upper limits of a/l (x) against omega0/omega ``w`` (y), NaN where there is
    none.  ``label`` goes on the lower curve alone, or ``labels`` = (lower's, upper's) tells
    the two apart; ``styles`` are their line styles."""
    lo_label, up_label = labels if labels is not None else (label, None)
    colors = (color, color) if isinstance(color, str) else color
    for values, style, text, color in ((lower, styles[0], lo_label, colors[0]),
                                       (upper, styles[1], up_label, colors[1])):
        if text is None:
            ax.plot(values, w, style, color=color, lw=lw)
        else:
            ax.plot(values, w, style, color=color, lw=lw, label=text)


def draw_exact_entry(ax):
    """The legend entry of :func:`draw_region`'s dashed edge: "exact (Floquet)"."""
    from matplotlib.lines import Line2D
    ax.add_line(Line2D([], [], ls="--", color="C0", lw=1.0, label="exact (Floquet)"))


def draw_map_panel(ax, a, w, stable, limits, region, ms):
    """One panel of a stability map on [0, 1] x [0, 1]: the Floquet region and its edge
    (``region`` = (shaded, edge) paths), the stable cells, eq. 28's limits when ``limits``
    has them (``limits["curves"]["eq28"]`` on ``limits["w0_over_w"]``)."""
    shaded, edge = region
    draw_region(ax, shaded, edge)
    draw_cells(ax, a, w, stable, ms)
    if "eq28" in limits["curves"]:
        lo, up = limits["curves"]["eq28"]
        draw_limits(ax, limits["w0_over_w"], lo, up, "eq. 28")
    draw_exact_entry(ax)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)


def draw_theta(ax, tau, theta, label, lw=0.9):
    """theta against tau, a black line."""
    return ax.plot(tau, theta, "-", color="k", lw=lw, label=label)


def draw_pivot(ax, tau, pivot, label, style=":", lw=0.6):
    """The pivot's height y0/a against tau, a grey line."""
    return ax.plot(tau, pivot, style, color="0.3", lw=lw, label=label)


def draw_error(ax, tau, error, style, color, label, lw=0.8):
    """An error (>= 0) against tau on a logarithmic axis; 1e-18 added so that a zero shows."""
    return ax.semilogy(tau, error + 1e-18, style, color=color, lw=lw, label=label)


def log_ticks(ax):
    """10⁻² tick labels on ``ax``'s logarithmic y axis, as text: matplotlib's own labels are
    mathtext, parsed per label and dpi."""
    import matplotlib.ticker

    from pendulab.figures import power_of_ten
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(power_of_ten))
    ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())


# ---------------------------------------------------------------------------
# --plot FILE of the commands
# ---------------------------------------------------------------------------

def plot_option(p, what):
    """--plot FILE on the parser ``p`` of a command; ``what`` says what the figure shows."""
    p.add_argument("--plot", metavar="FILE",
                   help="also write a figure to FILE, PNG, PDF or SVG by its extension (needs "
                        f"matplotlib, the 'figures' extra): {what}")


def requested_format(args, problems):
    """The format of a command's --plot ("png", "pdf", "svg"); None without --plot, or when
    :func:`check_target` refuses it (the refusal is recorded in ``problems``)."""
    if getattr(args, "plot", None) is None:
        return None
    return problems.call(check_target, args.plot)


def check_target(path, option="--plot"):
    """The format of ``path`` ("png", "pdf" or "svg"), or a one-line InputError: a name
    without one of those extensions, a directory, a folder that does not exist or cannot be
    written, or no matplotlib.  Writes nothing; call it before computing."""
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise InputError(f"{option} {path}: the file name must end in .png, .pdf or .svg")
    if os.path.isdir(path):
        raise InputError(f"{option} {path}: is a directory")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(f"{option} {path}: no directory {folder}")
    if not os.access(folder, os.W_OK | os.X_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise InputError(f"{option} {path}: cannot write there (permission denied)")
    if not have_matplotlib():
        raise InputError(f"{option} needs matplotlib: pip install 'pendulab[figures]'")
    return FORMATS[ext]


def have_matplotlib():
    """Whether matplotlib can be imported, found without importing it (a usage error with
    --plot stays as quick as one without)."""
    import importlib.util
    import sys
    if "matplotlib" in sys.modules:
        return sys.modules["matplotlib"] is not None
    try:
        return importlib.util.find_spec("matplotlib") is not None
    except (ImportError, ValueError):
        return False


def new_figure(width, height, nrow=1, ncol=1, **kw):
    """(figure, axes array) outside pyplot (nothing kept in a global figure list)."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=(width, height))
    return fig, fig.subplots(nrow, ncol, squeeze=False, **kw)


def figure_bytes(fig, fmt):
    """The bytes of ``fig`` as ``fmt``: no dates or versions inside (the same bytes each run)."""
    import io

    import matplotlib

    from pendulab import figures
    if fmt == "png":
        return figures.png(fig, DPI)
    if fmt == "pdf":
        return figures.save(fig, DPI)[".pdf"]
    buffer = io.BytesIO()
    with matplotlib.rc_context({**SVG_RC, **figures.SAVEFIG_RC}):
        fig.savefig(buffer, format="svg", metadata={"Date": None, "Creator": None})
    return buffer.getvalue()


def write(fig, path, fmt):
    """``fig`` drawn into ``path`` as ``fmt``, through a temporary file and one rename."""
    from pendulab.io import write_text_atomic
    try:
        write_text_atomic(path, figure_bytes(fig, fmt))
    except OSError as exc:
        raise InputError(f"--plot {path}: {exc.strerror or exc}") from None


def _rc():
    import matplotlib
    return matplotlib.rc_context(RC)


def _margins(fig, **inches):
    from pendulab.figures import margins
    margins(fig, **inches)


def sweep_figure(a, w, stable, criterion, count, limits, region, title, run=""):
    """The map of ``pendulab sweep``: one panel as the experiments product draws each of its
    criteria (:func:`draw_map_panel`), the count (and ``run``, what was integrated) in its
    title, ``title`` above it (that of the product's maps)."""
    import numpy as np
    with _rc():
        fig, axes = new_figure(5.4, 5.3)
        ax = axes[0][0]
        a, w = np.asarray(a, dtype=float), np.asarray(w, dtype=float)
        draw_map_panel(ax, a, w, stable, limits, region, cell_size(len(a)))
        ax.set_title(y=1.0, label=f"{LABELS[criterion]}: {count} of {stable.size} stable{run}")
        ax.set_xlabel(TEXT["a/l"])
        ax.set_ylabel(TEXT["w0/w"])
        ax.legend(loc="upper left", frameon=False)
        fig.suptitle(title)
        _margins(fig, left=0.62, right=0.25, bottom=0.48, top=0.75)
    return fig


def simulate_figure(tau, theta, pivot_tau, pivot, error=None, title=""):
    """theta against tau over the pivot's y0/a (its own panel below), and |RK4 - DOP853| of
    theta on a logarithmic axis when ``error`` is given."""
    import numpy as np
    rows = 3 if error is not None else 2
    ratios = [3, 1, 1.5][:rows]
    with _rc():
        fig, axes = new_figure(6.6, 2.0 + 1.25 * rows, rows, 1, sharex=True,
                               gridspec_kw={"height_ratios": ratios})
        ax, axp = axes[0][0], axes[1][0]
        draw_theta(ax, tau, theta, "RK4", lw=1.0)
        ax.set_ylabel(TEXT["theta(tau)"] + " (rad)")
        ax.set_title(y=1.0, label=title)
        draw_pivot(axp, pivot_tau, pivot, TEXT["pivot"], style="-", lw=0.8)
        axp.set_ylabel(TEXT["pivot"])
        low = axp
        if error is not None:
            axe = axes[2][0]
            draw_error(axe, tau, np.abs(np.asarray(error, dtype=float)), "-", "C3",
                       "|θ(RK4) − θ(DOP853)|")
            axe.set_ylabel("|RK4 − DOP853|")
            positive = np.abs(np.asarray(error, dtype=float))
            positive = positive[positive > 0]
            if positive.size:  # not down to draw_error's 1e-18 where the two agree (at tau = 0)
                axe.set_ylim(float(positive.min()) / 3, float(positive.max()) * 3)
            log_ticks(axe)
            low = axe
        low.set_xlabel(TEXT["tau"] + " = ωt/2")
        ax.set_xlim(float(tau[0]), float(tau[-1]))
        _margins(fig, left=0.85, right=0.15, bottom=0.45, top=0.3, hspace=0.12)
    return fig


def stability_figure(w, lower, upper, ratio, at, method_label, title):
    """Limits of a/l (x) against omega0/omega ``w`` (y), lower solid and upper dashed, the band
    between them shaded (stable), the asked ``ratio`` and its limits ``at`` = (lower, upper)
    marked; the axes fitted to the data."""
    import math

    import numpy as np
    lo = np.array([np.nan if v is None else v for v in lower], dtype=float)
    up = np.array([np.nan if v is None else v for v in upper], dtype=float)
    w = np.asarray(w, dtype=float)
    finite = np.concatenate([lo[np.isfinite(lo)], up[np.isfinite(up)]])
    right = 1.08 * float(finite.max()) if finite.size else 1.0
    no_upper = not np.isfinite(up).any()
    with _rc():
        fig, axes = new_figure(5.4, 4.2)
        ax = axes[0][0]
        band = np.isfinite(lo)
        edge = np.where(np.isfinite(up), up, right)  # no upper limit: stable up to the edge
        ax.fill_betweenx(w, lo, edge, where=band & (edge > lo), color="0.85", lw=0,
                         label="stable: a/l > lower (no upper limit by this method)" if no_upper
                         else "stable: lower < a/l < upper")
        name = method_name(method_label)
        draw_limits(ax, w, lo, up, None, color=("C3", "C0"), styles=("-", "--"),
                    labels=(f"lower, {name}", None if no_upper else f"upper, {name}"), lw=1.2)
        ax.axhline(ratio, color="0.4", lw=0.6, ls=":")
        for v, marker, side, colour in zip(at, ("o", "s"), ("lower", "upper"), ("C3", "C0")):
            if v is not None and math.isfinite(v):
                ax.plot([v], [ratio], marker, color=colour, mfc="white", ms=5, ls="none",
                        label=f"{side} = {v:.6g} at ω₀/ω = {ratio:g}")
        ax.set_xlim(0, right)
        ax.set_ylim(float(w[0]), float(w[-1]))
        ax.set_xlabel(TEXT["a/l"])
        ax.set_ylabel(TEXT["w0/w"])
        ax.set_title(y=1.0, label=title)
        ax.legend(loc="best", frameon=True, framealpha=0.9, edgecolor="none")
        _margins(fig, left=0.62, right=0.14, bottom=0.48, top=0.3)
    return fig


def method_name(method):
    """A stability method's name in a legend: "exact (Floquet)", "eq. 28", "series, order 8"."""
    names = {"exact": "exact (Floquet)", "eq12": "eq. 12", "eq19": "eq. 19",
             "eq19-corrected": "eq. 19 corrected", "eq28": "eq. 28"}
    kind, _, order = method.partition(":")
    if kind == "series":
        return f"series, order {order}"
    if kind == "integer-series":
        return f"a₀, b₁ series, order {order}"
    return names.get(method, method)


def mcmahon_beta(nu, k):
    """McMahon's leading term beta = (k + nu/2 - 1/4) pi of j_nu,k (DLMF 10.21.19)."""
    import numpy as np
    return (np.asarray(k, dtype=float) + float(nu) / 2 - 0.25) * np.pi


def mcmahon_correction(nu, k, terms=4):
    """j_nu,k - beta by McMahon's expansion: sum_j c_j(mu) beta^-(2j-1), j = 1..terms, with
    the c_j derived in :func:`pendulab.analyses.bessel_asymptotics.mcmahon_coefficients`."""
    from fractions import Fraction

    from flint import fmpq

    from pendulab.analyses.bessel_asymptotics import mcmahon_coefficients, poly_at
    nu = Fraction(nu)
    mu = fmpq(4) * fmpq(nu.numerator, nu.denominator) ** 2
    coeffs = [poly_at(c, mu) for c in mcmahon_coefficients()[:terms]]
    beta = mcmahon_beta(nu, k)
    return sum((int(c.p) / int(c.q)) * beta ** -(2 * j - 1) for j, c in enumerate(coeffs, start=1))


MCMAHON_TERMS = 4


def zeros_figure(nu, zeros, title):
    """The zeros j_nu,k against k over McMahon's beta_k (top), and j_nu,k - beta_k against k
    with McMahon's correction, which tends to 0 (bottom; DLMF 10.21.19)."""
    import numpy as np
    from matplotlib.ticker import MaxNLocator
    k = np.arange(1, len(zeros) + 1)
    j = np.asarray(zeros, dtype=float)
    fine = np.linspace(1, max(len(zeros), 2), 400)
    with _rc(), _math():
        fig, axes = new_figure(6.0, 5.2, 2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
        ax, ax2 = axes[0][0], axes[1][0]
        ax.plot(fine, mcmahon_beta(nu, fine), "-", color="C0", lw=1.0,
                label=r"$\beta_k = (k + \nu/2 - 1/4)\,\pi$ (McMahon's leading term)")
        ax.plot(k, j, "o", color="k", mfc="none", ms=4, ls="none", label=r"$j_{\nu,k}$ (certified)")
        ax.set_ylabel(r"$j_{\nu,k}$")
        ax.set_title(y=1.0, label=title)
        ax.legend(loc="upper left", frameon=False)
        diff = j - mcmahon_beta(nu, k)
        corr = mcmahon_correction(nu, fine, MCMAHON_TERMS)
        ax2.axhline(0.0, color="0.5", lw=0.6, ls=":", label=r"limit 0 as $k \to \infty$")
        ax2.plot(fine, corr, "-", color="C3", lw=1.0,
                 label=f"McMahon, {MCMAHON_TERMS} terms (DLMF 10.21.19)")
        ax2.plot(k, diff, "o", color="k", mfc="none", ms=4, ls="none", label=r"$j_{\nu,k} - \beta_k$")
        span = [float(diff.min()), float(diff.max()), 0.0]
        width = max(span) - min(span) or 1.0
        # the legend off the points: the points tend to 0 on the right; where they are near
        # it already, the legend goes to the far side, else between them and 0 (room made)
        below = diff[-1] < 0
        near = abs(diff[-1]) < 0.5 * float(np.abs(diff).max())
        upper = below != near
        ax2.set_ylim(min(span) - (0.1 if upper else 0.45) * width,
                     max(span) + (0.45 if upper else 0.1) * width)
        ax2.set_ylabel(r"$j_{\nu,k} - \beta_k$")
        ax2.set_xlabel(r"$k$")
        ax2.legend(loc="upper right" if upper else "lower right", frameon=False)
        ax.set_xlim(0.5, len(zeros) + 0.5)
        ax2.xaxis.set_major_locator(MaxNLocator(integer=True))
        _margins(fig, left=0.8, right=0.15, bottom=0.45, top=0.3, hspace=0.1)
    return fig


def margins_figure(after, before, limit_after, limit_before, title):
    """The margins of 002's claim against k: ``after[k]`` = inward[k] - the outward swing
    after it (top), ``before[k - 1]`` = inward[k] - the one before it (bottom), with their
    limits as k -> oo (derived from McMahon's expansion; None: not drawn)."""
    import numpy as np
    from matplotlib.ticker import MaxNLocator
    with _rc(), _math():
        fig, axes = new_figure(6.0, 4.8, 2, 1, sharex=True)
        rows = ((after, 0, limit_after, "C0", "o", "after", r"6 - \pi^2/2"),
                (before, 1, limit_before, "C3", "s", "before", r"6 + \pi^2/2"))
        for ax, (values, first, limit, colour, marker, name, closed) in zip(axes[:, 0], rows):
            k = np.arange(first, first + len(values))
            v = np.array([float(x) for x in values])
            if k.size:
                ax.plot(k, v, marker, color=colour, mfc="none", ms=4, ls="none",
                        label=f"inward swing $k$ minus the outward swing {name} it (certified)")
            if limit is not None:
                ax.axhline(limit, color=colour, lw=0.8, ls="--",
                           label=rf"limit as $k \to \infty$: ${closed} = {limit:.6g}$")
            ax.set_ylabel(f"margin {name}\n" + r"(unit $|dL/dt|/(4g)$)")
            ax.legend(loc="best", frameon=False)
        axes[0][0].set_title(y=1.0, label=title)
        axes[1][0].set_xlabel(r"$k$")
        axes[1][0].xaxis.set_major_locator(MaxNLocator(integer=True))
        _margins(fig, left=0.8, right=0.15, bottom=0.45, top=0.3, hspace=0.12)
    return fig


def _math():
    """Mathematics in Computer Modern, as the lecture notes typeset it."""
    import matplotlib
    return matplotlib.rc_context({"mathtext.fontset": "cm"})
