"""The lecture notes (product "notes"): the committed PDF compiles cleanly from the committed
notes.tex, its pages are not blank, the numbers in it are the derivation's, the scene decides
what is computed, bad options are one line, and a machine without TeX keeps the built PDF.

Compiling needs pdflatex (Debian: texlive-latex-base, texlive-latex-recommended,
texlive-lang-portuguese, lmodern; .ci/run installs them and sets PENDULAB_REQUIRE_TEX=1, so
that in CI a missing TeX is a failure, not a skip).
"""

import os
import re
import shutil
import subprocess
import tomllib
from pathlib import Path

import pytest

from pendulab.build import build
from pendulab.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "derivations" / "lecture-notes.toml"
BUILT = ROOT / "generated" / "lecture-notes"
HAVE_TEX = shutil.which("pdflatex") is not None
needs_tex = pytest.mark.skipif(
    not HAVE_TEX and not os.environ.get("PENDULAB_REQUIRE_TEX"),
    reason="pdflatex not installed (apt-get install texlive-latex-base texlive-latex-recommended "
           "texlive-lang-portuguese lmodern)")


# -- what a reader of the log would see -------------------------------------------------------

# the strict check of every LaTeX log (tests/test_latex.py shows it catching each kind of fault)
from test_latex import log_problems  # noqa: E402


def pdflatex_twice(directory, name="notes.tex"):
    """(return code, log text) of two pdflatex runs on ``name`` in ``directory``."""
    for _ in range(2):
        done = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-file-line-error", name],
                              cwd=directory, capture_output=True, text=True, errors="replace", timeout=300,
                              stdin=subprocess.DEVNULL)
    log = (Path(directory) / name).with_suffix(".log").read_text(errors="replace")
    return done.returncode, log


@needs_tex
def test_a_clean_document_passes_the_log_check(tmp_path):
    (tmp_path / "notes.tex").write_text("\\documentclass{article}\n\\begin{document}\n"
                                        "\\section{A}\\label{a} See Section~\\ref{a}.\n\\end{document}\n")
    code, log = pdflatex_twice(tmp_path)
    assert code == 0 and log_problems(log) == []


# -- the committed notes -----------------------------------------------------------------------

def test_the_committed_notes_are_there():
    names = {p.name for p in BUILT.iterdir()}
    assert {"notes.tex", "notes.pdf", "stability.pdf", "fig5.pdf"} <= names
    assert (BUILT / "notes.pdf").read_bytes().startswith(b"%PDF-")


@needs_tex
def test_the_committed_notes_compile_without_a_visible_warning(tmp_path):
    for f in BUILT.iterdir():
        if f.suffix in (".tex", ".pdf") and f.name != "notes.pdf":
            shutil.copy(f, tmp_path / f.name)
    code, log = pdflatex_twice(tmp_path)
    assert code == 0, log[-2000:]
    assert log_problems(log) == []


def ink(page):
    """(fraction of pixels darker than light grey, fraction of rows with such a pixel) of a PNG."""
    from PIL import Image
    image = Image.open(page).convert("L")
    histogram = image.histogram()
    width, height = image.size
    rows = sum(1 for y in range(height) if image.crop((0, y, width, y + 1)).getextrema()[0] < 200)
    return sum(histogram[:200]) / sum(histogram), rows / height


def pages_png(pdf, directory, first=1, last=2):
    """pdftoppm's 40-dpi grey PNGs of pages ``first`` to ``last`` of ``pdf``."""
    if shutil.which("pdftoppm") is None and not os.environ.get("PENDULAB_REQUIRE_TEX"):
        pytest.skip("pdftoppm not installed (apt-get install poppler-utils)")
    subprocess.run(["pdftoppm", "-r", "40", "-gray", "-png", "-f", str(first), "-l", str(last),
                    str(pdf), str(Path(directory) / "page")], check=True, timeout=120)
    return sorted(Path(directory).glob("page-*.png"))


def looks_written(page):
    # a page of text at 40 dpi: about 5 % of its pixels and over a third of its rows have ink;
    # a blank page (or one with only its number) has next to none
    pixels, rows = ink(page)
    return pixels > 0.02 and rows > 0.3


@needs_tex
def test_the_first_two_pages_are_not_blank(tmp_path):
    pages = pages_png(BUILT / "notes.pdf", tmp_path)
    assert len(pages) == 2
    for page in pages:
        assert looks_written(page), f"{page.name}: ink {ink(page)}"


