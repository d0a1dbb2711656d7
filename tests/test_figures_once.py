"""pendulab.figures.save draws a figure once for its PDF and PNG (figures._DrawnTwice).

The reference is matplotlib's own drawing of the same figure: ``savefig`` to PDF (the same
bytes at the same zlib level: the PDF's renderer gets the same calls) and ``figures.png``, a separate drawing on an
Agg canvas at the PNG's dpi.  The canvas drawn alongside the PDF has the PDF's coordinates
scaled by dpi/72, so its lines and markers fall on the pixels of a drawing of its own (up to
a pixel where a coordinate lies on a pixel's edge: the two roads round differently), and its
texts are laid out with the PDF's metrics (a glyph a fraction of a pixel away).  A figure with
something the canvas is not given (mathtext, an image) is drawn a second time for its PNG.
"""

import io

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from pendulab import figures  # noqa: E402


def _pixels(data):
    from PIL import Image
    image = Image.open(io.BytesIO(data))
    return image.mode, np.asarray(image.convert("RGB")).astype(int)


def _within_one_pixel(a, b):
    """For each pixel of ``a`` (but the border): the least difference to a pixel of ``b``
    at most one pixel away."""
    h, w = a.shape[:2]
    best = None
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            d = np.abs(a[1:-1, 1:-1] - b[1 + dy:h - 1 + dy, 1 + dx:w - 1 + dx]).max(axis=2)
            best = d if best is None else np.minimum(best, d)
    return best


def _figure(plt, text=True, margins=(0.62, 0.14, 0.48, 0.3)):
    fig, axes = plt.subplots(1, 2, figsize=(5.0, 2.6), sharey=True)
    t = np.linspace(0.0, 7.0, 300)
    for k, ax in enumerate(axes):
        ax.plot(t, np.sin(t + k), "-", color="C3", lw=1.0, label="sin")
        ax.plot(t[::25], np.cos(t[::25]), "o", mfc="none", mec="k", ms=4, mew=0.6)
        ax.plot(t, 0.5 * np.cos(2 * t), "--", color="C0", lw=1.2)
        ax.axhspan(-0.2, 0.1, color="0.85", zorder=0)
        if text:
            ax.set_title(f"panel {k}: θ(0) = 0.1")
            ax.set_xlabel("τ")
        else:
            ax.set_xticks([])
            ax.set_yticks([])
    if text:
        axes[0].set_ylabel("ω₀/ω")
        axes[0].legend(loc="upper left", frameon=False)
    figures.margins(fig, *margins, wspace=0.3)
    return fig


@pytest.mark.parametrize("dpi", [150, 100])
def test_lines_and_markers_on_the_pixels_of_a_drawing_of_their_own(dpi):
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt, text=False)
    try:
        saved = figures.save(fig, dpi=dpi)
        alone = figures.png(fig, dpi=dpi)
        buf = io.BytesIO()
        with matplotlib.rc_context({"pdf.compression": figures.PDF_COMPRESS_LEVEL}):
            fig.savefig(buf, format="pdf", metadata=figures.PDF_METADATA)
    finally:
        plt.close(fig)
    assert saved[".pdf"] == buf.getvalue()
    (mode1, once), (mode2, own) = _pixels(saved[".png"]), _pixels(alone)
    assert mode1 == mode2 == "RGB" and once.shape == own.shape == (round(2.6 * dpi), 5 * dpi, 3)
    assert (once != own).any(axis=2).mean() < 0.01      # nearly all pixels the same
    assert _within_one_pixel(once, own).max() <= 8      # the others a pixel away
    assert _within_one_pixel(own, once).max() <= 8


