"""Figures as deterministic PNG and PDF bytes (the products ``motion`` and ``experiments``).

matplotlib writes the date and its own version into PNG and PDF metadata;
:func:`save` leaves them out, so the same figure gives the same bytes on every
run (``pendulab build`` must reproduce generated/ byte for byte).

* :func:`pyplot` - (matplotlib, matplotlib.pyplot) on the Agg backend, or a
  one-line :class:`~pendulab.errors.InputError` naming the product when
  matplotlib (the "figures" extra) is not installed;
* :func:`save` - {".png": bytes, ".pdf": bytes} of a figure at ``dpi``, drawn once for both;
* :func:`png` - the PNG alone (RGB when the figure is opaque);
* :func:`collector_paused` - a figure function run with the garbage collector paused;
* :func:`margins` - fixed margins in inches in place of ``tight_layout``;
* :func:`unicode_expr`, :func:`power_of_ten` - labels in plain Unicode text
  (DejaVu Sans has the glyphs), which matplotlib draws without its mathtext
  parser (a parse per label and dpi, PNG and PDF).

>>> matplotlib, plt = pyplot("demo")
>>> fig, ax = plt.subplots()
>>> _ = ax.plot([0, 1], [1, 0])
>>> first, second = save(fig), save(fig)
>>> plt.close(fig)
>>> first == second, first[".png"][:4], first[".pdf"][:5]
(True, b'\\x89PNG', b'%PDF-')
"""

from pendulab.errors import InputError

#: metadata keys matplotlib fills with a date or its version, removed (None) on save (the PNG,
#: written by :func:`png`, has no text chunks at all)
PDF_METADATA = {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None}


def pyplot(what):
    """(matplotlib, matplotlib.pyplot) with the Agg backend; ``what`` names the product."""
    try:
        import matplotlib
    except ImportError:
        raise InputError(f"the {what} figures need matplotlib: pip install 'pendulab[figures]' "
                         "(or set figures = false)") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401  (matplotlib.ticker for the callers)
    return matplotlib, plt


def collector_paused(function):
    """``function`` run with Python's cyclic garbage collector paused (as it was after).

    A figure is tens of thousands of short-lived matplotlib objects (artists, transforms,
    ticks); each automatic collection on the way walks every object of the process, SymPy's
    and the build's too, and frees nothing of the figure, which lives until it is closed.
    The figure functions of the products are wrapped in it (and :func:`save` pauses it too).
    """
    import functools
    import gc

    @functools.wraps(function)
    def paused(*args, **kwargs):
        collecting = gc.isenabled()
        gc.disable()
        try:
            return function(*args, **kwargs)
        finally:
            if collecting:
                gc.enable()
    return paused


#: savefig settings pinned while a product's figure is saved, whatever a matplotlibrc says:
#: the figure as laid out (no tight box, which would also draw it twice), opaque, in its colours
SAVEFIG_RC = {"savefig.bbox": "standard", "savefig.transparent": False,
              "savefig.facecolor": "auto", "savefig.edgecolor": "auto"}


@collector_paused
def save(fig, dpi=150):
    """{".png": bytes, ".pdf": bytes} of ``fig`` (PNG at ``dpi``), no dates or versions inside.

    The figure is drawn once for both files (:class:`_DrawnTwice`): every call of the PDF's
    renderer is also made on an Agg canvas at ``dpi``, whose pixels become the PNG.  A figure
    with something the PNG would need its own drawing for (an image, a collection, mathtext,
    rasterised parts) is drawn a second time for the PNG (:func:`png`).  Python's cyclic
    garbage collector is paused meanwhile (:func:`collector_paused`): matplotlib makes tens
    of thousands of short-lived objects per figure, and each collection walks every object of
    the process (SymPy's too).
    """
    import io
    # an axis with no label text: matplotlib would still place its (empty) label below or
    # beside the tick labels, measuring them once more; nothing of it is drawn
    unlabelled = [axis for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
                  if axis._autolabelpos and not axis.label.get_text()]
    try:
        for axis in unlabelled:
            axis._autolabelpos = False
        buf = io.BytesIO()
        import matplotlib
        with _shared_font_subsets(), _DrawnTwice(fig, dpi) as both, _fonttools_quiet(), \
                matplotlib.rc_context({"pdf.compression": PDF_COMPRESS_LEVEL, **SAVEFIG_RC}):
            fig.savefig(buf, format="pdf", metadata=PDF_METADATA)
        return {".png": both.png() if both.complete else png(fig, dpi), ".pdf": buf.getvalue()}
    finally:
        for axis in unlabelled:
            axis._autolabelpos = True


