"""Product "experiments": the source's numerical experiments (000 sec. 4, Figs. 2-5).

Writes

* ``experiments.json`` - for each map (Figs. 3 and 4: initial conditions
  "text" (0.06, 0.01), "caption" (0.01, 0.06), "fig4" (0.1, 0.1)) the stable
  count per criterion and the maps as rows of "0"/"1" (row i: omega0/omega =
  w0_over_w[i], column j: a/l = a_over_l[j]); the eq. 28 and exact limits of
  a/l on the grid; the first experiment's stable pairs per initial condition;
  Fig. 5's nu and errors; Fig. 2's groups.  Numbers rounded to 10 significant
  digits.
* ``fig3-text``, ``fig3-caption``, ``fig4``, ``fig5``, ``fig2`` as ``.png``
  and ``.pdf`` (matplotlib, Agg; no dates or versions in the files, so the
  bytes are the same on every run).

The body, drive and angle come from the scene.  ``backend = "numpy"`` (the
default) keeps the bytes independent of a C compiler: trajectories that
fall and rotate are chaotic, and their verdict can change with the last bit
of sin(), which differs between the C library and NumPy.
"""

from pendulab.errors import InputError
from pendulab.figures import collector_paused
# the figures' rc settings, panel titles and labels (plain Unicode text, or typeset as
# mathematics for labels = "math"): shared with the commands' --plot
from pendulab.plots import LABELS, MATH, MATH_LABELS, RC, TEXT

from pendulab.limits import option as _limited

#: Type, default, range and help of the numbers and lists from pendulab.limits.LIMITS; the rest here.
OPTIONS = {
    "maps": _limited("experiments.maps"),
    "grid": _limited("experiments.grid"),
    "periods": _limited("experiments.periods"),
    "steps_per_period": _limited("experiments.steps_per_period"),
    "criteria": _limited("experiments.criteria"),
    "prune": (bool, False, "integrate only where the Floquet verdict may not hold"),
    "first_experiment": (bool, False, "10 x 10 initial conditions x the parameter grid"),
    "first_grid": _limited("experiments.first_grid"),
    "first_convention": (str, "linspace", "linspace, right or left (see docs/experiments.md)"),
    "fig5": (bool, True, "Fig. 5: RK4 against the series solution"),
    "fig5_orders": _limited("experiments.fig5_orders"),
    "fig5_periods": _limited("experiments.fig5_periods"),
    "fig2": (bool, True, "Fig. 2: fast and slow motion"),
    "fig2_periods": _limited("experiments.fig2_periods"),
    "figures": (bool, True, "write the PNG and PDF figures (needs matplotlib)"),
    "labels": (str, "text", "text (plain Unicode labels) or math (labels typeset as mathematics, "
               "Computer Modern, as the lecture notes include them)"),
    "backend": (str, "numpy", "integrator backend: numpy (reproducible bytes), c or auto"),
    "dask": (str, "", "address of a dask.distributed scheduler for the sweeps ('' = local)"),
}
SYSTEMS = ("kapitza",)
#: Points per axis of the limit curves and of the shaded Floquet region in the figures.
FINE = 301
#: Points of omega0/omega at which the eq. 28 curves of the figures are computed.
CURVE = 41

def _round(v):
    import math
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(f"{v:.10g}")


def _rows(m):
    return ["".join("1" if x else "0" for x in row) for row in m]


def system_spec(ctx):
    """The SystemSpec of a scene (body, drive, angle, inertia as the scene gives them)."""
    from pendulab.numerics.sweep import SystemSpec, use_stages
    p = dict(ctx.scene.parameters)
    inertia = p.get("inertia")
    spec = SystemSpec(body=p.get("body", "rod"), drive=p.get("drive"), angle=p.get("angle", "up"),
                      inertia=None if inertia is None else str(inertia))
    use_stages(spec, ctx.get("equations"), ctx.get("canonical"))
    return spec


