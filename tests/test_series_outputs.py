"""Outputs of the series: JSON, LaTeX, the generated module, the command line and the scene product."""

import importlib.util
import json
import os
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

from pendulab import symbols as S
from pendulab.analyses import series as se
from pendulab.cli import main
from pendulab.errors import InputError
from pendulab.exprs import load_expr
from pendulab.io import canonical_json
from pendulab.products import series as product

SRC = str(Path(__file__).resolve().parents[1] / "src")


def _cli(*args, seed="0"):
    env = dict(os.environ, PYTHONPATH=SRC, PYTHONHASHSEED=seed)
    return subprocess.run([sys.executable, "-m", "pendulab", "series", *args],
                          capture_output=True, text=True, env=env, timeout=120)


# -- JSON -----------------------------------------------------------------------------------

def test_json_keys_and_round_trip():
    rec = product.record("nu", 8)
    assert {"alpha", "c", "s", "order", "kind"} <= set(rec)
    s = se.mathieu_series(8)
    assert sorted(rec["alpha"], key=int) == [str(n) for n in range(1, 9)]
    for n in range(1, 9):
        assert load_expr(rec["alpha"][str(n)]) == s.alpha[n]
        assert [k for k, _ in rec["c"][str(n)]] == [k for k, _ in s.c[n]]
        for (k, text), (k2, expr) in zip(rec["c"][str(n)], s.c[n]):
            assert load_expr(text) == expr
    assert rec["s"] == rec["c"]


def test_every_json_string_reads_back_to_the_exact_coefficient():
    """The strings are written from the exact data (not by SymPy's printer); SymPy reads them back."""
    rec = product.record("nu", 14)
    s = se.mathieu_series(14)
    locals_ = {"nu": S.nu}
    for n in range(1, 15):
        assert sp.sympify(rec["alpha"][str(n)], locals=locals_) == s.alpha[n]
        for (k, text), (k2, e), (k3, raw) in zip(rec["c"][str(n)], s.c[n], s.c_raw[n]):
            back = sp.sympify(text, locals=locals_)
            assert k == k2 == k3 and back == e
            # and equal as a function, not only as a tree: compare at a rational point
            x = Fraction(5, 7)
            assert back.subs(S.nu, sp.Rational(5, 7)) == sp.Rational(raw.evaluate(x).numerator,
                                                                      raw.evaluate(x).denominator)
            assert "." not in text and "e" not in text.replace("nu", "")   # no floats


def test_long_json_expressions_read_back_with_sympy():
    """Order 20 strings exceed load_expr's length guard; SymPy's own parser reads them back."""
    rec = product.record("nu", 20)
    s = se.mathieu_series(20)
    locals_ = {"nu": S.nu}
    assert sp.sympify(rec["alpha"]["20"], locals=locals_) == s.alpha[20]
    k, text = rec["c"]["20"][3]
    assert sp.sympify(text, locals=locals_) == dict(s.c[20])[k]


def test_integer_kind_json():
    rec = product.record("a0", 8)
    assert set(rec) >= {"coefficients", "radius", "radius_source"}
    # DLMF 28.6.1: a_0(q) = -q^2/2 + 7q^4/128 - 29q^6/2304 + 68687q^8/18874368
    assert rec["coefficients"] == {"0": "0", "1": "0", "2": "-1/2", "3": "0", "4": "7/128", "5": "0",
                                   "6": "-29/2304", "7": "0", "8": "68687/18874368"}
    assert abs(rec["radius"] - 1.4687686138) <= 5e-11     # DLMF Table 28.6.1, rho_0^(1)
    assert rec["radius_source"] == "computed branch point, DLMF Table 28.6.1"


def test_json_is_byte_identical_across_processes():
    a = _cli("--order", "10", "--json", seed="1")
    b = _cli("--order", "10", "--json", seed="2")
    assert a.returncode == b.returncode == 0
    assert a.stdout == b.stdout
    alpha2 = sp.sympify(json.loads(a.stdout)["alpha"]["2"], locals={"nu": S.nu})
    assert sp.cancel(alpha2 - 1 / (2 * (S.nu**2 - 1))) == 0          # 000 eq. 27


