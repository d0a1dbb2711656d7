"""The layout of the experiments and motion figures: no text outside the figure, no two texts on
top of each other.

The figures use fixed margins (pendulab.figures.margins) instead of tight_layout, so nothing
moves a text that grows (a longer title, a wider tick label) back inside the page; these tests
draw each figure as its PNG is drawn and measure every text that is drawn.
"""

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


def _drawn_texts(monkeypatch):
    """Patch pendulab.figures.save: before each figure is saved, draw it at the PNG's dpi and
    record (name of the figure, [(text, bounding box in pixels)], figure box) for every text
    matplotlib draws (visible, not empty, inside the view limits for tick labels)."""
    import matplotlib.text
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pendulab import figures

    real_save = figures.save
    found = []

    def save(fig, dpi=150):
        texts = []
        real_draw = matplotlib.text.Text.draw

        def draw(self, renderer):
            real_draw(self, renderer)
            if self.get_visible() and self.get_text():
                texts.append((self.get_text(), self.get_window_extent(renderer)))

        fig.set_dpi(dpi)
        monkeypatch.setattr(matplotlib.text.Text, "draw", draw)
        try:
            FigureCanvasAgg(fig).draw()
        finally:
            monkeypatch.setattr(matplotlib.text.Text, "draw", real_draw)
        found.append((texts, fig.bbox.frozen()))
        return real_save(fig, dpi=dpi)

    monkeypatch.setattr(figures, "save", save)
    return found


def _check(found, expected):
    assert len(found) == expected
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


def _build(tmp_path, text):
    from pendulab.build import build
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "scene.toml").write_text(text)
    build(tmp_path / "s", tmp_path / "g", force=True, log=lambda m: None, jobs=1)


@pytest.mark.slow
def test_experiments_figures_keep_every_text_inside_and_apart(tmp_path, monkeypatch):
    found = _drawn_texts(monkeypatch)
    _build(tmp_path, EXPERIMENTS.format(drive="", more=""))
    _check(found, 3)  # the map, Fig. 5, Fig. 2


@pytest.mark.filterwarnings("ignore::pendulab.errors.AccuracyWarning")  # cells on a/l = 0, w = 0
def test_hill_drive_map_keeps_its_longer_title_inside(tmp_path, monkeypatch):
    found = _drawn_texts(monkeypatch)
    _build(tmp_path, EXPERIMENTS.format(drive='drive = "a*cos(omega*t) + a*cos(2*omega*t)"',
                                        more='criteria = ["bounded", "floquet"]\nfig5 = false\nfig2 = false'))
    _check(found, 1)
    titles = [t for t, _ in found[0][0] if "monodromy" in t]
    assert titles, "the Hill drive's map title names the monodromy matrix"


@pytest.mark.parametrize("length, t_end, more, figures", [
    ("L0 + v0*t", "20.0", "", 2),
    ("L0*(1 + eps*sin(Omega*t))", "10.0", "values = {eps = 0.05, Omega = 6.26}", 1),
])
def test_motion_figures_keep_every_text_inside_and_apart(tmp_path, monkeypatch, length, t_end, more,
                                                          figures):
    found = _drawn_texts(monkeypatch)
    _build(tmp_path, MOTION.format(length=length, t_end=t_end, more=more))
    _check(found, figures)
