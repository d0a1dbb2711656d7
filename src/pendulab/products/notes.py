"""Product "notes": lecture notes assembled from a scene, ``notes.tex`` and ``notes.pdf``.

The notes are a complete LaTeX article (amsmath, booktabs, graphicx, babel)
made of sections, each a jinja2 template (``templates/notes/<language>/``)
that holds fixed prose and slots only.  Every equation, table and number in
a slot comes from the analyses' own printers, through the other products'
functions (:mod:`pendulab.products.equations`, ``stability``, ``series``,
``experiments``, ``bessel``, ``errata``), computed for this scene and only for
the sections it asks for:

* ``pivot`` - the driven pivot: Lagrangian, Euler-Lagrange equation,
  linearisation, Mathieu's form with theta0 and theta1 (000 eqs. 2-7) for the
  scene's body, and the scene's ``[values]`` (SI numbers) put into them;
* ``stability`` - the limits of a/l by Floquet theory, the series, Butikov's
  averaging and Phelps and Hunter's formula (000 eqs. 12, 19, 28): table and figure;
* ``series`` - 000 eqs. 20-24 to ``series_order``, long coefficients broken
  across lines, and the integer-order series with their radii of convergence;
* ``simulations`` - the source's sec. 4: the stability maps (Figs. 3, 4),
  the series against RK4 (Fig. 5), the slow and fast motion (Fig. 2), the counts;
* ``string`` - the variable-length pendulum (002): derivation, Bessel form,
  the identities with their certified error, the zeros and the quarter periods
  with the source's claim and its margins;
* ``errata`` - every misprint found in both sources, each beside the
  computation that shows it;
* ``references`` - the bibliography that the other sections cite.

Where ``pdflatex`` (or ``latexmk``) is on the machine, :func:`assemble`
compiles the article twice (references resolve) with fixed dates and a fixed
trailer ID, so that the PDF is the same bytes on every run
(:func:`compile_pdf`); without TeX it writes the .tex and the figures and
asks the build to keep the PDF it already has (:class:`pendulab.io.Kept`).
"""

from pendulab.errors import InputError
from pendulab.limits import option as _limited

#: The sections a scene may ask for, in their default order.
SECTIONS = ("pivot", "stability", "series", "simulations", "string", "errata", "references")
#: language option -> babel's name of it
LANGUAGES = {"en": "english", "pt": "portuguese"}

OPTIONS = {
    "language": (str, "en", "en or pt: the language of headings and fixed prose (babel)"),
    "sections": (list, list(SECTIONS), "the sections, in this order: " + ", ".join(SECTIONS)),
    "series_order": _limited("notes.series_order"),
    "grid": _limited("notes.grid"),
    "dps": _limited("notes.dps"),
    "length": (str, "L0 + v0*t", "L(t) of the variable-length section (002: L0 + v0*t)"),
    "figures": (bool, True, "the figures, as vector PDF (needs matplotlib)"),
    "pdf": (bool, True, "compile notes.pdf where pdflatex or latexmk is installed"),
}
SYSTEMS = ("kapitza",)
#: what ``pendulab build`` prints after the scene's line: the file a reader opens
HEADLINE = ("the notes", "notes.pdf")

#: 002 (its last page): the differences of squares of zeros it lists as the first quarter
#: periods, inward and outward in turn, in the unit v0/(4 g); the notes set them beside ours.
SOURCE_QUARTER_PERIODS = ("22.8438", "21.6315", "32.6495", "31.5213", "42.5001", "41.3994")

#: 000 sec. 2.2: the Mathieu parameters the source gives for its Fig. 2 (a rod 10 cm long,
#: 6 mm pivot amplitude at 86 Hz), set beside the ones derived from the scene's values
SOURCE_FIG2_VALUES = ("-2e-3", "0.2")
SOURCE_FIG2 = {"theta0": r"-2 \times 10^{-3}", "theta1": "0.2"}

#: the string's direction (pendulab.analyses.bessel_periods) in the Portuguese notes
DIRECTION_PT = {"growing": "que cresce", "shortening": "que encurta"}