# -- LaTeX ------------------------------------------------------------------------------------

def test_latex_lines_fit_and_are_deterministic():
    text = product.latex_text(["nu", "a0", "b1"], 24)
    assert text == product.latex_text(["nu", "a0", "b1"], 24)
    assert text.count("\\begin{align*}") == text.count("\\end{align*}")
    assert text.count("{") == text.count("}")
    widths = [product._visible(line) for line in text.splitlines() if not line.startswith("%")]
    assert max(widths) <= product.LINE_WIDTH
    # long coefficients really are broken across lines
    assert "&\\quad" in text
    # every alpha_n appears exactly once
    for n in range(1, 25):
        assert text.count(f"\\alpha_{{{n}}} &=") == 1


def test_latex_is_byte_identical_across_processes():
    """Different hash seeds (set iteration order) must not change a byte of the LaTeX."""
    a = _cli("--order", "8", "--kind", "nu", "--latex", seed="3")
    b = _cli("--order", "8", "--kind", "nu", "--latex", seed="4")
    c = _cli("--order", "8", "--kind", "b1", "--latex", seed="5")
    d = _cli("--order", "8", "--kind", "b1", "--latex", seed="6")
    assert a.returncode == b.returncode == c.returncode == d.returncode == 0
    assert a.stdout == b.stdout and c.stdout == d.stdout
    assert "\\alpha_{8}" in a.stdout and "\\begin{align" in c.stdout


def test_latex_of_a_short_coefficient():
    text = product.latex_text(["nu"], 2)
    assert "\\alpha_{2} &= \\frac{1}{2 (\\nu - 1) (\\nu + 1)}" in text     # 000 eq. 27
    assert "C_{1,-1} &= -\\frac{1}{4 (\\nu - 1)}" in text


def test_visible_width_measure_can_fail():
    assert product._visible("1" * 100) > product.LINE_WIDTH


# -- generated Python module ------------------------------------------------------------------------

