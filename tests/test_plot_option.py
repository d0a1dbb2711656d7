"""``--plot FILE`` of sweep, simulate, stability, bessel zeros and bessel quarter-periods.

Each plot is a valid file of the type its extension names (magic bytes), and what it draws is
the command's own data: the figure is taken from :func:`pendulab.plots.write` on its way to
the file and its lines read back (never pixels).  Bad names, a missing matplotlib and a
folder that cannot hold the file are one-line errors with exit status 2, found before any
work, with nothing written.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from pendulab import plots
from pendulab.cli import main

MAGIC = {".png": b"\x89PNG\r\n\x1a\n", ".pdf": b"%PDF-", ".svg": b"<?xml"}

#: small, quick runs of each command (about a second each at most)
RUNS = {
    "sweep": ["sweep", "--criterion", "floquet", "--grid", "6", "--quiet"],
    "simulate": ["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "4",
                 "--every", "5", "--reference"],
    "stability": ["stability", "--ratio", "0.2"],
    "zeros": ["bessel", "zeros", "--order", "1", "--count", "8", "--dps", "15"],
    "quarter": ["bessel", "quarter-periods", "--count", "6", "--dps", "15"],
}
#: each command once in each format, spread over the runs
FORMAT_CASES = [("sweep", ".svg"), ("simulate", ".pdf"), ("stability", ".png"),
                ("stability", ".svg"), ("stability", ".pdf"), ("zeros", ".png"), ("quarter", ".svg")]


@pytest.fixture
def drawn(monkeypatch):
    """The figures handed to plots.write (which still writes them)."""
    figures = []
    real = plots.write

    def keep(fig, path, fmt):
        figures.append(fig)
        return real(fig, path, fmt)

    monkeypatch.setattr(plots, "write", keep)
    return figures


def _json(argv, capsys):
    capsys.readouterr()  # what came before
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _lines(ax):
    return [line for line in ax.get_lines() if len(line.get_xdata())]


@pytest.mark.parametrize("name, ext", FORMAT_CASES)
def test_each_plot_is_a_file_of_its_type(tmp_path, capsys, name, ext):
    path = tmp_path / f"figure{ext}"
    assert main(RUNS[name] + ["--plot", str(path)]) == 0
    capsys.readouterr()
    data = path.read_bytes()
    assert data.startswith(MAGIC[ext])
    if ext == ".svg":
        assert b"<svg" in data[:2000] and data.rstrip().endswith(b"</svg>")
    if ext == ".pdf":
        assert data.rstrip().endswith(b"%%EOF")
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary file left


@pytest.mark.parametrize("name", ["stability", "zeros"])  # plain text labels; mathematics
def test_a_plot_is_the_same_bytes_on_every_run(tmp_path, capsys, name):
    for ext in (".svg", ".png", ".pdf"):
        one, two = tmp_path / f"one{ext}", tmp_path / f"two{ext}"
        assert main(RUNS[name] + ["--plot", str(one)]) == 0
        assert main(RUNS[name] + ["--plot", str(two)]) == 0
        assert one.read_bytes() == two.read_bytes(), ext
        data = one.read_bytes()  # no date, no software version inside
        assert not any(mark in data for mark in (b"<dc:date>", b"CreationDate", b"Matplotlib v"))
    capsys.readouterr()


def test_sweep_plots_its_stable_cells_and_the_exact_limits(tmp_path, capsys, drawn):
    argv = ["sweep", "--criterion", "mean", "--grid", "8", "--periods", "60", "--quiet"]
    record = _json(argv, capsys)
    assert main(argv + ["--plot", str(tmp_path / "map.png")]) == 0
    (fig,) = drawn
    ax = fig.axes[0]
    cells = [line for line in ax.get_lines() if line.get_marker() == "o"]
    (circles,) = cells
    plotted = sorted(zip(np.round(circles.get_xdata(), 10), np.round(circles.get_ydata(), 10)))
    assert plotted == sorted((round(a, 10), round(w, 10)) for a, w in record["stable"])
    assert f"{record['count']} of 64 stable" in ax.get_title()
    # the dashed edge of the shaded region is the exact Floquet limits: where it crosses
    # omega0/omega = 0.2 it is at the limits that `pendulab stability --ratio 0.2` prints
    limits = _json(["stability", "--ratio", "0.2"], capsys)
    edge = [p for p in ax.patches if not p.get_fill()][0].get_path().vertices
    near = edge[np.abs(edge[:, 1] - 0.2) < 0.5 / 300]
    for side in ("lower", "upper"):
        assert np.min(np.abs(near[:, 0] - limits[side])) < 1.5 / 300, side
    assert ax.get_xlim() == (0.0, 1.0) and ax.get_ylim() == (0.0, 1.0)


def test_simulate_plots_theta_the_pivot_and_the_reference_error(tmp_path, capsys, drawn):
    argv = RUNS["simulate"]
    record = _json(argv, capsys)
    assert main(argv + ["--plot", str(tmp_path / "run.svg")]) == 0
    (fig,) = drawn
    top, pivot, error = fig.axes
    (theta,) = _lines(top)
    assert np.array_equal(theta.get_xdata(), record["tau"])
    assert np.array_equal(theta.get_ydata(), record["theta"])
    (y0,) = _lines(pivot)
    # the source's drive y0 = a cos(omega t) with tau = omega t / 2 (000 eq. 1, sec. 4):
    # y0/a = cos(2 tau), written here independently of the derived drive
    tau = np.asarray(y0.get_xdata())
    assert tau[0] == 0.0 and math.isclose(tau[-1], record["tau"][-1])
    assert np.max(np.abs(y0.get_ydata() - np.cos(2 * tau))) < 1e-12
    (err,) = _lines(error)
    want = np.abs(np.asarray(record["theta"]) - np.asarray(record["theta_reference"]))
    assert np.allclose(err.get_ydata() - 1e-18, want, rtol=1e-12, atol=1e-30)
    assert error.get_yscale() == "log"
    low, high = error.get_ylim()
    assert low <= want[want > 0].min() and high >= want.max()


def test_simulate_plots_the_pivot_of_its_drive(tmp_path, capsys, drawn):
    argv = ["simulate", "--a-over-l", "0.1", "--w0-over-w", "0.02", "--periods", "2",
            "--drive", "a*cos(omega*t) + a*cos(2*omega*t)", "--plot", str(tmp_path / "d.png")]
    assert main(argv) == 0
    capsys.readouterr()
    (fig,) = drawn
    assert len(fig.axes) == 2  # no --reference: no error panel
    (y0,) = _lines(fig.axes[1])
    tau = np.asarray(y0.get_xdata())
    # y0/a = cos(omega t) + cos(2 omega t) at t = 2 tau/omega
    assert np.max(np.abs(y0.get_ydata() - (np.cos(2 * tau) + np.cos(4 * tau)))) < 1e-12


def test_stability_plots_lower_and_upper_around_its_ratio(tmp_path, capsys, drawn):
    record = _json(RUNS["stability"], capsys)
    assert main(RUNS["stability"] + ["--plot", str(tmp_path / "s.pdf")]) == 0
    (fig,) = drawn
    ax = fig.axes[0]
    lines = {line.get_label(): line for line in _lines(ax)}
    lower, upper = lines["lower, exact (Floquet)"], lines["upper, exact (Floquet)"]
    assert lower.get_linestyle() != upper.get_linestyle()
    ratios = np.asarray(lower.get_ydata())
    assert ratios[0] == 0.0 and ratios[-1] == plots_min_top()  # max(2 x 0.2, 0.5)
    k = int(np.flatnonzero(ratios == 0.2)[0])
    assert lower.get_xdata()[k] == record["lower"] and upper.get_xdata()[k] == record["upper"]
    marks = {line.get_label().split(" ")[0]: line for line in _lines(ax) if line.get_marker() in ("o", "s")}
    assert sorted(marks) == ["lower", "upper"]
    for side in ("lower", "upper"):  # each marked at its own limit, on the asked ratio
        assert list(marks[side].get_xdata()) == [record[side]] and list(marks[side].get_ydata()) == [0.2]
    assert marks["lower"].get_marker() != marks["upper"].get_marker()
    # the axes fitted to the data: omega0/omega over the plotted ratios, a/l just past the limits
    assert ax.get_ylim() == (0.0, float(ratios[-1]))
    top = max(np.nanmax(upper.get_xdata()), np.nanmax(lower.get_xdata()))
    assert top < ax.get_xlim()[1] < 1.1 * top
    # and the stable band is shaded between them
    (band,) = ax.collections
    assert band.get_label().startswith("stable")


def plots_min_top():
    from pendulab.commands.stability import PLOT_MIN_TOP
    return PLOT_MIN_TOP


def test_stability_without_an_upper_limit_shades_to_the_edge(tmp_path, capsys, drawn):
    assert main(["stability", "--ratio", "0.3", "--method", "eq19",
                 "--plot", str(tmp_path / "s.png")]) == 0
    capsys.readouterr()
    ax = drawn[0].axes[0]
    labels = [line.get_label() for line in _lines(ax)]
    assert not any(label.startswith("upper") for label in labels)
    assert "no upper limit" in ax.collections[0].get_label()


def test_bessel_zeros_plot_the_zeros_and_mcmahon(tmp_path, capsys, drawn):
    argv = RUNS["zeros"]
    record = _json(argv, capsys)
    assert main(argv + ["--plot", str(tmp_path / "z.png")]) == 0
    (fig,) = drawn
    top, bottom = fig.axes
    points = [line for line in _lines(top) if line.get_marker() == "o"][0]
    assert list(points.get_xdata()) == list(range(1, 9))
    assert list(points.get_ydata()) == [float(z) for z in record["zeros"]]
    # j_1,k from SciPy (an independent method: scipy.special.jn_zeros); McMahon's curve at
    # k = 8 (beta = 7.75 pi, DLMF 10.21.19) within 1e-8 of j_1,8 - beta
    from scipy.special import jn_zeros
    j = jn_zeros(1, 8)
    curve = [line for line in _lines(bottom) if line.get_label().startswith("McMahon")][0]
    beta = (8 + 0.5 - 0.25) * math.pi
    assert math.isclose(curve.get_xdata()[-1], 8)
    assert abs(curve.get_ydata()[-1] - (j[-1] - beta)) < 1e-8
    diffs = [line for line in _lines(bottom) if line.get_marker() == "o"][0]
    assert np.allclose(diffs.get_ydata(), j - (np.arange(1, 9) + 0.25) * math.pi, atol=1e-12)


def test_mcmahon_correction_leading_term_is_dlmf_10_21_19():
    # DLMF 10.21.19: j_nu,k ~ beta - (mu - 1)/(8 beta) - ..., mu = 4 nu^2; at large beta the
    # first term dominates (the next is O(beta^-3))
    beta = plots.mcmahon_beta(2, 1e4)
    assert math.isclose(plots.mcmahon_correction(2, 1e4, 1), -(16 - 1) / (8 * beta), rel_tol=1e-12)
    assert math.isclose(plots.mcmahon_correction(2, 1e4), -(16 - 1) / (8 * beta), rel_tol=1e-6)


def test_quarter_periods_plot_the_margins_and_their_limits(tmp_path, capsys, drawn):
    argv = RUNS["quarter"]
    record = _json(argv, capsys)
    assert main(argv + ["--plot", str(tmp_path / "q.svg")]) == 0
    (fig,) = drawn
    after, before = fig.axes
    a = [line for line in _lines(after) if line.get_marker() == "o"][0]
    b = [line for line in _lines(before) if line.get_marker() == "s"][0]
    assert list(a.get_xdata()) == list(range(6)) and list(b.get_xdata()) == list(range(1, 6))
    assert list(a.get_ydata()) == [float(x) for x in record["margin_after"]]
    assert list(b.get_ydata()) == [float(x) for x in record["margin_before"]]
    # the limits as k -> oo: 6 -+ pi^2/2 (002's quarter periods from McMahon's expansion,
    # docs/bessel.md; here from math.pi, not from the derivation)
    flat = {round(float(line.get_ydata()[0]), 12) for ax in (after, before) for line in ax.get_lines()
            if line.get_linestyle() == "--"}
    assert flat == {round(6 - math.pi ** 2 / 2, 12), round(6 + math.pi ** 2 / 2, 12)}


# ---------------------------------------------------------------------------
# errors: one line, exit status 2, nothing written, nothing computed
# ---------------------------------------------------------------------------

@pytest.fixture
def no_work(monkeypatch):
    """Every command's computation fails the test if it is reached."""
    def forbidden(*args, **kwargs):
        raise AssertionError("computed before the --plot name was checked")

    from pendulab.analyses import bessel_periods, bessel_zeros, stability
    from pendulab.numerics import sweep
    monkeypatch.setattr(sweep, "sweep", forbidden)
    monkeypatch.setattr(sweep, "trajectory", forbidden)
    monkeypatch.setattr(stability, "limits", forbidden)
    monkeypatch.setattr(bessel_zeros, "bessel_zeros", forbidden)
    monkeypatch.setattr(bessel_periods, "quarter_periods", forbidden)