def preload(options):
    """Heavy modules this product imports: :func:`pendulab.build.compute_scenes` imports those
    that two or more scenes need once, before it forks its workers."""
    return ("matplotlib",) if options["figures"] else ()


def check_options(options):
    from pendulab.numerics.experiments import CONVENTIONS, INITIAL
    from pendulab.numerics.sweep import CRITERIA
    problems = []
    for m in options["maps"]:
        if m not in INITIAL:
            problems.append(f"maps: {m!r} is not one of {', '.join(INITIAL)}")
    for c in options["criteria"]:
        if c not in CRITERIA:
            problems.append(f"criteria: {c!r} is not one of {', '.join(CRITERIA)}")
    for key in ("maps", "criteria"):
        twice = sorted({x for x in options[key] if options[key].count(x) > 1}, key=str)
        if twice:
            problems.append(f"{key}: {', '.join(map(repr, twice))} listed twice")
    from pendulab import limits
    ranged = [k for k in OPTIONS if f"experiments.{k}" in limits.LIMITS]
    for key in ranged:
        try:
            limits.check(f"experiments.{key}", options[key], label=key)
        except InputError as exc:
            problems.append(str(exc))
    if options["first_convention"] not in CONVENTIONS:
        problems.append(f"first_convention must be one of {', '.join(CONVENTIONS)}")
    for k in options["fig5_orders"]:
        if isinstance(k, bool) or not isinstance(k, int) or not 2 <= k <= 40:
            problems.append(f"fig5_orders: {k!r} must be a whole number in [2, 40]")
    if options["labels"] not in ("text", "math"):
        problems.append(f"labels must be text or math, got {options['labels']!r}")
    if options["backend"] not in ("numpy", "c", "auto"):
        problems.append(f"backend must be numpy, c or auto, got {options['backend']!r}")
    if not problems:
        compiler = False
        if options["backend"] == "auto":  # costed as what it will run (C where a compiler is)
            from pendulab.numerics.ckernel import compiler_found
            compiler = compiler_found() is not None
        work = limits.work_problem("experiments", options, compiler=compiler)
        if work:
            problems.append(work)
    if problems:
        raise InputError("; ".join(problems))


def parts(options):
    """The parts that :func:`pendulab.build.compute_scenes` may compute in different processes:
    one per map ("map:<name>", with its figure), "summary" (the body, I/(m l^2) and the
    limits of a/l on the map grid), "first", "fig5" and "fig2" (each with its figure)."""
    return ([f"map:{name}" for name in options["maps"]] + ["summary"]
            + [k for k, on in (("first", options["first_experiment"]), ("fig5", options["fig5"]),
                               ("fig2", options["fig2"])) if on])


def _prepared(ctx, options):
    """(spec, mathieu, sweep keywords) of the scene, after every check of the options;
    made once per process and scene (``ctx.memo``)."""
    key = "experiments:prepared"
    if key not in ctx.memo:
        check_options(options)
        spec = system_spec(ctx)
        mathieu = _sweep()._stages(spec)[1].kind == "mathieu"
        if not mathieu:
            # a Hill drive: the Floquet verdict is the monodromy matrix's; eq. 28, the exact
            # limits of pendulab.analyses.stability and the series of Fig. 5 are Mathieu's, and
            # so are the exponents by which pruning chooses the cells it integrates
            wanted = [k for k in ("prune", "fig5", "fig2") if options[k]]
            if wanted:
                raise InputError(f"{' and '.join(wanted)}: the drive gives a Hill equation, and "
                                 f"{'they need' if len(wanted) > 1 else 'it needs'} Mathieu's "
                                 f"(theta0, theta1): set {' and '.join(k + ' = false' for k in wanted)}")
        if [c for c in options["criteria"] if c != "floquet"] or options["first_experiment"]:
            _check_step(spec, options, ctx.scene.path)
        kw = {"backend": options["backend"], "quiet": True}
        if options["dask"]:
            kw["dask"] = options["dask"]
        ctx.memo[key] = (spec, mathieu, kw)
    return ctx.memo[key]