class _fonttools_quiet:
    """fontTools' warnings silenced while a PDF embeds font subsets: the Computer Modern fonts
    that matplotlib ships carry creation dates before 1970, which fontTools reports on every
    subset ("timestamp seems very low") and then reads correctly."""

    def __enter__(self):
        import logging
        self.logger = logging.getLogger("fontTools")
        self.level = self.logger.level
        self.logger.setLevel(logging.ERROR)

    def __exit__(self, *exc):
        self.logger.setLevel(self.level)


#: zlib level of the PNG files: 3 writes them in about two thirds of the time of Pillow's
#: default (6), for files about 6 % larger
PNG_COMPRESS_LEVEL = 3
#: zlib level of the PDFs' streams (matplotlib's default 6): the paths of a dense figure are
#: compressed in about half the time, for files about 8 % larger
PDF_COMPRESS_LEVEL = 3


def png(fig, dpi=150):
    """PNG bytes of ``fig`` at ``dpi``: the pixels matplotlib's Agg canvas draws (as
    ``savefig`` draws them), written by Pillow with no text chunks.

    An opaque figure (every pixel's alpha 255, as the products' white ones) is written as RGB,
    not RGBA: a quarter fewer bytes to compress (about a third less time) and a smaller file.

    >>> import io
    >>> from PIL import Image
    >>> matplotlib, plt = pyplot("demo")
    >>> fig = plt.figure(figsize=(2, 1))
    >>> image = Image.open(io.BytesIO(png(fig, dpi=50)))
    >>> plt.close(fig)
    >>> image.mode, image.size, round(image.info["dpi"][0]), image.getpixel((0, 0))
    ('RGB', (100, 50), 50, (255, 255, 255))
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    before = fig.dpi
    fig.dpi = dpi
    try:
        canvas.draw()
        return _png_bytes(canvas.buffer_rgba(), dpi)
    finally:
        fig.dpi = before


def _png_bytes(buffer, dpi):
    """A PNG file of an Agg canvas' RGBA ``buffer`` (RGB when opaque), no text chunks."""
    import io

    from PIL import Image
    height, width = buffer.shape[:2]
    image = Image.frombuffer("RGBA", (width, height), buffer, "raw", "RGBA", 0, 1)
    if image.getextrema()[3][0] == 255:  # opaque
        image = image.convert("RGB")
    out = io.BytesIO()
    image.save(out, format="png", dpi=(dpi, dpi), compress_level=PNG_COMPRESS_LEVEL)
    return out.getvalue()


_NONE = object()


class _DrawnTwice:
    """While a figure is saved as PDF: each of its drawing calls also drawn on an Agg canvas.

    matplotlib draws a figure once per file, and most of a drawing's time is Python's: tick
    locators and formatters, text layout, transforms, artist by artist.  The PDF's renderer
    (72 units to the inch) is wrapped here in :class:`_Both`, which makes every call also on a
    RendererAgg at ``dpi``, its coordinates scaled by dpi/72: the figure's transforms are
    linear in its dpi, and line widths, dashes and font sizes stay in points for both.  Only
    the texts' metrics differ: the layout (alignment, the legends' and labels' places) is the
    PDF's, so a text of the PNG may sit a few pixels (up to 3 in the products) from where a
    drawing of its own would put it.  ``complete`` is False when the figure asked for
    something :class:`_Both` does not draw on the canvas; the caller then draws the PNG by
    itself.
    """

    def __init__(self, fig, dpi):
        self.fig, self.dpi = fig, dpi
        self.agg = None
        self.complete = False

    def __enter__(self):
        from matplotlib.backends.backend_agg import RendererAgg
        fig = self.fig
        width, height = fig.get_size_inches()
        self.agg = RendererAgg(width * self.dpi, height * self.dpi, self.dpi)
        self._own = fig.__dict__.get("draw", _NONE)  # an override of the figure's own
        draw = fig.draw
        drawn = []

        def both(renderer):
            tee = _Both(renderer, self.agg, self.dpi / 72.0)
            draw(tee)
            drawn.append(tee)
            # one drawing, complete, is the PNG; a second one (savefig measuring a tight
            # box first) would be drawn over it: then the PNG gets a drawing of its own
            self.complete = len(drawn) == 1 and not tee.missed

        # savefig's PDF backend calls figure.draw(renderer) once: this instance attribute
        # stands in for the method while the file is written
        fig.draw = both
        return self

    def __exit__(self, *exc):
        if self._own is _NONE:
            del self.fig.draw
        else:
            self.fig.draw = self._own
        return False

    def png(self):
        return _png_bytes(self.agg.buffer_rgba(), self.dpi)


