"""The build pipeline: stages computed lazily, products asked for by name.

A scene names products; each product module (``pendulab.products.<name>``)
asks the :class:`Context` for the stages it needs with ``ctx.get(name)``.  A
stage runs at most once per build and only when some product asks for it, so
a scene that wants only the equations never imports the series or Floquet
code.  ``ctx.ran`` records which stages ran (tests use it).

Stages (ARCHITECTURE.md): system -> equations -> canonical -> closed_form.
Analyses that are not part of a scene's equations (series, Floquet,
averaging) are called by their products directly.
"""

import importlib

from pendulab.errors import InputError, PendulabError

#: product name -> module that defines OPTIONS, SYSTEMS and produce(ctx, options)
PRODUCTS = {
    "equations": "pendulab.products.equations",
    "series": "pendulab.products.series",
    "floquet": "pendulab.products.floquet",
    "stability": "pendulab.products.stability",
    "quarter_periods": "pendulab.products.quarter_periods",
    "bessel": "pendulab.products.bessel",
    "motion": "pendulab.products.motion",
    "kernels": "pendulab.products.kernels",
    "experiments": "pendulab.products.experiments",
    "notes": "pendulab.products.notes",
    "animation": "pendulab.products.animation",
}


def product_module(name):
    """Import the module of product ``name`` (only when the product is used)."""
    if name not in PRODUCTS:
        raise InputError(f"unknown product {name!r} (known: {', '.join(sorted(PRODUCTS))})")
    return importlib.import_module(PRODUCTS[name])


def _stage_system(ctx):
    from pendulab.systems import DrivenPivot, VariableLength
    p = dict(ctx.scene.parameters)
    if ctx.scene.system == "kapitza":
        kwargs = {"body": p.get("body", "rod"), "angle": p.get("angle", "up")}
        if "drive" in p:
            kwargs["drive"] = p["drive"]
        if "inertia" in p:
            kwargs["inertia_value"] = p["inertia"]
        return DrivenPivot(**kwargs)
    kwargs = {}
    if "length" in p:
        kwargs["length"] = p["length"]
    if "mass" in p:
        kwargs["mass"] = p["mass"]
    return VariableLength(**kwargs)


def _stage_equations(ctx):
    from pendulab.equations import derive
    return derive(ctx.get("system"))


#: Canonical forms computed in this process, by derivation key (see _stage_canonical).
_CANONICAL = {}


def _stage_canonical(ctx):
    """The canonical form; shared by the scenes whose equations are the same derivation."""
    return canonical_form(ctx.get("equations"))


def canonical_form(equations):
    """The canonical form of ``equations``, formed once per derivation in this process.

    :func:`pendulab.canonical.periodic_form` for the driven pivot,
    :func:`pendulab.canonical.length_form` for the variable length.  The
    equations depend only on the derivation key of the system
    (:func:`pendulab.equations.derivation_key`: drive and angle, or length and
    mass), and the canonical form only on the equations, so a build that has
    a rod and a point mass with one drive forms it once, and the analyses that
    need the source's drive with a symbolic I (``stability.body_map``,
    ``phelps_hunter``, the sweeps) take the same one.
    """
    from pendulab import canonical
    from pendulab.equations import MAX_CACHED, derivation_key
    from pendulab.systems import DrivenPivot
    key = derivation_key(equations.system)
    if key not in _CANONICAL:
        if isinstance(equations.system, DrivenPivot):
            form = canonical.periodic_form(equations)
        else:
            form = canonical.length_form(equations)
        if len(_CANONICAL) >= MAX_CACHED:
            _CANONICAL.pop(next(iter(_CANONICAL)))
        _CANONICAL[key] = form
    return _CANONICAL[key]


def _stage_closed_form(ctx):
    if ctx.scene.system != "variable-length":
        return None
    form = ctx.get("canonical")
    if form is None or form.alpha is None:
        return None
    from pendulab.analyses.bessel import closed_form
    return closed_form(form, ctx.get("system").length)


STAGES = {
    "system": _stage_system,
    "equations": _stage_equations,
    "canonical": _stage_canonical,
    "closed_form": _stage_closed_form,
}


class Context:
    """Lazily computed stages of one scene.

    ``memo`` is a scratch dict for the products of the scene: what two parts of
    one product both need (see :func:`run_part`) is computed once per process.
    """

    def __init__(self, scene):
        self.scene = scene
        self._values = {}
        self.ran = []
        self.memo = {}

    def get(self, name):
        if name not in STAGES:
            raise InputError(f"unknown stage {name!r}")
        if name not in self._values:
            self._values[name] = STAGES[name](self)
            self.ran.append(name)
        return self._values[name]


# ---------------------------------------------------------------------------
# products, whole or in parts
# ---------------------------------------------------------------------------
#
# A product module defines ``produce(ctx, options) -> {file: text or bytes}``.
# A dear one may also define
#
#   parts(options)                          -> [part name, ...]   (no computation)
#   produce_part(ctx, options, part)        -> a picklable result
#   assemble(scene, options, {part: result}) -> {file: text or bytes}
#
# so that ``pendulab build`` can compute its parts in different processes; its
# ``produce`` must give the same files as assembling its parts computed in
# order (then the files cannot depend on where the parts ran).


def product_parts(name, options):
    """The part names of product ``name`` with ``options``; [None] for a product made whole."""
    parts = getattr(product_module(name), "parts", None)
    return [None] if parts is None else list(parts(options))


def run_part(ctx, name, part):
    """The result of one part of product ``name`` of ``ctx.scene`` (part None: the whole
    product's {file: text}); an error carries the product's name."""
    module = product_module(name)
    options = ctx.scene.products[name]
    try:
        if part is None:
            return module.produce(ctx, options)
        return module.produce_part(ctx, options, part)
    except PendulabError as exc:
        exc.product = name  # pendulab.build names it in the one-line error
        raise


def finish_product(scene, name, results):
    """{file: text} of product ``name`` from {part: result} of every one of its parts."""
    if list(results) == [None]:
        return results[None]
    try:
        return product_module(name).assemble(scene, scene.products[name], results)
    except PendulabError as exc:
        exc.product = name
        raise


def run_product(ctx, name):
    """{file: text} of the product ``name`` of ``ctx.scene`` (its stages from ``ctx``)."""
    return run_part(ctx, name, None)


def add_files(files, name, produced):
    """Add the {file: text} that product ``name`` ``produced`` to ``files``; an InputError
    when one of them is already there (another product wrote it) or is the manifest."""
    for fname, text in produced.items():
        if fname in files or fname == "manifest.json":
            raise InputError(f"product {name!r} writes {fname!r}, which another product writes")
        files[fname] = text


def merge_files(parts):
    """One {file: text} of the [(product name, {file: text})] of a scene, in that order
    (:func:`add_files` for each)."""
    files = {}
    for name, produced in parts:
        add_files(files, name, produced)
    return files


def run_products(scene):
    """Compute every product ``scene`` asks for; return ({file: text}, context)."""
    ctx = Context(scene)
    files = {}
    for name in sorted(scene.products):
        add_files(files, name, run_product(ctx, name))  # a clash stops before the next product
    return files, ctx