@needs_tex
def test_a_blank_page_is_seen_as_blank(tmp_path):
    (tmp_path / "notes.tex").write_text("\\documentclass{article}\n\\begin{document}\n"
                                        "\\null\\newpage\\null\n\\end{document}\n")
    pdflatex_twice(tmp_path)
    pages = pages_png(tmp_path / "notes.pdf", tmp_path / "png" if (tmp_path / "png").mkdir() is None else None)
    assert len(pages) == 2 and not any(looks_written(p) for p in pages)


def test_the_figures_are_vector_pdf_with_mathematics_in_their_labels():
    tex = (BUILT / "notes.tex").read_text()
    figures = re.findall(r"\\includegraphics\[[^]]*\]\{([^}]*)\}", tex)
    assert figures and all(name.endswith(".pdf") for name in figures)
    for name in figures:
        data = (BUILT / name).read_bytes()
        assert data.startswith(b"%PDF-"), name
        assert b"/Subtype /Image" not in data, f"{name} holds a raster image"
        # mathtext's Computer Modern italic (cmmi10) sets the symbols theta, omega, a/l
        assert re.search(rb"/BaseFont /[A-Z]{6}\+Cmmi10", data), f"{name}: no mathematics in the labels"


def _number_after(tex, pattern):
    m = re.search(pattern + r"\s*=\s*(-?[0-9.]+)(?:\s*\\times\s*10\^\{(-?\d+)\})?", tex)
    assert m, pattern
    return float(m.group(1)) * (10.0 ** int(m.group(2)) if m.group(2) else 1.0)


def test_the_pivot_section_puts_the_scenes_values_into_the_derived_parameters():
    import math
    values = tomllib.loads(SCENE.read_text())["values"]
    l, a, g = values["l"], values["a"], values["g"]
    omega = 2 * math.pi * 86
    # independently of the derivation: a uniform rod with its centre of mass at l has
    # I = (4/3) m l^2 (a rod of length 2l about its end), omega0^2 = m g l / I, and 000 eqs. 5-6
    # give theta0 = -4 omega0^2/omega^2 (inverted), theta1 = 2 a l m / I
    theta0, theta1 = -4 * (3 * g / (4 * l)) / omega ** 2, 3 * a / (2 * l)
    tex = (BUILT / "notes.tex").read_text()
    section = tex[tex.index(r"\paragraph{The pendulum in numbers.}"):]
    assert _number_after(section, r"\\theta_0") == pytest.approx(theta0, rel=1e-3)
    assert _number_after(section, r"\\theta_1") == pytest.approx(theta1, rel=1e-3)


def test_the_source_quarter_periods_stand_beside_ours_and_agree():
    # 002, last page: the first quarter periods, in the unit v0/(4g) (the source's six values)
    source = [22.8438, 21.6315, 32.6495, 31.5213, 42.5001, 41.3994]
    tex = (BUILT / "notes.tex").read_text()
    rows = re.findall(r"^\$([0-9.]+)\$ & \$([0-9.]+)\$ \\\\$", tex, flags=re.M)
    assert [float(s) for s, _ in rows] == source
    for printed, ours in rows:
        assert abs(float(ours) - float(printed)) < 6e-5, (printed, ours)


def test_each_section_of_the_scene_is_in_the_notes_in_its_order():
    sections = tomllib.loads(SCENE.read_text())["products"]["notes"]["sections"]
    tex = (BUILT / "notes.tex").read_text()
    labels = [m for m in re.findall(r"\\label\{sec:([a-z]+)\}", tex)]
    assert labels == [s for s in sections if s != "references"]
    assert (r"\begin{thebibliography}" in tex) == ("references" in sections)


def test_every_citation_has_an_entry_and_every_entry_is_cited():
    tex = (BUILT / "notes.tex").read_text()
    cited = {k for group in re.findall(r"\\src\{([^}]*)\}", tex) for k in group.split(",")}
    entries = set(re.findall(r"\\bibitem\{([^}]*)\}", tex))
    assert cited <= entries
    assert entries - cited == set(), "bibliography entries that the text never cites"


# -- what the scene asks for -------------------------------------------------------------------