#: SI unit of each physical symbol a scene's [values] may give (LaTeX, siunitx-free)
UNITS = {"l": r"\mathrm{m}", "a": r"\mathrm{m}", "omega": r"\mathrm{s^{-1}}",
         "g": r"\mathrm{m\,s^{-2}}", "m": r"\mathrm{kg}", "I": r"\mathrm{kg\,m^2}",
         "I0": r"\mathrm{kg\,m^2}", "omega0": r"\mathrm{s^{-1}}"}


def check_options(options):
    """One InputError listing every problem of ``options`` (scene validation calls this)."""
    problems = []
    if options["language"] not in LANGUAGES:
        problems.append(f"language must be one of {', '.join(LANGUAGES)}, got {options['language']!r}")
    sections = options["sections"]
    if not sections:
        problems.append("sections must name at least one of " + ", ".join(SECTIONS))
    for s in sections:
        if s not in SECTIONS:
            problems.append(f"sections: {s!r} is not one of {', '.join(SECTIONS)}"[:200])
    twice = sorted({s for s in sections if isinstance(s, str) and sections.count(s) > 1})
    if twice:
        problems.append(f"sections: {', '.join(map(repr, twice))} listed twice")
    if "string" in sections:
        from pendulab.exprs import parse
        try:
            parse(options["length"])
        except InputError as exc:
            problems.append(f"length: {exc}")
    if problems:
        raise InputError("; ".join(problems))


def preload(options):
    """Heavy modules this product imports (see :func:`pendulab.build.compute_scenes`)."""
    return ("matplotlib",) if options["figures"] else ()


def parts(options):
    """One part per section (computed side by side by :func:`pendulab.build.compute_scenes`)."""
    return list(options["sections"])


# ---------------------------------------------------------------------------
# templates
# ---------------------------------------------------------------------------

def environment():
    """The jinja2 environment of the notes: LaTeX-safe delimiters ``((* *))``, ``((( )))``,
    ``((# #))``, so that TeX's braces and ``%`` never meet jinja2's own."""
    import jinja2
    return jinja2.Environment(
        loader=jinja2.PackageLoader("pendulab", "templates"),
        block_start_string="((*", block_end_string="*))",
        variable_start_string="(((", variable_end_string=")))",
        comment_start_string="((#", comment_end_string="#))",
        line_statement_prefix=None, trim_blocks=True, lstrip_blocks=True,
        keep_trailing_newline=True, undefined=jinja2.StrictUndefined, autoescape=False)


def render(name, options, **slots):
    """The template ``notes/<language>/<name>.tex.j2`` with ``slots`` filled in, and
    ``sections`` (the sections the notes have, which a cross-reference may need)."""
    return environment().get_template(f"notes/{options['language']}/{name}.tex.j2").render(
        sections=options["sections"], **slots)


#: LaTeX's special characters in running text, and what prints each as itself
_TEXT_SPECIALS = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
                  "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
                  "^": r"\textasciicircum{}"}


def plain(text):
    """Plain ``text`` (a scene's name or description) as LaTeX that prints it as it is."""
    return "".join(_TEXT_SPECIALS.get(ch, ch) for ch in text)


def align(rows):
    """An align* environment of ``rows``."""
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def strip_banner(tex):
    """A product's LaTeX fragment without its leading '%' comment lines."""
    lines = tex.splitlines()
    while lines and lines[0].startswith("%"):
        lines.pop(0)
    return "\n".join(lines).strip("\n")


def labelled(tex, label):
    """A product's table float with ``\\label{label}`` after its caption (so the text can
    refer to it)."""
    return tex.replace("\\end{table}", f"\\label{{{label}}}\n\\end{{table}}", 1)


def number(value, digits=6):
    """``value`` (a SymPy or float number) as LaTeX: 6 significant digits, powers of ten
    as \\times 10^{k}."""
    import sympy as sp
    text = f"{float(sp.N(value, digits + 10)):.{digits}g}"
    if "e" in text:
        mantissa, exp = text.split("e")
        return rf"{mantissa} \times 10^{{{int(exp)}}}"
    return text