def _refused(argv, capsys):
    assert main(argv) == 2
    out = capsys.readouterr()
    assert out.out == ""
    assert out.err.count("\n") == 1 and out.err.startswith("pendulab: error: "), out.err
    assert "Traceback" not in out.err
    return out.err


@pytest.mark.parametrize("name", sorted(RUNS))
@pytest.mark.parametrize("target, message", [
    ("figure.txt", "must end in .png, .pdf or .svg"),
    ("figure", "must end in .png, .pdf or .svg"),
    ("missing/figure.png", "no directory"),
    ("file/figure.svg", "no directory"),
    ("folder.png", "is a directory"),
])
def test_a_bad_plot_name_is_refused_before_any_work(tmp_path, capsys, no_work, name, target, message):
    (tmp_path / "file").write_text("a file")
    (tmp_path / "folder.png").mkdir()
    before = sorted(p.name for p in tmp_path.iterdir())
    err = _refused(RUNS[name] + ["--plot", str(tmp_path / target)], capsys)
    assert message in err and f"--plot {tmp_path / target}" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before


@pytest.mark.parametrize("name", sorted(RUNS))
def test_without_matplotlib_plot_says_so_in_one_line(tmp_path, capsys, monkeypatch, no_work, name):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib` now fails
    err = _refused(RUNS[name] + ["--plot", str(tmp_path / "figure.png")], capsys)
    assert "--plot needs matplotlib" in err and "pendulab[figures]" in err
    assert list(tmp_path.iterdir()) == []


def test_without_matplotlib_in_a_fresh_process(tmp_path):
    # an import hook that refuses matplotlib, as on a machine without the figures extra
    (tmp_path / "sitecustomize.py").write_text(
        "import sys\n"
        "class _Refuse:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'matplotlib' or name.startswith('matplotlib.'):\n"
        "            raise ImportError('no matplotlib here')\n"
        "sys.meta_path.insert(0, _Refuse())\n")
    import os
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path)] + sys.path)}
    run = subprocess.run([sys.executable, "-m", "pendulab", "stability", "--ratio", "0.2",
                          "--plot", str(tmp_path / "s.png")], capture_output=True, text=True, env=env)
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.count("\n") == 1 and "--plot needs matplotlib" in run.stderr, run.stderr
    assert not (tmp_path / "s.png").exists()


def test_a_plot_that_cannot_be_written_leaves_nothing(tmp_path, capsys, monkeypatch):
    # the folder vanishes between the check and the write: one line, no partial file
    from pendulab import io
    real = io.write_text_atomic

    def vanishing(path, data):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(io, "write_text_atomic", vanishing)
    err = _refused(RUNS["stability"] + ["--plot", str(tmp_path / "s.png")], capsys)
    assert "Permission denied" in err
    assert list(tmp_path.iterdir()) == [] and real is not vanishing


_PROBE = """
import contextlib, io, json, sys
import pendulab.cli as cli
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    code = cli.main(json.loads(sys.argv[1]))
print(json.dumps({"code": code, "heavy": sorted({m.split(".")[0] for m in sys.modules}
                  & {"matplotlib", "numpy", "sympy", "scipy", "mpmath", "flint"})}))
"""


@pytest.mark.parametrize("argv", [
    ["stability", "--ratio", "2000", "--plot", "s.png"],   # a bad ratio with --plot
    ["stability", "--ratio", "0.2", "--plot", "s.txt"],    # a bad --plot name
    ["sweep", "--grid", "0", "--plot", "map.svg"],
    ["bessel", "zeros", "--order", "1", "--count", "1", "--plot", "z.gif"],
])
def test_a_refused_plot_imports_nothing_heavy(tmp_path, argv):
    import os

    import pendulab
    # run in an empty folder (a relative file name lands there), with this pendulab
    src = os.path.dirname(os.path.dirname(os.path.abspath(pendulab.__file__)))
    env = {**os.environ, "PYTHONPATH": src}
    run = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(argv)], capture_output=True,
                         text=True, check=True, cwd=tmp_path, env=env)
    res = json.loads(run.stdout)
    assert res == {"code": 2, "heavy": []}
    assert list(tmp_path.iterdir()) == []


def test_a_run_refused_after_its_work_writes_no_plot(tmp_path, capsys):
    # the linear equation at omega0/omega = 1000 grows like exp(2000 tau): RK4 (at a step its
    # stability check accepts) overflows and the command refuses the run; the plot, drawn only from a finished run, is not written
    err = _refused(["simulate", "--linear", "--w0-over-w", "1000", "--a-over-l", "0", "--periods",
                    "1", "--steps-per-period", "2300", "--plot", str(tmp_path / "run.png")], capsys)
    assert "overflowed" in err
    assert list(tmp_path.iterdir()) == []


def test_sweep_plot_of_a_hill_drive_draws_the_monodromy_region(tmp_path, capsys, drawn):
    # a drive with a second harmonic gives a Hill equation: no eq. 28 (Mathieu's), the region
    # is the monodromy matrix's verdict on the sweep's own grid, as in the experiments product
    argv = ["sweep", "--drive", "a*cos(omega*t) + a*cos(2*omega*t)", "--criterion", "floquet",
            "--grid", "6", "--quiet"]
    record = _json(argv, capsys)
    assert main(argv + ["--plot", str(tmp_path / "hill.png")]) == 0
    (fig,) = drawn
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["exact (Floquet)"]
    assert "monodromy" in fig._suptitle.get_text()
    circles = [line for line in ax.get_lines() if line.get_marker() == "o"][0]
    assert len(circles.get_xdata()) == record["count"]