def _sweep():
    from pendulab.numerics import sweep
    return sweep


def _check_step(spec, options, path):
    """Refuse the maps' and first experiment's RK4 step where it is unstable on their grids
    (:func:`pendulab.numerics.step_check.enforce`); a coarse step is said on stderr."""
    import sys

    from pendulab.numerics import experiments as E
    from pendulab.numerics.step_check import enforce
    S = _sweep()
    axes = [S.linspace_grid(options["grid"])] if options["maps"] else []
    if options["first_experiment"]:
        axes.append(E.axis(options["first_grid"], options["first_convention"]))
    for values in axes:
        grid = S.make_spec(spec, a_over_l=values, w0_over_w=values, periods=options["periods"],
                           steps_per_period=options["steps_per_period"])
        enforce(grid, f"steps_per_period = {options['steps_per_period']}",
                warn=lambda line: sys.stderr.write(f"pendulab: {path}: products.experiments: {line}\n"))


def _fine(ctx, spec, mathieu, w):
    """What the map figures draw under the cells and its traced outline (:func:`region_paths`),
    made once per process and scene: for Mathieu's equation the eq. 28 curves on CURVE points
    and the Floquet region on FINE x FINE points; for a Hill drive the Floquet (monodromy)
    region on the map's own grid ``w``."""
    key = "experiments:fine"
    if key not in ctx.memo:
        ctx.memo[key] = map_limits(spec, mathieu, w)
    return ctx.memo[key]


def map_limits(spec, mathieu, w, region=None):
    """(limits, region paths) that a map figure draws under its cells (see :func:`_fine`;
    ``pendulab sweep --plot`` draws the same).  ``region``: the Floquet map on w x w when the
    caller has it already (a Hill drive's map by the floquet criterion)."""
    from pendulab.numerics import experiments as E
    if mathieu:
        fine = E.S.linspace_grid(FINE)
        w21 = E.S.linspace_grid(CURVE)
        limits = {"w0_over_w": w21, "curves": E.limit_curves(spec, w21, ("eq28",)),
                  "region_values": fine, "region": E.floquet_region(spec, fine)}
    else:
        limits = {"w0_over_w": w, "curves": {}, "region_values": w,
                  "region": E.floquet_region(spec, w) if region is None else region}
    return limits, region_paths(limits)


def produce_part(ctx, options, part):
    """The result of one part (see :func:`parts`): its numbers and, with figures on, the
    {file name: bytes} of its figure under "files"."""
    from pendulab.errors import SceneError
    try:
        return _part(ctx, options, part)
    except InputError as exc:
        raise SceneError(ctx.scene.path, "products.experiments", str(exc)) from None


def _part(ctx, options, part):
    from pendulab.numerics import experiments as E
    spec, mathieu, kw = _prepared(ctx, options)
    figures = options["figures"]
    L = MATH if options["labels"] == "math" else TEXT
    if part.startswith("map:"):
        name = part[4:]
        m = E.stability_maps(spec, options["grid"], E.INITIAL[name], options["periods"],
                             options["steps_per_period"], tuple(options["criteria"]),
                             prune=options["prune"], **kw)
        files = {}
        if figures:
            fine, region = _fine(ctx, spec, mathieu, m["w0_over_w"])
            files = {MAP_FILES[name] + ext: data
                     for ext, data in figure_map(m, fine, map_title(name, m, fine, L), region, L).items()}
        return {"map": m, "files": files}
    if part == "summary":
        out = {"body": spec.body, "inertia_ratio": str(E.inertia_ratio(spec)), "limits": None}
        if options["maps"] and mathieu:
            w = E.S.linspace_grid(options["grid"])
            out["limits"] = {"w0_over_w": w, "curves": E.limit_curves(spec, w)}
        return out
    if part == "first":
        return {"first": E.first_experiment(spec, options["first_grid"], options["first_convention"],
                                            options["periods"], options["steps_per_period"], **kw)}
    if part == "fig5":
        r = E.fig5(spec, periods=options["fig5_periods"], orders=tuple(options["fig5_orders"]),
                   backend=options["backend"])
        return {"fig5": r, "files": {"fig5" + ext: d for ext, d in figure_fig5(r, L).items()} if figures else {}}
    if part == "fig2":
        r = E.fig2(spec, periods=options["fig2_periods"], backend=options["backend"])
        return {"fig2": r, "files": {"fig2" + ext: d for ext, d in figure_fig2(r, L).items()} if figures else {}}
    raise InputError(f"no part {part!r} of the experiments product")