# ---------------------------------------------------------------------------
# sections
# ---------------------------------------------------------------------------

def produce_part(ctx, options, section):
    """{"tex": the section's LaTeX, "files": {figure file: bytes}} of one section."""
    from pendulab.errors import SceneError
    try:
        _refuse(ctx, section)
        return _SECTION[section](ctx, options)
    except InputError as exc:
        raise SceneError(ctx.scene.path, "products.notes", f"section {section}: {exc}") from None


#: the sections that need Mathieu's equation (theta0, theta1), not a Hill equation
MATHIEU_SECTIONS = ("stability", "simulations")


def _refuse(ctx, section):
    """InputError where the notes' prose would be false for the scene: they are written for
    the inverted pendulum (angle "up"), and two sections for Mathieu's equation."""
    if ctx.scene.parameters.get("angle", "up") != "up":
        raise InputError('the notes are written for the inverted pendulum: angle must be "up", '
                         f'got {ctx.scene.parameters.get("angle")!r}')
    if section in MATHIEU_SECTIONS and ctx.get("canonical").kind != "mathieu":
        raise InputError(f"this drive gives a {ctx.get('canonical').kind} equation, not Mathieu's, "
                         "which this section needs: leave " + " and ".join(MATHIEU_SECTIONS)
                         + " out of sections")


def _pivot(ctx, options):
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.products.equations import latex_steps
    system, form = ctx.get("system"), ctx.get("canonical")
    steps = {step: align(rows) for step, rows in latex_steps(ctx)}
    values, groups = [], {}
    if ctx.scene.values and form.kind == "mathieu":
        from pendulab.numerics.model import mathieu_parameters
        given = {str(k): v for k, v in ctx.scene.values.items()}
        values = [(sp.latex(sp.Symbol(k)), number(v), UNITS.get(k, ""))
                  for k, v in sorted(given.items())]
        th0, th1 = mathieu_parameters(ctx.get("equations"), form, values=given, groups=False)
        if th0.is_number and th1.is_number:
            groups = {"theta0": number(th0, 4), "theta1": number(th1, 4),
                      # the source's values are these to one significant digit
                      "rounded": all(float(f"{float(ours):.1g}") == float(theirs) for ours, theirs
                                     in ((th0, SOURCE_FIG2_VALUES[0]), (th1, SOURCE_FIG2_VALUES[1])))}
    return {"tex": render("pivot", options, steps=steps, body=system.body,
                          inertia=sp.latex(system.inertia),
                          inertia_ratio=sp.latex(sp.simplify(system.inertia_ratio)),
                          drive=sp.latex(system.drive), kind=form.kind, values=values,
                          groups=groups, source_fig2=SOURCE_FIG2, omega0=sp.latex(S.m * S.g * S.l / S.I)),
            "files": {}}


def stability_options(options):
    """The stability product's options for the notes: 11 ratios in [0, 1], every method."""
    order = min(max(options["series_order"], 2), 40)
    return {"points": 11, "max_ratio": "1", "figure": False,
            "methods": ["exact", "eq12", "eq19", "eq19-corrected", "eq28", f"series:{order}"]}


def _stability(ctx, options):
    import json

    from pendulab.products import stability
    opts = stability_options(options)
    made = stability.produce(ctx, opts)
    doc = json.loads(made["stability.json"])
    files = {}
    if options["figures"]:
        files["stability.pdf"] = stability.figure(doc, "pdf")
    return {"tex": render("stability", options, table=labelled(strip_banner(made["stability.tex"]), "tab:stability"),
                          figure="stability.pdf" if files else None,
                          order=opts["methods"][-1].split(":")[1]),
            "files": files}


