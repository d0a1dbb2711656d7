"""The experiments and motion figures: no text outside the figure, no two texts on top of each
other, and every font of the PDFs embedded with the right glyphs.

The figures use fixed margins (pendulab.figures.margins) instead of tight_layout, so nothing
moves a text that grows (a longer title, a wider tick label) back inside the page; these tests
draw each figure as its PNG is drawn and measure every text that is drawn.  The PDFs' fonts
are subsets shared by the figures of a process (pendulab.figures.COMMON_CHARACTERS); the
tests read each PDF's fonts back and compare every character's glyph with the font file's.
"""

import io
import re
import warnings
import zlib

import pytest

pytest.importorskip("matplotlib")

EXPERIMENTS = """
name = "exp"
system = "kapitza"
[parameters]
body = "rod"
{drive}
[products.experiments]
grid = 6
periods = 10
steps_per_period = 40
maps = ["text"]
first_experiment = false
fig5_periods = 4
fig2_periods = 4
{more}
"""

MOTION = """
name = "vl"
system = "variable-length"
[parameters]
length = "{length}"
[products.motion]
t_end = {t_end}
points = 201
{more}
"""

SCENES = {
    "experiments": EXPERIMENTS.format(drive="", more=""),
    "hill": EXPERIMENTS.format(drive='drive = "a*cos(omega*t) + a*cos(2*omega*t)"',
                               more='criteria = ["bounded", "floquet"]\nfig5 = false\nfig2 = false'),
    "growing": MOTION.format(length="L0 + v0*t", t_end="20.0", more=""),
    "periodic": MOTION.format(length="L0*(1 + eps*sin(Omega*t))", t_end="10.0",
                              more="values = {eps = 0.05, Omega = 6.26}"),
}
#: figures each scene draws
FIGURES = {"experiments": 3, "hill": 1, "growing": 2, "periodic": 1}


def _recording_save(found):
    """A stand-in for pendulab.figures.save: before the figure is saved, it is drawn at the
    PNG's dpi and (texts, figure box) appended to ``found``: [(text, bounding box in pixels)]
    of every text matplotlib draws (visible, not empty, inside the view limits for tick labels)."""
    import matplotlib.text
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pendulab import figures
    real_save = figures.save

    def save(fig, dpi=150):
        texts = []
        real_draw = matplotlib.text.Text.draw

        def draw(self, renderer):
            real_draw(self, renderer)
            if self.get_visible() and self.get_text():
                texts.append((self.get_text(), self.get_window_extent(renderer)))

        fig.set_dpi(dpi)
        matplotlib.text.Text.draw = draw
        try:
            FigureCanvasAgg(fig).draw()
        finally:
            matplotlib.text.Text.draw = real_draw
        found.append((texts, fig.bbox.frozen()))
        return real_save(fig, dpi=dpi)

    return save


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """{scene: (recorded texts per figure, output directory, font subsets made)} of the SCENES,
    built once (each from no font subsets made)."""
    from pendulab import figures
    from pendulab.build import build
    from pendulab.errors import AccuracyWarning
    out = {}
    for name, text in SCENES.items():
        root = tmp_path_factory.mktemp(name)
        (root / "s").mkdir()
        (root / "s" / "scene.toml").write_text(text)
        found = []
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(figures, "save", _recording_save(found))
            mp.setattr(figures, "_SUBSETS", {})
            with warnings.catch_warnings():
                # the Hill drive's cells on a/l = 0 or omega0/omega = 0
                warnings.simplefilter("ignore", AccuracyWarning)
                build(root / "s", root / "g", force=True, log=lambda m: None, jobs=1)
            subsets = list(figures._SUBSETS)
        (scene_dir,) = [d for d in (root / "g").iterdir() if d.is_dir()]
        out[name] = (found, scene_dir, subsets)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(SCENES))
def test_every_text_inside_the_figure_and_apart(built, scene):
    found, _, _ = built[scene]
    assert len(found) == FIGURES[scene]
    for texts, box in found:
        assert texts
        for text, b in texts:
            # a whole pixel of slack: antialiased edges of a text that touches the border
            assert b.x0 >= box.x0 - 1 and b.x1 <= box.x1 + 1, f"{text!r} cut at the left or right"
            assert b.y0 >= box.y0 - 1 and b.y1 <= box.y1 + 1, f"{text!r} cut at the bottom or top"
        for i, (t1, b1) in enumerate(texts):
            for t2, b2 in texts[i + 1:]:
                overlap = min(b1.x1, b2.x1) - max(b1.x0, b2.x0), min(b1.y1, b2.y1) - max(b1.y0, b2.y0)
                assert min(overlap) <= 1, f"{t1!r} and {t2!r} overlap"


