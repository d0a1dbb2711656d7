"""Every committed LaTeX fragment compiles cleanly in a bare article.

A new user pastes a fragment into ``\\documentclass{article}`` with amsmath,
booktabs and graphicx and nothing else (default margins, 10pt).  Each
fragment is compiled there with two passes of pdflatex, and the test fails on
any LaTeX error, "Float too large", an overfull hbox wider than 1pt, an
undefined reference or citation, or a missing figure file
(:func:`strict_problems`; tests/test_latex_command.py uses the same check for
the output of ``pendulab latex``).

Needs pdflatex (Debian: texlive-latex-base, texlive-latex-recommended; .ci/run
installs them).  On a machine without TeX the test is skipped with that reason:
the fragments are still produced and checked for determinism elsewhere.
"""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# fragments, not whole documents (the lecture notes are checked in tests/test_notes.py)
FRAGMENTS = sorted(p for p in (ROOT / "generated").glob("*/*.tex")
                   if "\\documentclass" not in p.read_text())

#: The packages a bare article of a new user loads.
BARE_PACKAGES = ("amsmath", "booktabs", "graphicx")

#: An overfull hbox up to this width is tolerated (TeX reports 0.2pt for a rounding).
OVERFULL_TOLERANCE_PT = 1.0

needs_pdflatex = pytest.mark.skipif(
    shutil.which("pdflatex") is None,
    reason="pdflatex not installed (apt-get install texlive-latex-base texlive-latex-recommended)")

_OVERFULL = re.compile(r"^Overfull \\hbox \((\d+(?:\.\d+)?)pt too wide\)")
_UNDEFINED = re.compile(r"LaTeX Warning: (Reference|Citation) .* undefined")
_MISSING_FILE = re.compile(r"File `[^']*' not found")


def bare_document(body, packages=BARE_PACKAGES):
    """A bare ``article`` loading ``packages`` (nothing else) around ``body``."""
    uses = "".join(f"\\usepackage{{{p}}}\n" for p in packages)
    return f"\\documentclass{{article}}\n{uses}\\begin{{document}}\n{body}\n\\end{{document}}\n"


def log_problems(log):
    """The problems a pdflatex log shows: errors ("! ..."), "Float too large", overfull
    hboxes wider than :data:`OVERFULL_TOLERANCE_PT`, undefined references or citations,
    missing files.  One text per problem, in the log's order."""
    problems = []
    for line in log.splitlines():
        m = _OVERFULL.match(line)
        if m and float(m.group(1)) > OVERFULL_TOLERANCE_PT:
            problems.append(line.strip())
        elif line.startswith("! "):
            problems.append(line.strip())
        elif "Float too large" in line or _UNDEFINED.search(line) or _MISSING_FILE.search(line):
            problems.append(line.strip())
        elif "There were undefined references" in line or "There were undefined citations" in line:
            problems.append(line.strip())
    return problems


def strict_problems(body, workdir, packages=BARE_PACKAGES):
    """Compile ``body`` in :func:`bare_document` (two pdflatex passes in ``workdir``) and
    return :func:`log_problems` of the last pass run (with the exit status if it is not 0)."""
    workdir = Path(workdir)
    (workdir / "doc.tex").write_text(bare_document(body, packages))
    for _pass in range(2):
        res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error",
                              "-no-shell-escape", "doc.tex"],
                             cwd=workdir, capture_output=True, text=True, timeout=120)
        log = (workdir / "doc.log").read_text(errors="replace")
        problems = log_problems(log)
        if res.returncode != 0:
            problems.append(f"pdflatex exit status {res.returncode}")
            return problems
    return problems


@needs_pdflatex
@pytest.mark.parametrize("fragment", FRAGMENTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_fragment_compiles_strictly_in_a_bare_article(fragment, tmp_path):
    # figures a fragment includes sit beside it in generated/<scene>/
    for figure in fragment.parent.glob("*.pdf"):
        shutil.copy(figure, tmp_path / figure.name)
    assert strict_problems(fragment.read_text(), tmp_path) == []


def test_there_are_fragments_to_compile():
    names = {p.name for p in FRAGMENTS}
    assert {"equations.tex", "series.tex", "stability.tex", "bessel_zeros.tex",
            "bessel_quarter_periods.tex", "motion.tex"} <= names


# -- the check itself refuses what it must -------------------------------------------------

@needs_pdflatex
@pytest.mark.parametrize("body,what", [
    # 60 rows of a float: taller than the page of a bare article (about 43 lines)
    ("\\begin{table}\\centering\\begin{tabular}{r}\\toprule\n"
     + "".join(f"{k} \\\\\n" for k in range(60)) + "\\bottomrule\\end{tabular}\\end{table}",
     "Float too large"),
    ("$" + "x + " * 120 + "x$\n\n\\[" + "x + " * 80 + "x\\]", "Overfull \\hbox"),
    ("see Table~\\ref{tab:nowhere}", "Reference"),
    ("as in \\cite{nobody}", "Citation"),
    ("\\includegraphics{no-such-figure}", "not found"),
    ("\\begin{align*} x &= 1 \\end{align}", "! "),
    ("\\undefinedcommand", "! Undefined control sequence"),
])
def test_the_strict_check_refuses_a_bad_fragment(body, what, tmp_path):
    problems = strict_problems(body, tmp_path)
    assert any(what in p for p in problems), problems


@needs_pdflatex
def test_the_strict_check_accepts_a_slightly_overfull_line_and_a_good_fragment(tmp_path):
    good = ("\\begin{table}\\centering\\caption{A table}\\label{tab:a}\\begin{tabular}{r}"
            "\\toprule 1 \\\\ \\bottomrule\\end{tabular}\\end{table} See Table~\\ref{tab:a}.")
    assert strict_problems(good, tmp_path) == []


def test_log_parsing_reads_the_width_of_an_overfull_box():
    log = ("Overfull \\hbox (0.5pt too wide) in paragraph at lines 3--4\n"
           "Overfull \\hbox (12.3pt too wide) detected at line 7\n")
    assert log_problems(log) == ["Overfull \\hbox (12.3pt too wide) detected at line 7"]
