"""Every committed LaTeX fragment compiles, and none runs off the page.

Needs pdflatex (Debian: texlive-latex-base, texlive-latex-recommended; .ci/run
installs them).  On a machine without TeX the test is skipped with that reason:
the fragments are still produced and checked for determinism elsewhere.
"""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# fragments, not whole documents (the lecture notes are checked in tests/test_notes.py)
FRAGMENTS = sorted(p for p in (ROOT / "generated").glob("*/*.tex")
                   if "\\documentclass" not in p.read_text())

PREAMBLE = r"""\documentclass[11pt]{article}
\usepackage[a4paper,margin=2.5cm]{geometry}
\usepackage{amsmath}
\usepackage{booktabs}
\begin{document}
"""


@pytest.mark.skipif(shutil.which("pdflatex") is None,
                    reason="pdflatex not installed (apt-get install texlive-latex-base texlive-latex-recommended)")
@pytest.mark.parametrize("fragment", FRAGMENTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_fragment_compiles_without_overfull_boxes(fragment, tmp_path):
    doc = tmp_path / "notes.tex"
    doc.write_text(PREAMBLE + fragment.read_text() + "\n\\end{document}\n")
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", doc.name],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    log = (tmp_path / "notes.log").read_text(errors="replace")
    assert res.returncode == 0, log[-2000:]
    overfull = [line for line in log.splitlines() if line.startswith("Overfull \\hbox")]
    assert not overfull, overfull[:5]


def test_there_are_fragments_to_compile():
    names = {p.name for p in FRAGMENTS}
    assert {"equations.tex", "series.tex", "stability.tex"} <= names