class _Both:
    """A renderer that passes each call to the PDF's renderer and the drawing calls to an Agg
    renderer as well (see :class:`_DrawnTwice`); ``missed`` names a drawing call it could not
    repeat on the canvas (then the canvas is incomplete)."""

    #: calls that only the PDF gets; the canvas is then incomplete
    ALONE = ("draw_image", "draw_path_collection", "draw_quad_mesh", "draw_gouraud_triangles",
             "draw_gouraud_triangle", "draw_tex", "draw_mathtext", "start_rasterizing",
             "start_filter")

    def __init__(self, pdf, agg, scale):
        from matplotlib.transforms import Affine2D
        self._pdf, self._agg, self._s = pdf, agg, scale
        self._scale = Affine2D().scale(scale)
        self._raster_depth, self._rasterizing = 0, False
        self.missed = None

    def __getattr__(self, name):
        if name in _Both.ALONE:
            self.missed = self.missed or name
        return getattr(self._pdf, name)

    def _gc(self, gc):
        """A copy of ``gc`` for the canvas: its clip rectangle and path scaled."""
        from matplotlib.backend_bases import GraphicsContextBase
        from matplotlib.transforms import TransformedPath
        out = GraphicsContextBase()
        out.copy_properties(gc)
        rect = gc.get_clip_rectangle()
        if rect is not None:
            out.set_clip_rectangle(rect.transformed(self._scale))
        path, affine = gc.get_clip_path()
        if path is not None:
            out.set_clip_path(TransformedPath(path, affine + self._scale))
        return out

    def draw_path(self, gc, path, transform, rgbFace=None):  # noqa: N803 (matplotlib's name)
        self._pdf.draw_path(gc, path, transform, rgbFace)
        self._agg.draw_path(self._gc(gc), path, transform + self._scale, rgbFace)

    def draw_markers(self, gc, marker_path, marker_trans, path, trans, rgbFace=None):  # noqa: N803
        self._pdf.draw_markers(gc, marker_path, marker_trans, path, trans, rgbFace)
        self._agg.draw_markers(self._gc(gc), marker_path, marker_trans + self._scale, path,
                               trans + self._scale, rgbFace)

    def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        self._pdf.draw_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        if ismath:
            self.missed = self.missed or "mathtext"
            return
        # the PDF's y is upwards, Agg's text y downwards (RendererAgg.flipy)
        self._agg.draw_text(self._gc(gc), x * self._s, self._agg.height - y * self._s, s, prop,
                            angle, ismath=False, mtext=mtext)


def margins(fig, left, right, bottom, top, wspace=0.0, hspace=0.0):
    """fig.subplots_adjust from margins and gaps in inches (the figure's own size).

    In place of ``tight_layout``, which measures every text twice more (about
    0.07 s for a 2 x 2 figure and slower saves after it): the margins are
    fixed for the font sizes of the products' rc settings.
    """
    w, h = fig.get_size_inches()
    gs = fig.axes[0].get_subplotspec().get_gridspec()
    nrow, ncol = gs.get_geometry()
    aw = (w - left - right - wspace * (ncol - 1)) / ncol
    ah = (h - bottom - top - hspace * (nrow - 1)) / nrow
    fig.subplots_adjust(left=left / w, right=1 - right / w, bottom=bottom / h, top=1 - top / h,
                        wspace=wspace / aw, hspace=hspace / ah)


#: digits and signs to superscripts
SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")