@pytest.mark.slow
def test_hill_drive_map_title_names_the_monodromy_matrix(built):
    (texts, _), = built["hill"][0]
    assert [t for t, _ in texts if "monodromy" in t]


# -- fonts -------------------------------------------------------------------------------

def _objects(pdf):
    return {int(m.group(1)): m.group(2) for m in re.finditer(rb"(\d+) 0 obj\n(.*?)endobj", pdf, re.S)}


def _stream(obj):
    data = obj.split(b"stream\n", 1)[1]
    return zlib.decompressobj().decompress(data) if b"/FlateDecode" in obj.split(b"stream\n")[0] else data


def _ref(obj, key):
    return int(re.search(rb"/" + key + rb" (\d+) 0 R", obj).group(1))


def _to_unicode(cmap):
    """{character code: text} of a ToUnicode CMap as matplotlib writes it (bfrange arrays)."""
    out = {}
    for start, _end, values in re.findall(rb"<([0-9a-f]+)> <([0-9a-f]+)> \[([^\]]*)\]", cmap):
        for k, v in enumerate(values.split()):
            out[int(start, 16) + k] = bytes.fromhex(v[1:-1].decode()).decode("utf-16be")
    return out


def _embedded_fonts(pdf):
    """[(kind, base font, {character: glyph name in the embedded font})] of a PDF's fonts."""
    from fontTools.ttLib import TTFont
    objs = _objects(pdf)
    fonts = []
    for obj in objs.values():
        head = obj.split(b"stream\n")[0]
        if b"/Subtype /CIDFontType2" in head:
            name = re.search(rb"/BaseFont /([^\s/]+)", head).group(1).decode()
            descriptor = objs[_ref(head, b"FontDescriptor")]
            font = TTFont(io.BytesIO(_stream(objs[_ref(descriptor, b"FontFile2")])))
            order = font.getGlyphOrder()
            gids = _stream(objs[_ref(head, b"CIDToGIDMap")])
            (parent,) = [o for o in objs.values() if re.search(
                rb"/DescendantFonts \[ %d 0 R \]" % next(k for k, v in objs.items() if v is obj), o)]
            chars = _to_unicode(_stream(objs[_ref(parent, b"ToUnicode")]))
            glyphs = {text: order[int.from_bytes(gids[2 * cid:2 * cid + 2], "big")]
                      for cid, text in chars.items()}
            fonts.append(("Type 42", name, glyphs))
        elif b"/Subtype /Type3" in head:
            name = re.search(rb"/BaseFont /([^\s/]+)", head).group(1).decode()
            procs = objs[_ref(head, b"CharProcs")]
            fonts.append(("Type 3", name, {n.decode(): n.decode()
                                           for n in re.findall(rb"/([^\s/]+) \d+ 0 R", procs)}))
        elif re.search(rb"/Type /Font[\s>]", head) and b"/Subtype /Type0" not in head:
            pytest.fail(f"a font that is not embedded: {head[:200]!r}")
    return fonts


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(SCENES))
def test_pdf_fonts_are_embedded_with_the_glyphs_of_their_characters(built, scene):
    from matplotlib import font_manager
    _, directory, _ = built[scene]
    pdfs = sorted(directory.glob("*.pdf"))
    assert len(pdfs) == FIGURES[scene]
    dejavu = font_manager.get_font(font_manager.findfont("DejaVu Sans"))
    for pdf in pdfs:
        fonts = _embedded_fonts(pdf.read_bytes())
        assert fonts, pdf.name
        for kind, name, glyphs in fonts:
            assert glyphs, (pdf.name, name)
            if kind == "Type 42" and name.endswith("+DejaVuSans"):
                # each character's glyph in the subset is the font file's glyph of that character
                for text, glyph in glyphs.items():
                    assert glyph == dejavu.get_glyph_name(dejavu.get_char_index(ord(text))), \
                        (pdf.name, text, glyph)


@pytest.mark.slow
def test_the_figures_of_a_product_share_one_subset_per_font(built):
    """The experiments' three PDFs (a map, Fig. 5, Fig. 2) ask fontTools for one subset of
    DejaVu Sans: the characters they draw are among pendulab.figures.COMMON_CHARACTERS."""
    _, _, subsets = built["experiments"]
    assert len(subsets) == 1 and subsets[0][0].endswith("DejaVuSans.ttf")