def _series(ctx, options):
    from pendulab.products.series import integer_record, latex_text
    order = options["series_order"]
    radii = []
    for kind in ("a0", "b1"):
        rec = integer_record(kind, order)
        radii.append({"kind": kind[0], "m": kind[1:], "radius": rec["radius"],
                      "source": rec["radius_source"]})
    return {"tex": render("series", options, order=order,
                          series=strip_banner(latex_text(["nu"], order)),
                          integer=strip_banner(latex_text(["a0", "b1"], min(order, 8))),
                          integer_order=min(order, 8), radii=radii),
            "files": {}}


def experiments_options(options):
    """The experiments product's options for the notes (its defaults, the notes' grid, every
    map and criterion, pruned by the Floquet verdict, NumPy's bytes)."""
    from pendulab.products.experiments import OPTIONS as EXPERIMENTS
    opts = {key: default for key, (_kind, default, _help) in EXPERIMENTS.items()}
    opts.update({"grid": options["grid"], "prune": True, "figures": options["figures"],
                 "backend": "auto", "first_experiment": False, "labels": "math"})
    return opts


def _simulations(ctx, options):
    import json

    from pendulab.numerics.experiments import INITIAL, SOURCE_COUNTS
    from pendulab.products import experiments
    opts = experiments_options(options)
    made = experiments.produce(ctx, opts)
    doc = json.loads(made["experiments.json"])
    files = {k: v for k, v in made.items() if k.endswith(".pdf")}
    # the Floquet verdict is never integrated: its column of zeros is left out
    integrated = [c for c in opts["criteria"] if c != "floquet"]
    maps = []
    for name in opts["maps"]:
        m = doc["maps"][name]
        theta, omega = INITIAL[name]
        maps.append({"name": name, "theta": theta, "omega": omega,
                     "counts": [m["counts"][c] for c in opts["criteria"]],
                     "integrated": [m["simulated"][c] for c in integrated],
                     "figure": experiments.MAP_FILES[name] + ".pdf" if files else None})
    # which criteria give the source's count at each initial condition it names (grid 10 only)
    source_match = []
    if opts["grid"] == 10:
        for name in opts["maps"]:
            key = INITIAL[name]
            if key in SOURCE_COUNTS:
                counts = doc["maps"][name]["counts"]
                source_match.append({"theta": key[0], "omega": key[1], "source": SOURCE_COUNTS[key],
                                     "criteria": [c for c in opts["criteria"]
                                                  if counts[c] == SOURCE_COUNTS[key]]})
    fig5 = doc.get("fig5")
    fig5_rows = [(n, number(fig5["nu"][n], 6), number(fig5["max_error_vs_rk4"][n], 2),
                  number(fig5["max_error_vs_rk4_linear"][n], 2),
                  number(fig5["series_estimate"][n], 2))
                 for n in sorted(fig5["max_error_vs_rk4"], key=int)] if fig5 else []
    return {"tex": render("simulations", options, maps=maps, criteria=opts["criteria"],
                          step=f"1/{opts['grid'] - 1}" if opts["grid"] > 2 else "1",
                          integrated=integrated,
                          grid=opts["grid"], periods=opts["periods"],
                          steps=opts["steps_per_period"], source=SOURCE_COUNTS,
                          fig5=fig5, fig5_rows=fig5_rows, source_match=source_match,
                          kernel=opts["backend"],
                          fig5_file="fig5.pdf" if "fig5.pdf" in files else None,
                          fig2=doc.get("fig2"),
                          fig2_file="fig2.pdf" if "fig2.pdf" in files else None,
                          number=number),
            "files": files}


def string_scene(ctx, options):
    """The variable-length scene of the notes' ``string`` section (its length from the
    notes' options), parsed as any scene is."""
    from pendulab.products.bessel import OPTIONS as BESSEL
    from pendulab.scene import parse_scene
    bessel = {key: default for key, (_kind, default, _help) in BESSEL.items()}
    bessel["dps"] = options["dps"]
    data = {"name": f"{ctx.scene.name}-string", "system": "variable-length",
            "parameters": {"length": options["length"]},
            "products": {"equations": {}, "bessel": bessel}}
    from pendulab.errors import SceneError
    try:
        return parse_scene(data, ctx.scene.path)
    except SceneError as exc:  # its key is the sub-scene's: name the notes' option instead
        raise InputError(f"length {options['length']!r}: {exc.problem}") from None