def unicode_expr(expr):
    """A SymPy expression on one line of Unicode text for a figure label.

    Symbols as SymPy's pretty printer names them (subscripts, Greek letters),
    products with a middle dot, integer powers as superscripts, square roots
    with a radical sign, other powers with a caret, and the true minus sign.

    >>> import sympy as sp
    >>> unicode_expr(sp.sympify("L0 + v0*t"))
    'L₀ + t·v₀'
    >>> unicode_expr(sp.sympify("L0*(1 + eps*sin(Omega*t))"))
    'L₀·(eps·sin(Ω·t) + 1)'
    >>> unicode_expr(sp.sympify("sqrt(L0**2 - a*t**3/2)"))
    '√(L₀² − a·t³/2)'
    >>> unicode_expr(sp.sympify("L0*(1 + t/T)**(-3/4)"))
    'L₀/(1 + t/T)^(3/4)'
    """
    from sympy.printing.pretty.pretty_symbology import pretty_use_unicode
    # pretty_symbol answers in ASCII unless unicode is switched on (SymPy switches it by the
    # encoding of sys.stdout): on for this call only, the same text everywhere
    before = pretty_use_unicode(True)
    try:
        return _unicode_printer().doprint(expr).replace("-", "\u2212")
    finally:
        pretty_use_unicode(before)


def _unicode_printer():
    from sympy import S
    from sympy.printing.precedence import PRECEDENCE
    from sympy.printing.pretty.pretty_symbology import pretty_symbol
    from sympy.printing.str import StrPrinter

    class UnicodePrinter(StrPrinter):
        def _print_Symbol(self, expr):
            return pretty_symbol(expr.name)

        def _print_Mul(self, expr):
            return super()._print_Mul(expr).replace("*", "·")

        def _print_Pow(self, expr, rational=False):
            base, exp = expr.as_base_exp()
            if exp is S.Half:
                return f"√({self._print(base)})"
            if exp.is_Integer and exp > 0 or exp.is_Integer and not base.is_Atom:
                return self.parenthesize(base, PRECEDENCE["Pow"], strict=False) + \
                    str(exp).translate(SUPERSCRIPT)
            if exp.is_Integer or exp.is_Rational and exp < 0:
                return super()._print_Pow(expr, rational)
            return (self.parenthesize(base, PRECEDENCE["Pow"], strict=False) + "^"
                    + (self._print(exp) if exp.is_Atom and not exp.is_Rational else f"({self._print(exp)})"))

    return UnicodePrinter()


def power_of_ten(x, pos=None):
    """A tick label of a logarithmic axis, ``10⁻²``, in place of matplotlib's mathtext one.

    >>> power_of_ten(1e-18), power_of_ten(100.0), power_of_ten(1.0), power_of_ten(0.02)
    ('10⁻¹⁸', '10²', '10⁰', '0.02')
    """
    import math
    if x > 0:
        k = round(math.log10(x))
        if math.isclose(x, 10.0 ** k, rel_tol=1e-9):
            return "10" + str(k).translate(SUPERSCRIPT)
    return f"{x:g}".replace("-", "\u2212")


# ---------------------------------------------------------------------------
# PDF font subsets, made once per process
# ---------------------------------------------------------------------------

#: (font file, glyph indices) -> (bytes of the subset font, glyph index map)
_SUBSETS = {}
#: Subsets kept (a build's figures need a dozen or so).
MAX_SUBSETS = 256


#: Characters every embedded font subset holds besides those its figure draws: ASCII and the
#: Greek letters, sub- and superscripts and signs of the products' labels.  The figures of a
#: process then ask fontTools for the same subset again and again (one subset per font and
#: process instead of one per figure), at the price of some glyphs a figure does not use.
COMMON_CHARACTERS = ("".join(chr(c) for c in range(0x20, 0x7F))
                     + "θτωνπΩεΔμλ" "₀₁₂₃₄₅₆₇₈₉" "⁰¹²³⁴⁵⁶⁷⁸⁹⁻" "−±×·⟨⟩′²")

#: Glyphs by name besides: the ligatures matplotlib's text layout puts in place of "fi", "fl".
COMMON_GLYPH_NAMES = ("fi", "fl")

#: font file -> frozenset of the glyph indices of COMMON_CHARACTERS and COMMON_GLYPH_NAMES in it
_COMMON = {}


def _common_glyphs(fontfile):
    """The glyph indices of :data:`COMMON_CHARACTERS` and :data:`COMMON_GLYPH_NAMES` that
    ``fontfile`` has (those it lacks, index 0, left out)."""
    hit = _COMMON.get(fontfile)
    if hit is None:
        from matplotlib.font_manager import get_font
        font = get_font(fontfile)
        glyphs = [font.get_char_index(ord(c)) for c in COMMON_CHARACTERS]
        glyphs += [font.get_name_index(n) for n in COMMON_GLYPH_NAMES]
        hit = _COMMON[fontfile] = frozenset(g for g in glyphs if g)
    return hit