def _scene(tmp_path, notes, name="n"):
    path = tmp_path / f"{name}.toml"
    lines = [f'name = "{name}"', 'system = "kapitza"', "[products.notes]"]
    lines += [f"{k} = {v}" for k, v in notes.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_only_the_sections_asked_for_are_computed(tmp_path, monkeypatch):
    from pendulab.products import bessel, experiments, stability

    def refuse(*a, **k):
        raise AssertionError("computed a section the scene did not ask for")
    for module in (experiments, stability, bessel):
        monkeypatch.setattr(module, "produce", refuse)
    path = _scene(tmp_path, {"sections": '["pivot", "series"]', "series_order": 3, "pdf": "false"})
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    tex = (tmp_path / "out" / "n" / "notes.tex").read_text()
    assert r"\label{sec:pivot}" in tex and r"\label{sec:series}" in tex
    assert "sec:simulations" not in tex and "sec:stability" not in tex
    assert r"\cite" not in tex  # no references section: \src prints nothing
    assert sorted(p.name for p in (tmp_path / "out" / "n").iterdir()) == ["manifest.json", "notes.tex"]


def test_the_series_section_has_the_order_asked_for(tmp_path):
    path = _scene(tmp_path, {"sections": '["series"]', "series_order": 5, "pdf": "false"})
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    tex = (tmp_path / "out" / "n" / "notes.tex").read_text()
    assert r"\alpha_{4}" in tex or r"\alpha_4" in tex
    assert r"\alpha_{6}" not in tex and r"\alpha_6" not in tex


@pytest.mark.parametrize("notes, fragment", [
    ({"language": '"fr"'}, "language must be one of en, pt"),
    ({"sections": '["pivot", "appendix"]'}, "'appendix' is not one of"),
    ({"sections": '["pivot", "pivot"]'}, "listed twice"),
    ({"sections": "[]"}, "sections must name at least one"),
    ({"series_order": 0}, "series_order"),
    ({"grid": 1000}, "grid"),
    ({"length": '"__import__(1)"', "sections": '["string"]'}, "length"),
])
def test_bad_notes_options_are_one_line_and_write_nothing(tmp_path, capsys, notes, fragment):
    path = _scene(tmp_path, notes)
    out = tmp_path / "out"
    assert main(["build", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0] and "n.toml" in err[0], err
    assert not (out / "n").exists()


def test_the_notes_refuse_a_variable_length_scene_in_one_line(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text('name = "s"\nsystem = "variable-length"\n[products.notes]\n')
    assert main(["build", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "notes" in err[0]


# -- Portuguese --------------------------------------------------------------------------------

def test_portuguese_headings_and_babel(tmp_path):
    path = _scene(tmp_path, {"language": '"pt"', "sections": '["pivot", "series", "references"]',
                             "series_order": 2, "pdf": "false"})
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    tex = (tmp_path / "out" / "n" / "notes.tex").read_text()
    assert r"\usepackage[portuguese]{babel}" in tex
    assert r"\section{O pivô oscilante}" in tex
    assert "The driven pivot" not in tex and "Lagrangian." not in tex


def test_every_template_exists_in_both_languages():
    base = ROOT / "src" / "pendulab" / "templates" / "notes"
    assert sorted(p.name for p in (base / "en").iterdir()) == sorted(p.name for p in (base / "pt").iterdir())


@needs_tex
def test_portuguese_notes_compile_cleanly(tmp_path):
    path = _scene(tmp_path, {"language": '"pt"', "sections": '["pivot", "series", "references"]',
                             "series_order": 2})
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    directory = tmp_path / "out" / "n"
    assert (directory / "notes.pdf").read_bytes().startswith(b"%PDF-")
    code, log = pdflatex_twice(directory)
    assert code == 0 and log_problems(log) == []


# -- without TeX -------------------------------------------------------------------------------

def test_without_tex_the_tex_is_written_and_the_pdf_left_out_in_one_line(tmp_path, monkeypatch):
    from pendulab.products import notes
    monkeypatch.setattr(notes, "tex_engine", lambda: None)
    path = _scene(tmp_path, {"sections": '["pivot"]'})
    lines = []
    build(path, tmp_path / "out", log=lines.append, jobs=1)
    directory = tmp_path / "out" / "n"
    assert (directory / "notes.tex").is_file() and not (directory / "notes.pdf").exists()
    said = [line for line in lines if "notes.pdf" in line]
    assert len(said) == 1 and "neither pdflatex nor latexmk" in said[0] and "not written" in said[0]


def test_without_tex_the_pdf_built_before_from_the_same_inputs_is_kept(tmp_path, monkeypatch):
    from pendulab.products import notes
    out = tmp_path / "out"
    shutil.copytree(BUILT, out / "lecture-notes")
    monkeypatch.setattr(notes, "tex_engine", lambda: None)
    lines = []
    build(SCENE, out, force=True, log=lines.append)
    assert (out / "lecture-notes" / "notes.pdf").read_bytes() == (BUILT / "notes.pdf").read_bytes()
    assert any("kept as built before from the same inputs" in line for line in lines)


@needs_tex
def test_without_tex_a_pdf_of_other_inputs_is_not_kept(tmp_path, monkeypatch):
    from pendulab.products import notes
    out = tmp_path / "out"
    # an earlier build of this scene name, from other options: its PDF does not show this notes.tex
    path = _scene(tmp_path, {"sections": '["pivot"]'})
    build(path, out, log=lambda m: None, jobs=1)
    assert (out / "n" / "notes.pdf").exists()
    path.write_text(path.read_text().replace('["pivot"]', '["pivot", "series"]'))
    monkeypatch.setattr(notes, "tex_engine", lambda: None)
    lines = []
    build(path, out, log=lines.append, jobs=1)
    assert not (out / "n" / "notes.pdf").exists()
    assert any("not written" in line for line in lines)


# -- scenes the prose would be false for -------------------------------------------------------

@pytest.mark.parametrize("parameters, sections, fragment", [
    ('angle = "down"', '["pivot"]', 'angle must be "up"'),
    ('drive = "a*cos(omega*t) + b*cos(2*omega*t)"', '["stability"]', "leave stability and simulations out"),
    ('drive = "a*cos(omega*t) + b*cos(2*omega*t)"', '["simulations"]', "leave stability and simulations out"),
])
def test_scenes_the_notes_would_misdescribe_are_refused(tmp_path, capsys, parameters, sections, fragment):
    path = tmp_path / "n.toml"
    path.write_text(f'name = "n"\nsystem = "kapitza"\n[parameters]\n{parameters}\n'
                    f"[products.notes]\nsections = {sections}\npdf = false\n")
    assert main(["build", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0], err
    assert not (tmp_path / "out" / "n").exists()


def test_a_hill_drive_still_gets_its_pivot_section(tmp_path):
    path = tmp_path / "n.toml"
    path.write_text('name = "n"\nsystem = "kapitza"\n[parameters]\n'
                    'drive = "a*cos(omega*t) + b*cos(2*omega*t)"\n'
                    '[products.notes]\nsections = ["pivot"]\npdf = false\n')
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    tex = (tmp_path / "out" / "n" / "notes.tex").read_text()
    assert r"\paragraph{Hill's form.}" in tex and "Mathieu's form." not in tex


def test_the_scenes_name_and_description_are_printed_as_written(tmp_path):
    path = tmp_path / "n.toml"
    path.write_text('name = "aula_3"\nsystem = "kapitza"\ndescription = "A & B: 100% RK4, C# ~5"\n'
                    '[products.notes]\nsections = ["pivot"]\npdf = false\n')
    build(path, tmp_path / "out", log=lambda m: None, jobs=1)
    tex = (tmp_path / "out" / "aula_3" / "notes.tex").read_text()
    assert r"\texttt{aula\_3}" in tex and r"A \& B: 100\% RK4, C\# \textasciitilde{}5" in tex


def test_the_pdf_left_out_without_tex_is_made_once_tex_is_there(tmp_path, monkeypatch):
    from pendulab.products import notes
    path = _scene(tmp_path, {"sections": '["pivot"]'})
    out = tmp_path / "out"
    monkeypatch.setattr(notes, "tex_engine", lambda: None)
    build(path, out, log=lambda m: None, jobs=1)
    assert not (out / "n" / "notes.pdf").exists()
    lines = []
    build(path, out, log=lines.append, jobs=1)  # still no TeX: nothing to do
    assert any("up to date" in line for line in lines)
    monkeypatch.setattr(notes, "tex_engine", lambda: "pdflatex")  # TeX installed since
    monkeypatch.setattr(notes, "compile_pdf", lambda files, engine: b"%PDF-1.5 made")
    lines = []
    build(path, out, log=lines.append, jobs=1)
    assert (out / "n" / "notes.pdf").read_bytes() == b"%PDF-1.5 made"
    assert not any("up to date" in line for line in lines)