def test_texts_where_a_drawing_of_their_own_puts_them():
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    try:
        saved = figures.save(fig)
        alone = figures.png(fig)
    finally:
        plt.close(fig)
    (_, once), (_, own) = _pixels(saved[".png"]), _pixels(alone)
    assert (once != own).any(axis=2).mean() < 0.05
    # glyphs a fraction of a pixel apart: their antialiased edges differ, whole glyphs do not
    near = _within_one_pixel(once, own)
    assert (near > 64).mean() < 0.005
    # in blocks of 6 x 6 pixels (a glyph's size) the ink is the same to a few percent
    h, w = (s // 6 * 6 for s in once.shape[:2])
    blocks = [x[:h, :w].reshape(h // 6, 6, w // 6, 6, 3).mean(axis=(1, 3)) for x in (once, own)]
    assert np.abs(blocks[0] - blocks[1]).max() < 48


def test_a_text_moved_by_a_pixel_fails_the_comparison():
    # the tests above can fail: the same figure with its margins moved by one pixel
    matplotlib, plt = figures.pyplot("test")
    figs = [_figure(plt), _figure(plt, margins=(0.62 + 1 / 150, 0.14 - 1 / 150, 0.48, 0.3))]
    try:
        (_, a), (_, b) = (_pixels(figures.png(f)) for f in figs)
    finally:
        for f in figs:
            plt.close(f)
    assert (a != b).any(axis=2).mean() > 0.005


@pytest.mark.parametrize("extra", ["mathtext", "image"])
def test_what_the_canvas_is_not_given_is_drawn_again(extra):
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    if extra == "mathtext":
        fig.axes[1].set_xlabel(r"$\omega_0/\omega$")
    else:
        fig.axes[1].imshow(np.arange(12.0).reshape(3, 4), extent=(0, 7, -1, 1), aspect="auto")
    try:
        with figures._DrawnTwice(fig, 150) as both:
            fig.savefig(io.BytesIO(), format="pdf", metadata=figures.PDF_METADATA)
        assert not both.complete
        saved = figures.save(fig)
        alone = figures.png(fig)
    finally:
        plt.close(fig)
    assert saved[".png"] == alone
    assert "draw" not in fig.__dict__  # the figure's own draw method again


def test_saving_leaves_the_garbage_collector_as_it_was():
    import gc
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    try:
        assert gc.isenabled()
        figures.save(fig)
        assert gc.isenabled()
        gc.disable()
        try:
            figures.save(fig)
            assert not gc.isenabled()
        finally:
            gc.enable()
    finally:
        plt.close(fig)


def test_figure_functions_run_with_the_collector_paused():
    import gc

    from pendulab.products import experiments, motion, stability

    @figures.collector_paused
    def inside(fail=False):
        if fail:
            raise ValueError("drawing failed")
        return gc.isenabled()

    assert gc.isenabled()
    assert inside() is False and gc.isenabled()
    with pytest.raises(ValueError):
        inside(fail=True)
    assert gc.isenabled()
    for f in (experiments.figure_map, experiments.figure_fig5, experiments.figure_fig2,
              motion.figure_theta, motion.figure_envelope, stability.figure):
        assert f.__wrapped__.__name__ == f.__name__  # each product figure is wrapped


def _map_inputs(shift, crits):
    """A small map in figure_map's form: cells stable below a line that moves with ``shift``."""
    a = np.linspace(0.0, 1.0, 7)
    w = np.linspace(0.0, 1.0, 7)
    fine = np.linspace(0.0, 1.0, 41)
    maps = {c: (w[:, None] < (0.3 + shift + 0.1 * k) * a[None, :] + 0.1) for k, c in enumerate(crits)}
    m = {"a_over_l": list(a), "w0_over_w": list(w), "maps": maps,
         "counts": {c: int(v.sum()) for c, v in maps.items()}}
    limits = {"w0_over_w": list(fine), "region_values": list(fine),
              "region": (fine[:, None] < (0.5 + shift) * fine[None, :]).astype(float),
              "curves": {"eq28": (list(0.4 * fine + shift), list(0.9 * fine + 0.05))}}
    return m, limits, f"map {shift}\nsecond line"


@pytest.mark.parametrize("crits", [["mean", "mean-abs", "bounded", "floquet"], ["bounded", "floquet", "mean"]])
def test_map_figure_kept_for_the_next_map_draws_a_new_figures_bytes(crits):
    from pendulab.products import experiments
    shifts = [0.0, 0.2, 0.1]
    fresh = []
    for s in shifts:
        experiments._MAP_FIGURES.clear()
        fresh.append(experiments.figure_map(*_map_inputs(s, crits)))
    experiments._MAP_FIGURES.clear()
    kept = [experiments.figure_map(*_map_inputs(s, crits)) for s in shifts]
    assert len(experiments._MAP_FIGURES) == 1
    experiments._MAP_FIGURES.clear()
    assert len({f[".png"] for f in fresh}) == len(shifts)  # the maps differ
    assert kept == fresh


@pytest.mark.parametrize("rc", [{"savefig.bbox": "tight"}, {"savefig.transparent": True},
                                {"savefig.facecolor": "red"}])
def test_a_matplotlibrc_savefig_setting_changes_neither_file(rc):
    """A user's matplotlibrc (savefig.bbox: tight draws the figure twice, once to measure)
    must not reach the products' files: save() gives the bytes it gives with the defaults."""
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    try:
        plain = figures.save(fig)
        with matplotlib.rc_context(rc):
            under_rc = figures.save(fig)
    finally:
        plt.close(fig)
    assert under_rc == plain


def test_a_second_drawing_during_one_save_sends_the_png_to_its_own_drawing():
    """Were savefig to draw the figure twice (a tight box measured first), the canvas would
    hold both drawings: it is then not used."""
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    try:
        with figures._DrawnTwice(fig, 150) as both:
            fig.savefig(io.BytesIO(), format="pdf", metadata=figures.PDF_METADATA, bbox_inches="tight")
        assert not both.complete
    finally:
        plt.close(fig)


def test_a_figures_own_draw_override_is_used_and_kept():
    matplotlib, plt = figures.pyplot("test")
    fig = _figure(plt)
    calls = []
    real = fig.draw

    def own(renderer):
        calls.append(renderer)
        return real(renderer)
    fig.draw = own
    try:
        figures.save(fig)
    finally:
        plt.close(fig)
    assert len(calls) == 1 and fig.__dict__["draw"] is own