#: Tables left out of the embedded subsets: those a text-shaping engine reads (a PDF places
#: every glyph itself, by the positions in its content stream) and font editors' own tables.
#: fontTools then neither reads nor prunes DejaVu Sans' large GSUB and GPOS tables: a subset
#: costs a third of the time, and the file is 4 kB smaller.
LEFT_OUT_TABLES = ("GSUB", "GPOS", "GDEF", "BASE", "JSTF", "kern", "kerx", "morx", "feat",
                   "trak", "FFTM", "PfEd", "meta")


def _lean_subset(fontfile, glyphs):
    """(bytes, glyph index map) of the subset of ``fontfile`` (matplotlib's font path, with
    its face index) holding ``glyphs``, as matplotlib's own subset but without
    :data:`LEFT_OUT_TABLES`: each glyph's outline and metrics, names and the character map."""
    import io

    from fontTools import subset
    options = subset.Options(glyph_names=True, recommended_glyphs=True)
    options.drop_tables += [t for t in LEFT_OUT_TABLES if t not in options.drop_tables]
    options.font_number = getattr(fontfile, "face_index", 0)
    font = subset.load_font(fontfile, options)
    try:
        subsetter = subset.Subsetter(options=options)
        subsetter.populate(gids=glyphs)
        subsetter.subset(font)
        out = io.BytesIO()
        font.save(out, reorderTables=False)
        return out.getvalue(), dict(subsetter.glyph_index_map)
    finally:
        font.close()


class _SavedFont:
    """Stands for the subset TTFont where matplotlib's PDF backend only saves it to a file."""

    def __init__(self, data):
        self._data = data

    def save(self, file, reorderTables=False):  # noqa: N803 (fontTools' name)
        file.write(self._data)


class _SavedSubset:
    def __init__(self, data, glyph_index_map):
        self.font = _SavedFont(data)
        self.glyph_index_map = dict(glyph_index_map)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


class _shared_font_subsets:
    """While a PDF is written: each (font, glyph set) is subset by fontTools once per process.

    matplotlib embeds every font of a PDF (Type 42) as a subset made by
    fontTools (``matplotlib.backends._backend_pdf_ps.get_glyphs_subset``),
    which reads and prunes the whole font file again for each figure, about
    0.07 s per font.  Inside this context manager the glyphs asked for are
    joined with those of :data:`COMMON_CHARACTERS`, so that the figures of a
    process, whose labels differ in a few characters, ask for the same glyph
    set; the subset is made the first time (:func:`_lean_subset`, without
    the text-shaping tables) and its bytes are given back afterwards: the same
    bytes, since fontTools' subset is a function of the font and the glyphs.
    The PDF still maps each character it shows to its glyph (matplotlib's
    CIDToGIDMap from the subset's glyph index map) and lists only those.
    Outside it (or with a matplotlib without these functions) nothing changes.
    """

    def __enter__(self):
        try:
            from matplotlib.backends import _backend_pdf_ps as pdf_ps
        except ImportError:
            pdf_ps = None
        self._module = pdf_ps
        self._real = getattr(pdf_ps, "get_glyphs_subset", None)
        if self._real is None or not hasattr(pdf_ps, "font_as_file"):
            self._module = None
            return self
        real = self._real

        def get_glyphs_subset(fontfile, glyphs):
            try:
                glyphs = frozenset(glyphs) | _common_glyphs(fontfile)
                key = (fontfile, glyphs)
                hit = _SUBSETS.get(key)
            except TypeError:  # an unhashable font file object: no sharing
                return real(fontfile, glyphs)
            if hit is None:
                hit = _lean_subset(fontfile, glyphs)
                if len(_SUBSETS) >= MAX_SUBSETS:
                    _SUBSETS.clear()
                _SUBSETS[key] = hit
            return _SavedSubset(*hit)

        pdf_ps.get_glyphs_subset = get_glyphs_subset
        return self

    def __exit__(self, *exc):
        if self._module is not None:
            self._module.get_glyphs_subset = self._real
        return False