def assemble(scene, options, results):
    """{file: text or bytes} of the product from {part: result} of every part of :func:`parts`."""
    from pendulab.io import canonical_json
    summary = results["summary"]
    merged = {"maps": {name: results[f"map:{name}"]["map"] for name in options["maps"]},
              "limits": summary["limits"]}
    for key in ("first", "fig5", "fig2"):
        if key in results:
            merged[key] = results[key][key]
    files = {"experiments.json": canonical_json(document(merged, options, scene.name, summary))}
    for part in parts(options):
        files.update(results[part].get("files", {}))
    return files


def document(results, options, scene_name, summary):
    from pendulab.numerics.experiments import INITIAL, SOURCE_COUNTS
    doc = {"scene": scene_name, "source": "000_8cba66c4fdf94ac6.txt sec. 4, Figs. 2-5",
           "body": summary["body"], "inertia_ratio": summary["inertia_ratio"],
           "periods": options["periods"], "steps_per_period": options["steps_per_period"],
           "criteria_note": "mean: |time mean of theta| < 0.1; mean-abs: time mean of |theta| < 0.1; "
                            "bounded: |theta| < pi/2 throughout; floquet: exact linear verdict "
                            "(means over the steps + 1 RK4 states)",
           "maps": {}}
    for name, m in results["maps"].items():
        doc["maps"][name] = {
            "initial": list(INITIAL[name]), "grid": len(m["a_over_l"]),
            "a_over_l": [_round(v) for v in m["a_over_l"]], "w0_over_w": [_round(v) for v in m["w0_over_w"]],
            "counts": m["counts"], "simulated": m["simulated"],
            "rows": {c: _rows(v) for c, v in m["maps"].items()}}
    if results["limits"] is not None:
        doc["limits"] = {"w0_over_w": [_round(v) for v in results["limits"]["w0_over_w"]],
                         **{meth: {"lower": [_round(float(x)) for x in lo],
                                   "upper": [_round(float(x)) for x in up]}
                            for meth, (lo, up) in results["limits"]["curves"].items()}}
    if "first" in results:
        f = results["first"]
        ics = [tuple(p) for p in f["initial"]]
        named = {}
        for key in ((0.1, 0.1), (0.06, 0.01), (0.01, 0.06)):
            if key in ics:
                named[f"{key[0]},{key[1]}"] = {c: v[ics.index(key)] for c, v in f["counts"].items()}
        doc["first_experiment"] = {
            "convention": f["convention"], "a_over_l": [_round(v) for v in f["a_over_l"]],
            "initial": [list(p) for p in ics], "counts": f["counts"],
            "range": {c: [min(v), max(v)] for c, v in f["counts"].items()},
            "named": named, "floquet_count": f["floquet"],
            "source": {"min": SOURCE_COUNTS["min"], "max": SOURCE_COUNTS["max"],
                       "0.1,0.1": SOURCE_COUNTS[(0.1, 0.1)], "0.06,0.01": SOURCE_COUNTS[(0.06, 0.01)]}}
    if "fig5" in results:
        r = results["fig5"]
        doc["fig5"] = {"theta0": _round(r["theta0"]), "theta1": _round(r["theta1"]),
                       "nu": {str(k): _round(v) for k, v in r["nu"].items()},
                       "max_error_vs_rk4": {str(k): _round(v) for k, v in r["error"].items()},
                       "max_error_vs_rk4_linear": {str(k): _round(v) for k, v in r["error_linear"].items()},
                       "series_estimate": {str(k): _round(v) for k, v in r["estimate"].items()},
                       "tau_max": _round(float(r["tau"][-1])),
                       "rk4_error_vs_dop853": _error(r["rk4_error"]),
                       "rk4_error_vs_dop853_linear": _error(r["rk4_error_linear"])}
    if "fig2" in results:
        r = results["fig2"]
        doc["fig2"] = {k: _round(r[k]) for k in ("theta0", "theta1", "a_over_l", "w0_over_w", "nu")}
        doc["fig2"]["rk4_error_vs_dop853"] = _error(r["rk4_error"])
    return doc