def _string(ctx, options):
    import json

    import sympy as sp

    from pendulab.pipeline import Context
    from pendulab.products import bessel
    from pendulab.products.equations import latex_steps
    from pendulab.errors import SceneError
    sub = Context(string_scene(ctx, options))
    steps = {step: align(rows) for step, rows in latex_steps(sub)}
    try:
        made = bessel.produce(sub, sub.scene.products["bessel"])
    except InputError as exc:  # the sub-scene's product: name the notes' option
        problem = exc.problem if isinstance(exc, SceneError) else str(exc)
        raise InputError(f"length {options['length']!r}: {problem}") from None
    doc = json.loads(made["bessel.json"])
    q = doc["quarter_periods"]
    # time order: the first inward swing, then the outward one after it, ...
    ours = [x for pair in zip(q["inward"], q["outward"]) for x in pair]
    # the source's values are those of a growing string from z0 = j_2,1
    pairs = ([(src, mine[:len(src) + 4]) for src, mine in zip(SOURCE_QUARTER_PERIODS, ours)]
             if q["direction"] == "growing" and q["start"] == "z0 = j_2,1" else [])
    ident = doc["identities"]
    return {"tex": render("string", options, steps=steps,
                          zeros=labelled(strip_banner(made["bessel_zeros.tex"]), "tab:zeros"),
                          periods=labelled(strip_banner(made["bessel_quarter_periods.tex"]),
                                           "tab:quarter"),
                          identities=labelled(strip_banner(made["bessel_identities.tex"]),
                                              "tab:identities"),
                          claim_holds=q["claim_holds"], direction=q["direction"],
                          direction_pt=DIRECTION_PT.get(q["direction"], q["direction"]),
                          margin_before=(number(min(q["margin_before"], key=float))
                                         if q["margin_before"] else None),
                          margin_after=(number(min(q["margin_after"], key=float))
                                        if q["margin_after"] else None),
                          z_low=number(ident["z_range"][0], 3), z_high=number(ident["z_range"][1], 3),
                          shown=len(q["inward"]) + len(q["outward"]), source_pairs=pairs,
                          length=sp.latex(sub.get("system").length),
                          worst=number(ident["worst_relative_error"], 3), dps=ident["dps"],
                          agreements=ident["engine_agreements"], points=ident["points"],
                          nmax=ident["nmax"], contained=ident["arb_balls_contain_exact_values"]),
            "files": {}}


def _errata(ctx, options):
    from pendulab.products.errata import entries
    # every field is LaTeX: printed and found are math, the others running text
    return {"tex": render("errata", options, entries=entries()), "files": {}}


def _references(ctx, options):
    return {"tex": render("references", options), "files": {}}


_SECTION = {"pivot": _pivot, "stability": _stability, "series": _series,
            "simulations": _simulations, "string": _string, "errata": _errata,
            "references": _references}


# ---------------------------------------------------------------------------
# the article and its PDF
# ---------------------------------------------------------------------------

def document_text(scene, options, results):
    """notes.tex: the article of the sections' LaTeX, in the scene's order."""
    body = "\n\n".join(results[s]["tex"].rstrip("\n") for s in options["sections"])
    return render("notes", options, babel=LANGUAGES[options["language"]],
                  scene=plain(scene.name), description=plain(scene.description or ""), body=body,
                  references="references" in options["sections"])


def assemble(scene, options, results):
    """{file: text or bytes}: notes.tex, the figures it includes, and notes.pdf (compiled
    here where TeX is installed; otherwise a :class:`pendulab.io.Kept` of the built one)."""
    files = {}
    for section in options["sections"]:
        files.update(results[section]["files"])
    files["notes.tex"] = document_text(scene, options, results)
    if options["pdf"]:
        from pendulab.io import Kept
        engine = tex_engine()
        if engine is None:
            files["notes.pdf"] = Kept(
                "notes.pdf", inputs=sorted(files), product="notes",
                reason="neither pdflatex nor latexmk is installed: notes.tex is written")
        else:
            files["notes.pdf"] = compile_pdf(files, engine)
    return files


