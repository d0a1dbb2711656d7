"""What makes the main job fast gives the values of the plain code, bit for bit.

* the stability-interval scan of the series (pendulab.analyses.series._branch_scan:
  batched companion eigenvalues, brentq polish on demand) against the scalar
  function it replaces, _branch_theta1, point by point;
* the first-band memo of pendulab.analyses.floquet against a fresh computation;
* the PDF font subsets shared within a process (pendulab.figures.save), and each
  subset against matplotlib's own (fontTools with matplotlib's options).
The reproduction of generated/ itself is tests/test_build.py's.
"""

import io

import numpy as np
import pytest

from pendulab.analyses import series


@pytest.mark.parametrize("order", [2, 4, 6, 8])
@pytest.mark.parametrize("target", [-4.0, -0.36, -0.01, -1e-9, 0.3])
def test_branch_scan_is_the_scalar_branch_bit_for_bit(order, target):
    polys = series._alpha_polys_in_x(order)
    xs = np.unique(np.concatenate([np.linspace(target, 0.0, 400), 1.0 - np.geomspace(1.0, 1e-7, 3000)]))
    xs = xs[xs > target][::7]  # every 7th point of the scan: both parts of the grid, up to the pole
    scanned = list(series._branch_scan(polys, xs, target))
    assert [x for x, _ in scanned] == [float(x) for x in xs]
    values = [None if r is None else r.value() for _, r in scanned]
    with np.errstate(all="ignore"):  # the scalar function divides by zero at the pole x = 1
        direct = [series._branch_theta1(polys, float(x), target) for x in xs]
    assert values == direct
    assert any(v is not None for v in direct)


def test_root_brackets_decide_as_the_polished_values():
    polys = series._alpha_polys_in_x(6)
    xs = np.linspace(-0.5, 0.9, 300)
    fresh = [r for _, r in series._branch_scan(polys, xs, -0.5) if r is not None]
    polished = [r for _, r in series._branch_scan(polys, xs, -0.5) if r is not None]
    for r in polished:
        r.value()
    for a, b, pa, pb in zip(fresh, fresh[1:], polished, polished[1:]):
        assert a.less(b) == (pa.value() < pb.value())
        assert b.less(a) == (pb.value() < pa.value())


def test_the_interval_is_the_one_of_the_point_by_point_scan():
    """interval_series_theta1 against the loop it had before (scalar _branch_theta1 at every x;
    the maximum found by the same minimiser, which tests/test_roots.py checks)."""
    from pendulab.numerics.roots import brent_minimum

    def point_by_point(order, target):
        polys = series._alpha_polys_in_x(order)
        lower = series._branch_theta1(polys, 0.0, target) if target < 0 else 0.0
        xs = np.unique(np.concatenate([np.linspace(target, 0.0, 400), 1.0 - np.geomspace(1.0, 1e-7, 3000)]))
        prev, before = (target, 0.0), None
        for x in xs[xs > target]:
            t = series._branch_theta1(polys, float(x), target)
            if t is None:
                return lower, None
            if t < prev[1]:
                lo_x = before[0] if before is not None else target
                _, low = brent_minimum(lambda s: -(series._branch_theta1(polys, s, target) or 0.0),
                                       lo_x, float(x), xatol=1e-13, maxiter=500)
                return lower, max(-low, prev[1])
            before, prev = prev, (float(x), t)
        return lower, None

    # the stability product's and the experiments' orders and theta0 = -4 (omega0/omega)^2 on
    # their grids (k/20 and k/40), and a few more: the batched first descent (series._first_descent)
    # must stop where the point-by-point loop stops
    targets = [-0.64, -0.04, 0.2, 0.0, -4.0, -1e-9] + [-4 * (k / 40) ** 2 for k in range(1, 41, 3)]
    for order in (2, 3, 6, 8):
        for target in targets:
            with np.errstate(all="ignore"):
                expected = point_by_point(order, target)
            assert series.interval_series_theta1(order, target) == expected


def test_first_band_memo_gives_the_fresh_band():
    from pendulab.analyses import floquet
    from pendulab.analyses.floquet import _charvalues
    # double precision, proved route: a start and a ball per end (a_0 and b_1 crossings)
    _charvalues._ENDS.clear()
    rod = floquet.stability_limits(0.35, 4 / 3)
    assert len(_charvalues._ENDS) == 4
    point = floquet.stability_limits(0.35, 1)  # the same theta0: taken from the memo
    assert len(_charvalues._ENDS) == 4
    _charvalues._ENDS.clear()
    assert floquet.stability_limits(0.35, 1) == point
    assert floquet.stability_limits(0.35, 4 / 3) == rod
    # the mpmath route's memo: one band per working precision
    _charvalues._BANDS.clear()
    rod = floquet.stability_limits(0.35, 4 / 3, method="mpmath")
    assert len(_charvalues._BANDS) == 2          # the two working precisions
    point = floquet.stability_limits(0.35, 1, method="mpmath")
    assert len(_charvalues._BANDS) == 2
    _charvalues._BANDS.clear()
    assert floquet.stability_limits(0.35, 1, method="mpmath") == point
    assert floquet.stability_limits(0.35, 4 / 3, method="mpmath") == rod