# ---------------------------------------------------------------------------
# figures
# ---------------------------------------------------------------------------

def _matplotlib():
    from pendulab.figures import pyplot
    return pyplot("experiment")


def _rc(L):
    """The figures' rc settings: :data:`RC`, and Computer Modern mathematics for ``labels = "math"``."""
    return {**RC, "mathtext.fontset": "cm"} if L["math"] else RC


def _number(x, spec, L):
    """``format(x, spec)`` as a label part: mathematics for ``labels = "math"``, else with a
    true minus sign (:func:`_minus`)."""
    return f"${format(x, spec)}$" if L["math"] else _minus(x, spec)


def save(fig):
    """{".png": bytes, ".pdf": bytes} with no dates or software versions inside."""
    from pendulab.figures import save as save_bytes
    return save_bytes(fig, dpi=RC["savefig.dpi"])


def _margins(fig, **inches):
    from pendulab.figures import margins
    margins(fig, **inches)


def _minus(x, spec):
    """``format(x, spec)`` with a true minus sign (U+2212), as mathtext wrote it."""
    from pendulab.plots import minus
    return minus(x, spec)


def region_paths(limits):
    """(shaded, edge): matplotlib Paths of the Floquet-stable region of ``limits`` (the fine
    Floquet map, 1 = stable, on region_values x region_values) and of its edge.

    The contours contourf(levels=[0.5, 1.5]) and contour(levels=[0.5]) would trace, by the
    same contour generator (contourpy, mpl2014, corner mask), made once for every panel of
    every map instead of twice per panel.
    """
    import contourpy
    import numpy as np
    from matplotlib.path import Path
    values = np.asarray(limits["region_values"], dtype=float)
    x, y = np.meshgrid(values, values)
    gen = contourpy.contour_generator(x, y, np.asarray(limits["region"], dtype=float), name="mpl2014",
                                      corner_mask=True, line_type=contourpy.LineType.SeparateCode,
                                      fill_type=contourpy.FillType.OuterCode)

    def path(vertices, codes):
        return Path(np.concatenate(vertices), np.concatenate(codes)) if vertices else Path(np.empty((0, 2)))

    return path(*gen.filled(0.5, 1.5)), path(*gen.lines(0.5))