def produce(ctx, options):
    """{file: text or bytes}: every section in order, assembled."""
    return assemble(ctx.scene, options, {s: produce_part(ctx, options, s) for s in parts(options)})


def can_make(name):
    """Whether this machine can make file ``name`` of the product (notes.pdf needs TeX)."""
    return name != "notes.pdf" or tex_engine() is not None


def tex_engine():
    """"latexmk" or "pdflatex", whichever is installed (latexmk first), or None."""
    import shutil
    for name in ("latexmk", "pdflatex"):
        if shutil.which(name) and (name == "pdflatex" or shutil.which("pdflatex")):
            return name
    return None


#: Fixed time for the PDF's dates (SOURCE_DATE_EPOCH; 2000-01-01 00:00 UTC), so that the
#: bytes do not depend on when the notes were compiled.
EPOCH = "946684800"


def compile_pdf(files, engine="pdflatex"):
    """The bytes of notes.pdf compiled from ``files`` (notes.tex and its figures) in a
    temporary directory: latexmk, or pdflatex twice, so that references resolve.

    Reproducible: SOURCE_DATE_EPOCH and FORCE_SOURCE_DATE fix every date pdfTeX writes,
    and the preamble fixes the trailer ID and drops the pdfTeX file-name keys.  A LaTeX
    error is one InputError with the first error line of the log.
    """
    import os
    import subprocess
    import tempfile
    env = dict(os.environ, SOURCE_DATE_EPOCH=EPOCH, FORCE_SOURCE_DATE="1", TZ="UTC")
    with tempfile.TemporaryDirectory(prefix="pendulab-notes-") as tmp:
        for name, data in files.items():
            mode = "wb" if isinstance(data, bytes) else "w"
            with open(os.path.join(tmp, name), mode, **({} if mode == "wb" else {"encoding": "utf-8"})) as f:
                f.write(data)
        base = ["-interaction=nonstopmode", "-halt-on-error", "-file-line-error"]
        if engine == "latexmk":
            runs = [["latexmk", "-pdf", "-quiet", "-silent",
                     "-pdflatex=pdflatex " + " ".join(base) + " %O %S", "notes.tex"]]
        else:
            runs = [["pdflatex", *base, "notes.tex"]] * 2
        for cmd in runs:
            try:
                done = subprocess.run(cmd, cwd=tmp, env=env, stdin=subprocess.DEVNULL,
                                      capture_output=True, timeout=300)
            except subprocess.TimeoutExpired:
                raise InputError(f"{cmd[0]} took more than 300 s on notes.tex") from None
            if done.returncode != 0:
                raise InputError(f"{cmd[0]} failed on notes.tex: {_first_error(tmp)}")
        unresolved = _unresolved(tmp)
        if unresolved:
            raise InputError(f"notes.tex has {unresolved} after {engine}'s last run")
        with open(os.path.join(tmp, "notes.pdf"), "rb") as f:
            return f.read()


def _log(directory):
    """The text of notes.log in ``directory`` (None where pdfTeX wrote none)."""
    import os
    try:
        with open(os.path.join(directory, "notes.log"), encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return None


def _unresolved(directory):
    """"undefined references" or "undefined citations" where the log of notes.tex says so, else ""."""
    log = _log(directory) or ""
    found = [kind for kind, mark in (("undefined references", "LaTeX Warning: Reference"),
                                     ("undefined citations", "LaTeX Warning: Citation"))
             if mark in log]
    return " and ".join(found)


def _first_error(directory):
    """The first error line of notes.log in ``directory``."""
    import re
    log = _log(directory)
    if log is None:
        return "no log written"
    for line in log.splitlines():
        if line.startswith("!") or re.match(r"\S*\.tex:\d+: ", line):
            return line.strip()[:200]
    return "see its log"