def _load_module(text, tmp_path):
    path = tmp_path / "series_coefficients.py"
    path.write_text(text)
    spec = importlib.util.spec_from_file_location("series_coefficients_test", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_generated_module_holds_the_exact_coefficients(tmp_path):
    text = product.python_module_text(["nu", "a0", "b1"], 10, "a test")
    assert text.startswith("# Generated by pendulab") and "Do not edit" in text
    assert text == product.python_module_text(["nu", "a0", "b1"], 10, "a test")
    mod = _load_module(text, tmp_path)
    s = se.mathieu_series(10)
    x = Fraction(3, 7)
    for n in range(1, 11):
        assert mod.value(mod.ALPHA[n], x) == s.alpha_raw[n].evaluate(x)
        for k, v in s.c_raw[n]:
            assert mod.value(mod.C[n][k], x) == v.evaluate(x)
    t1 = Fraction(1, 5)
    assert mod.theta0(x, t1) == x * x + sum(a.evaluate(x) * t1**n for n, a in s.alpha_raw.items())
    assert mod.CHARACTERISTIC["b1"] == se.characteristic_series("b1", 10).coefficients
    assert mod.RADIUS == {"a0": se.RADII["a0"], "b1": se.RADII["b1"]}
    # DLMF Table 28.6.1: rho_0^(1) = 1.4687686138, rho_0^(3) = 3.7699574940 (to half a unit)
    assert abs(mod.RADIUS["a0"] - 1.4687686138) <= 5e-11 and abs(mod.RADIUS["b1"] - 3.769957494) <= 5e-11


# -- command line ---------------------------------------------------------------------------------------

def test_cli_text_and_formats(capsys):
    assert main(["series", "--order", "2"]) == 0
    out = capsys.readouterr().out
    assert "alpha_2 = " in out and "C[1][1] = " in out
    assert main(["series", "--order", "4", "--kind", "b1", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["coefficients"]["1"] == "-1" and abs(rec["radius"] - 3.769957494) <= 5e-11   # DLMF Table 28.6.1
    assert main(["series", "--order", "3", "--latex"]) == 0
    assert "\\begin{align*}" in capsys.readouterr().out


@pytest.mark.parametrize("args,fragment", [
    (["--order", "0"], "order must be an integer from 1"),
    (["--order", "61"], "order must be an integer from 1"),
    (["--order", "3", "--kind", "c2"], "kind must be"),
    (["--order", "3", "--kind", "b0"], "b0"),
])
def test_cli_bad_input_exits_2_with_one_line(args, fragment):
    res = _cli(*args)
    assert res.returncode == 2
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0]


def test_cli_rejects_two_formats():
    res = _cli("--order", "3", "--json", "--latex")
    assert res.returncode == 2 and "not allowed with" in res.stderr


# -- scene product ------------------------------------------------------------------------------------

class _Scene:
    name = "series-test"


class _Ctx:
    scene = _Scene()

    def get(self, name):          # the series product needs no stage
        raise AssertionError(f"stage {name} should not run")


def test_product_files_and_options():
    assert product.OPTIONS["order"][:2] == (int, 8)
    files = product.produce(_Ctx(), {"order": 6, "kinds": ["nu", "a0", "b1"]})
    assert sorted(files) == ["series.json", "series.tex", "series_coefficients.py"]
    data = json.loads(files["series.json"])
    assert data["order"] == 6 and set(data["series"]) == {"nu", "a0", "b1"}
    assert files["series.json"] == canonical_json(data)
    assert files == product.produce(_Ctx(), {"order": 6, "kinds": ["nu", "a0", "b1"]})


def test_product_bad_options_list_every_problem():
    with pytest.raises(InputError) as info:
        product.produce(_Ctx(), {"order": 0, "kinds": ["nu", "x1", "nu"]})
    msg = str(info.value)
    assert "order must be" in msg and "'x1'" in msg and "listed twice" in msg and "\n" not in msg


def test_build_writes_the_series_product(tmp_path):
    scene = tmp_path / "series-scene.toml"
    scene.write_text('name = "series-scene"\nsystem = "kapitza"\n\n[parameters]\nbody = "rod"\n\n'
                     '[products.series]\norder = 4\nkinds = ["nu", "b1"]\n')
    out = tmp_path / "generated"
    assert main(["build", str(scene), "--out", str(out)]) == 0
    d = out / "series-scene"
    assert (d / "series.json").exists() and (d / "series.tex").exists()
    first = (d / "series.json").read_bytes()
    assert main(["build", str(scene), "--out", str(out), "--force"]) == 0
    assert (d / "series.json").read_bytes() == first
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\nsystem = "kapitza"\n\n[products.series]\norder = 500\n')
    assert main(["build", str(bad), "--out", str(out)]) == 2
    assert not (out / "bad").exists()


@pytest.mark.skipif(__import__("shutil").which("pdflatex") is None, reason="pdflatex not installed")
def test_latex_compiles_without_overfull_boxes(tmp_path):
    """A long series (order 24, with the integer kinds) stays on the page (pdflatex's own verdict)."""
    doc = tmp_path / "series.tex"
    doc.write_text("\\documentclass[11pt]{article}\n\\usepackage[a4paper,margin=2.5cm]{geometry}\n"
                   "\\usepackage{amsmath}\n\\begin{document}\n"
                   + product.latex_text(["nu", "a0", "b1"], 24) + "\n\\end{document}\n")
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", doc.name],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    log = (tmp_path / "series.log").read_text(errors="replace")
    assert res.returncode == 0, log[-2000:]
    assert not [line for line in log.splitlines() if line.startswith("Overfull")]