def test_shared_pdf_font_subsets_are_made_once_and_hold_the_common_glyphs():
    pytest.importorskip("matplotlib")
    from matplotlib.backends import _backend_pdf_ps

    from pendulab import figures
    real = _backend_pdf_ps.get_glyphs_subset
    matplotlib, plt = figures.pyplot("test")
    with matplotlib.rc_context({"pdf.fonttype": 42}):
        fig, ax = plt.subplots()
        try:
            ax.plot([0, 1], [1, 0], label=r"$\theta(\tau)$, $\omega_0/\omega$")
            ax.set_title("stable: 14 pairs")
            ax.legend()
            figures._SUBSETS.clear()
            first = figures.save(fig)[".pdf"]
            made = len(figures._SUBSETS)
            second = figures.save(fig)[".pdf"]      # every subset from the memo
            unshared = io.BytesIO()
            fig.savefig(unshared, format="pdf", metadata=figures.PDF_METADATA)
        finally:
            plt.close(fig)
    assert made >= 2 and len(figures._SUBSETS) == made
    assert first == second
    assert unshared.getvalue() != first  # the common glyphs are in the shared subsets only
    assert _backend_pdf_ps.get_glyphs_subset is real  # matplotlib's function is back in place


def test_lean_font_subset_is_matplotlibs_without_the_shaping_tables():
    """figures._lean_subset against matplotlib's own subset (fontTools with matplotlib's
    options) of the same glyphs: the same glyphs by name, outlines and advance widths, the
    same character map; only the tables of figures.LEFT_OUT_TABLES are missing."""
    pytest.importorskip("matplotlib")
    from fontTools.ttLib import TTFont
    from matplotlib import font_manager
    from matplotlib.backends import _backend_pdf_ps

    from pendulab import figures
    path = font_manager.findfont("DejaVu Sans")
    fontfile = font_manager.FontPath(path, 0)  # as matplotlib's PDF backend names a font file
    glyphs = figures._common_glyphs(path)
    data, index_map = figures._lean_subset(fontfile, glyphs)
    with _backend_pdf_ps.get_glyphs_subset(fontfile, glyphs) as theirs:
        plain = TTFont(_backend_pdf_ps.font_as_file(theirs.font))
        their_map = dict(theirs.glyph_index_map)
    lean = TTFont(io.BytesIO(data))
    missing = set(plain.keys()) - set(lean.keys())
    assert missing and missing <= set(figures.LEFT_OUT_TABLES) and set(lean.keys()) <= set(plain.keys())
    assert "GSUB" in missing and "GPOS" in missing
    # every glyph asked for is in both, at the index each map gives
    order, their_order = lean.getGlyphOrder(), plain.getGlyphOrder()
    assert set(glyphs) <= set(index_map) and set(glyphs) <= set(their_map)
    names = {order[index_map[g]] for g in glyphs}
    assert names == {their_order[their_map[g]] for g in glyphs}
    for name in names:
        assert lean["glyf"][name].getCoordinates(lean["glyf"])[0] == \
            plain["glyf"][name].getCoordinates(plain["glyf"])[0], name
        assert lean["hmtx"][name] == plain["hmtx"][name], name
    assert lean.getBestCmap() == {c: n for c, n in plain.getBestCmap().items() if n in set(order)}


def test_is_zero_proves_bessel_identities_and_refuses_the_others():
    """The closed form's zero test (pendulab.analyses.bessel.is_zero): DLMF 10.6.1 and 10.6.2
    are zero by the fast route; expressions that are not zero are not; a zero the fast route
    cannot see (a trigonometric one) is left to simplify."""
    import sympy as sp

    from pendulab.analyses.bessel import _fast_zero, is_zero
    x, a = sp.symbols("x a", positive=True)
    J, Y = sp.besselj, sp.bessely
    recurrence = J(0, 3 * sp.sqrt(x)) + J(2, 3 * sp.sqrt(x)) - 2 / (3 * sp.sqrt(x)) * J(1, 3 * sp.sqrt(x))
    derivative = sp.diff(Y(3, a * x), x) - a * (Y(2, a * x) - Y(4, a * x)) / 2       # DLMF 10.6.1-2
    assert _fast_zero(recurrence) and is_zero(recurrence)
    assert _fast_zero(sp.expand(derivative)) and is_zero(derivative)
    for other in (J(0, x) - J(2, x), J(1, x) - Y(1, x), recurrence + 1 / x, x * J(3, x) - 4 * J(2, x)):
        assert not _fast_zero(other) and not is_zero(other)
    trig = sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1
    assert not _fast_zero(trig) and is_zero(trig)


def test_scalar_horner_is_numpy_polyval_bit_for_bit():
    """series._horner (the scalar branch's and the polish's polynomial values) against numpy.polyval."""
    rng = np.random.default_rng(7)
    polys = [p for order in (2, 6, 12) for _, num, den in series._alpha_polys_in_x(order) for p in (num, den)]
    points = list(rng.uniform(-5.0, 1.0, 200)) + [0.0, 1.0, -0.0, 1e300, -1e300]
    with np.errstate(all="ignore"):
        for p in polys + [rng.normal(size=9) * 10.0 ** rng.integers(-200, 200, 9)]:
            for x in points:
                expected = np.polyval(p, x)
                got = series._horner(list(p), float(x))
                assert got == expected or (np.isnan(expected) and got != got)