@collector_paused
def figure_map(m, limits, title, region=None, L=TEXT):
    """2 x 2 panels (one per criterion): stable cells as open circles (as in the source), the
    Floquet region shaded, eq. 28 (solid) and exact (dashed) limits of a/l drawn over them.
    ``region``: :func:`region_paths` of ``limits`` (made here if not given)."""
    import numpy as np
    matplotlib, plt = _matplotlib()
    shaded, edge = region_paths(limits) if region is None else region
    crits = list(m["maps"])
    ncol = 2 if len(crits) > 1 else 1
    nrow = (len(crits) + ncol - 1) // ncol
    a = np.asarray(m["a_over_l"])
    w = np.asarray(m["w0_over_w"])
    key = (nrow, ncol, len(crits), L["math"])
    with matplotlib.rc_context(_rc(L)):
        fig, axes = _MAP_FIGURES.pop(key, None) or _map_figure(matplotlib, nrow, ncol)
        kept = False
        try:
            from pendulab.plots import cell_size, draw_map_panel
            ms = cell_size(len(a))
            for k, c in enumerate(crits):
                ax = axes[k // ncol][k % ncol]
                draw_map_panel(ax, a, w, m["maps"][c], limits, (shaded, edge), ms)
                ax.set_title(y=1.0, label=f"{(MATH_LABELS if L['math'] else LABELS)[c]}: "
                             f"{m['counts'][c]} stable")
                if k + ncol >= len(crits):  # the lowest panel of its column (the last row, or above an empty cell)
                    ax.set_xlabel(L["a/l"])
                    ax.xaxis.set_tick_params(labelbottom=True)
                if k % ncol == 0:
                    ax.set_ylabel(L["w0/w"])
            axes[0][0].legend(loc="upper left", frameon=False)
            for k in range(len(crits), nrow * ncol):
                axes[k // ncol][k % ncol].set_visible(False)
            fig.suptitle(title)
            # fixed margins in inches (tick labels, axis labels, titles at RC's sizes) in place of
            # tight_layout: one text-metrics pass less, and the same layout for PNG and PDF
            _margins(fig, left=0.62, right=0.14, bottom=0.48, top=0.8, wspace=0.32, hspace=0.36)
            out = save(fig)
            _empty_map_figure(fig)
            _MAP_FIGURES[key] = (fig, axes)
            kept = True
            return out
        finally:
            if not kept:
                plt.close(fig)


#: (rows, columns, panels) -> (figure, axes): a map's figure emptied of its data after saving,
#: for the next map of the process.  The maps share their layout, limits and ticks; making the
#: 2 x 2 axes and their 48 ticks again costs about 0.05 s per map.
_MAP_FIGURES = {}


def _map_figure(matplotlib, nrow, ncol):
    """A new (figure, axes) of :func:`figure_map` (outside pyplot: it may be kept)."""
    from matplotlib.figure import Figure
    # the suptitle takes two lines (see figures()): 0.18 in more at the top than one line
    fig = Figure(figsize=(6.6, 3.3 * nrow + 0.58))
    return fig, fig.subplots(nrow, ncol, squeeze=False, sharex=True, sharey=True)


def _empty_map_figure(fig):
    """Takes out what :func:`figure_map` added to the panels (lines, patches, the legend) and
    puts the axes' colour cycle and data limits back as a new figure has them."""
    for ax in fig.axes:
        for artist in [*ax.lines, *ax.patches]:
            artist.remove()
        if ax.get_legend() is not None:
            ax.get_legend().remove()
        ax.set_prop_cycle(None)
        ax.relim()


@collector_paused
def figure_fig5(r, L=TEXT):
    import numpy as np

    matplotlib, plt = _matplotlib()
    with matplotlib.rc_context(_rc(L)):
        fig, (ax, ax2) = plt.subplots(2, 1, figsize=(6.6, 5.0), sharex=True,
                                      gridspec_kw={"height_ratios": [2, 1]})
        try:
            from pendulab.plots import draw_error, draw_theta, log_ticks
            tau = r["tau"]
            draw_theta(ax, tau, r["theta"], "RK4, full equation", lw=1.0)
            styles = ["--", ":", "-."]
            for k, (n, th) in enumerate(r["series"].items()):
                ax.plot(tau, th, styles[k % 3], color=f"C{3 + k}", lw=1.0,
                        label=f"series (eq. 23), order {n}")
                draw_error(ax2, tau, np.abs(th - r["theta"]), styles[k % 3], f"C{3 + k}",
                           f"order {n}: max {r['error'][n]:.1e}")
            ax.set_ylabel(L["theta(tau)"])
            if L["math"]:
                ax.set_title(y=1.0, label=rf"$a/l = 1/5$, $\omega_0/\omega = 1/20$, $\theta(0) = {r['theta'][0]:g}$, "
                             rf"$\theta'(0) = 0.01$ ($\theta_0 = {r['theta0']:.3g}$, $\theta_1 = {r['theta1']:.3g}$)")
            else:
                ax.set_title(y=1.0, label=f"a/l = 1/5, ω₀/ω = 1/20, θ(0) = {r['theta'][0]:g}, "
                             f"dθ/dτ(0) = 0.01 (θ₀ = {_minus(r['theta0'], '.3g')}, θ₁ = {_minus(r['theta1'], '.3g')})")
            ax.legend(loc="lower left", frameon=False)
            log_ticks(ax2)  # 10⁻² as text, not mathtext
            ax2.set_xlabel(L["tau"])
            ax2.set_ylabel(L["error"])
            ax2.legend(loc="lower right", frameon=False)
            _margins(fig, left=0.8, right=0.12, bottom=0.45, top=0.3, hspace=0.15)
            return save(fig)
        finally:
            plt.close(fig)


@collector_paused
def figure_fig2(r, L=TEXT):
    matplotlib, plt = _matplotlib()
    with matplotlib.rc_context(_rc(L)):
        fig, ax = plt.subplots(figsize=(6.6, 3.6))
        try:
            from pendulab.plots import draw_pivot, draw_theta
            tau = r["tau"]
            draw_theta(ax, tau, r["theta"], f"{L['theta(tau)']} (RK4, eq. 7)")
            ax.plot(tau, r["slow"], "--", color="C3", lw=1.2, label="slow part (mean over one drive period)")
            ax.set_xlabel(L["tau"])
            ax.set_ylabel(L["theta"])
            ax2 = ax.twinx()
            draw_pivot(ax2, tau, r["pivot"], L["pivot"])
            ax2.set_ylabel(L["pivot"])
            ax2.set_ylim(-6, 6)
            ax.set_title(y=1.0, label=f"{L['theta0']} = {_number(r['theta0'], 'g', L)}, "
                         f"{L['theta1']} = {_number(r['theta1'], 'g', L)}, "
                         f"{L['theta(0)']} = {_number(r['theta'][0], 'g', L)}, {L['dtheta(0)']} = {_number(0, 'g', L)}")
            h1, l1 = ax.get_legend_handles_labels()
            h2, l2 = ax2.get_legend_handles_labels()
            fig.legend(h1 + h2, l1 + l2, loc="lower center", ncol=3, frameon=False)
            _margins(fig, left=0.85, right=0.6, bottom=0.8, top=0.3)
            return save(fig)
        finally:
            plt.close(fig)


#: file name (without extension) of each map's figure
MAP_FILES = {"text": "fig3-text", "caption": "fig3-caption", "fig4": "fig4"}


def map_title(name, m, fine, L=TEXT):
    """The suptitle of map ``name``'s figure."""
    from pendulab.numerics.experiments import INITIAL
    th, om = INITIAL[name]
    return initial_title(th, om, len(m["a_over_l"]), fine, L)


def initial_title(th, om, n, fine, L=TEXT, extra=""):
    """The suptitle of a map of n x n pairs from theta(0) = th, dtheta/dtau(0) = om (``extra``
    after the pairs)."""
    # two lines: on one the suptitle is wider than the figure (clipped at both edges)
    pairs = f"${n}^2$" if L["math"] else f"{n}²"
    return (f"{L['theta(0)']} = {_number(th, 'g', L)}, {L['dtheta(0)']} = {_number(om, 'g', L)}, "
            f"{pairs} pairs{extra}\n"
            + ("shaded: Floquet-stable; solid: eq. 28; dashed: exact" if fine["curves"]
               else "shaded: Floquet-stable (monodromy); dashed: its edge"))


def _error(value):
    """An integrator error to 3 significant digits: its size, not its last bits."""
    return float(f"{value:.3g}")


def produce(ctx, options):
    """{file: text or bytes}: every part of :func:`parts` in order, assembled."""
    return assemble(ctx.scene, options, {part: produce_part(ctx, options, part)
                                         for part in parts(options)})
