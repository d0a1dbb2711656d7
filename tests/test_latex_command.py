"""``pendulab latex``: one fragment on stdout, compiling strictly with the packages it names.

Each kind's output is compiled as tests/test_latex.py compiles the committed
fragments (a bare article, two pdflatex passes, no error, no float too large,
no overfull hbox over 1pt, no undefined reference), loading only the packages
its header names.  Its content is checked against facts from outside pendulab:
the sources' equations (000 eqs. 5, 6, 12, 20-22; 002's quarter periods) and
published tables of Bessel zeros (Abramowitz & Stegun Table 9.5, DLMF 10.21).
"""

import re
import shlex
from fractions import Fraction

import pytest
import sympy as sp

from pendulab.cli import main
from test_latex import needs_pdflatex, strict_problems


def run(argv, capsys):
    """(exit status, stdout, stderr) of ``pendulab latex ...``."""
    try:
        status = main(["latex"] + argv)
    except SystemExit as exc:  # argparse's own usage errors
        status = exc.code
    out = capsys.readouterr()
    return status, out.out, out.err


def header_packages(fragment):
    """The packages the header comment names (``% needs: \\usepackage{...}``)."""
    head = [line for line in fragment.splitlines() if line.startswith("% needs:")]
    assert len(head) == 1, fragment[:300]
    return re.findall(r"\\usepackage\{([a-z]+)\}", head[0])


#: one command of each kind (cheap options), and cases that once ran off the page
KINDS = [
    ["series", "--order", "4"],
    ["series", "--order", "8", "--kind", "a0", "--kind", "b1"],
    ["eom", "kapitza"],
    ["eom", "kapitza", "--body", "point", "--drive",
     "a*cos(omega*t) + b*cos(2*omega*t) + c*sin(3*omega*t) + d*cos(4*omega*t)"],
    ["eom", "variable-length"],
    # 21 ratios: the rod's committed table gave "Float too large" in one float
    ["stability", "--points", "21", "--methods", "exact,eq12,eq19,eq28,series:4"],
    # 8 methods: more columns than one tabular holds
    ["stability", "--points", "4", "--max-ratio", "10",
     "--methods", "eq12,eq19,eq19-corrected,eq28,series:2,series:3,integer-series:2,integer-series:4"],
    ["zeros"],
    ["zeros", "--nu", "1/3", "--nu", "2.5", "--nu", "0", "--nu", "300", "--count", "65",
     "--dps", "15"],
    ["quarter-periods", "--count", "6"],
    ["quarter-periods", "--count", "5", "--length", "L0 - v0*t"],
]


@needs_pdflatex
@pytest.mark.parametrize("argv", KINDS, ids=lambda a: " ".join(a)[:60])
def test_each_kind_compiles_strictly_with_only_the_packages_it_names(argv, capsys, tmp_path):
    status, out, err = run(argv, capsys)
    assert status == 0 and err == "", err
    packages = header_packages(out)
    assert packages and set(packages) <= {"amsmath", "booktabs"}
    assert strict_problems(out, tmp_path, packages=packages) == []


@needs_pdflatex
def test_a_fragment_without_the_packages_it_names_does_not_compile(capsys, tmp_path):
    # the check of the check: the header's packages are really needed
    status, out, _err = run(["zeros", "--count", "2"], capsys)
    assert status == 0
    assert strict_problems(out, tmp_path, packages=()) != []


@pytest.mark.parametrize("argv", [KINDS[0], KINDS[2], KINDS[7], ["stability", "--points", "3"]],
                         ids=lambda a: " ".join(a)[:40])
def test_stdout_is_the_fragment_and_its_header_names_the_command(argv, capsys):
    status, out, err = run(argv, capsys)
    assert status == 0 and err == ""
    lines = out.splitlines()
    head = [line for line in lines[:3] if line.startswith("%")]
    assert lines[0].startswith("% made by: pendulab latex " + argv[0])
    assert any(line.startswith("% needs: ") for line in head)
    body = [line for line in lines if line and not line.startswith("%")]
    assert body[0].startswith("\\begin") and body[-1].startswith("\\end")
    # the command in the header, every option written out, makes the same fragment
    command = lines[0][len("% made by: "):].split("   (pendulab")[0]
    again = shlex.split(command)
    assert again[:2] == ["pendulab", "latex"]
    status, out2, _err = run(again[2:], capsys)
    assert status == 0 and out2 == out


@pytest.mark.parametrize("argv, where", [
    (["series"], "--order"),
    (["series", "--order", "0"], "--order"),
    (["series", "--order", "x"], "--order"),
    (["series", "--order", "31"], "--order"),             # kind nu: at most 30 in LaTeX
    (["series", "--order", "3", "--kind", "c7"], "--kind"),
    (["series", "--order", "3", "--kind", "nu", "--kind", "nu"], "--kind"),
    (["eom"], "SYSTEM"),
    (["eom", "pendulum"], "SYSTEM"),
    (["eom", "kapitza", "--length", "L0 + v0*t"], "--length"),
    (["eom", "kapitza", "--drive", "cos(("], "--drive"),
    (["eom", "kapitza", "--inertia", "m*l**2"], "--inertia"),
    (["eom", "variable-length", "--length", "-L0"], "--length"),
    (["stability", "--points", "1"], "--points"),
    (["stability", "--max-ratio", "0"], "--max-ratio"),
    (["stability", "--methods", "exact,nope"], "--methods"),
    (["stability", "--body", "cube"], "--body"),
    (["stability", "--points", "401", "--methods", "exact,series:40"], "--points and --methods"),
    (["zeros", "--nu", "-1"], "--nu"),
    (["zeros", "--nu", "1", "--nu", "1"], "--nu"),
    (["zeros", "--nu", "1", "--nu", "2", "--nu", "3", "--nu", "4", "--nu", "5"], "--nu"),
    (["zeros", "--count", "10000", "--dps", "1000"], "--count x --dps"),
    (["zeros", "--dps", "0"], "--dps"),
    (["quarter-periods", "--count", "0"], "--count"),
    (["quarter-periods", "--count", "10000", "--dps", "1000"], "--count x --dps"),
    (["quarter-periods", "--length", "L0 + t**2"], "--length"),
    (["nothing"], "WHAT"),
])
def test_bad_arguments_are_one_line_and_nothing_on_stdout(argv, where, capsys):
    status, out, err = run(argv, capsys)
    assert status == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("pendulab: error: "), err
    assert "Traceback" not in err and "usage:" not in err
    assert where in err or where in ("SYSTEM", "WHAT"), err


# -- the content against facts from outside pendulab --------------------------------------------

NU = sp.Symbol("nu")


def _latex_number(tex):
    """The series' LaTeX of a rational function of nu (\\frac, \\nu, ^{k}, juxtaposition) read
    into SymPy by text substitution, without pendulab (a reader for these rows only)."""
    from sympy.parsing.sympy_parser import (implicit_multiplication, parse_expr,
                                            standard_transformations)
    text = tex.replace("\\nu", " nu ")
    text = re.sub(r"\\omega_\{0\}", " w0 ", text).replace("\\omega", " w ")
    text = re.sub(r"\^\{(\d+)\}", r"**\1", text)
    while "\\frac{" in text:  # innermost first
        text, done = re.subn(r"\\frac\{([^{}]*)\}\{([^{}]*)\}", r"((\1)/(\2))", text)
        assert done, tex  # a brace this reader does not know
    return parse_expr(text, local_dict={"nu": NU},
                      transformations=standard_transformations
                      + (implicit_multiplication,))


def _rows(fragment):
    """{left side: right side} of the align rows 'lhs &= rhs'."""
    out = {}
    for line in fragment.splitlines():
        if "&=" in line:
            lhs, rhs = line.split("&=", 1)
            out[lhs.strip()] = rhs.strip().rstrip("\\").strip()
    return out


def test_the_order_2_series_is_the_sources(capsys):
    # 000 eqs. 20-22 worked to second order (sec. 3, before eq. 27): alpha_1 = 0,
    # c_1 = (1/4)[cos((nu+2)tau)/(nu+1) - cos((nu-2)tau)/(nu-1)],
    # alpha_2 = 1/(2 (nu - 1)(nu + 1)),
    # c_2 = (1/32)[cos((nu+4)tau)/((nu+1)(nu+2)) + cos((nu-4)tau)/((nu-1)(nu-2))];
    # alpha_2 is DLMF 28.15.1's q^2 term, 1/(2(nu^2 - 1)), with a = theta0, q = -theta1
    status, out, _err = run(["series", "--order", "2"], capsys)
    assert status == 0
    rows = _rows(out)
    source = {r"\alpha_{1}": sp.Integer(0),
              r"C_{1,1}": 1 / (4 * (NU + 1)), r"C_{1,-1}": -1 / (4 * (NU - 1)),
              r"\alpha_{2}": 1 / (2 * (NU - 1) * (NU + 1)),
              r"C_{2,2}": 1 / (32 * (NU + 1) * (NU + 2)),
              r"C_{2,-2}": 1 / (32 * (NU - 1) * (NU - 2))}
    assert set(source) <= set(rows)
    for name, value in source.items():
        assert sp.simplify(_latex_number(rows[name]) - value) == 0, (name, rows[name])


@pytest.mark.parametrize("body, inertia", [("rod", sp.Rational(4, 3)), ("point", sp.Integer(1))])
def test_the_mathieu_parameters_are_the_sources(body, inertia, capsys):
    # 000 eq. 5: theta0 = -4 omega0^2/omega^2; eq. 6: theta1 = 2 a l m/I, with I = m l^2 for a
    # point mass and 4 m l^2/3 for a rod about its end (sec. 2.1)
    status, out, _err = run(["eom", "kapitza", "--body", body], capsys)
    assert status == 0
    rows = _rows(out)
    a, l, w0, w = sp.symbols("a l w0 w")
    assert sp.simplify(_latex_number(rows[r"\theta_0"]) + 4 * w0**2 / w**2) == 0
    last = rows[r"\theta_1"].split("=")[-1]
    local = _latex_number(last).subs({sp.Symbol("a"): a, sp.Symbol("l"): l})
    assert sp.simplify(local - 2 * a / (inertia * l)) == 0, last


def _table_rows(fragment):
    """The data rows of the tabulars (cells as text), in order."""
    rows = []
    for line in fragment.splitlines():
        if line.endswith("\\\\") and "&" in line and not line.startswith(("$k$", "\\multicolumn",
                                                                          "$\\omega")):
            cells = [c.strip() for c in line[:-2].split("&")]
            if cells[0] and cells[0][0].isdigit():
                rows.append(cells)
    return rows


def test_the_zeros_are_the_published_ones(capsys):
    # Abramowitz & Stegun Table 9.5 (DLMF 10.21(vi), Table 10.21.1): zeros of J1 and J2
    published = {1: ("3.8317059702", "5.1356223018"), 2: ("7.0155866698", "8.4172441404"),
                 3: ("10.1734681351", "11.6198411721")}
    status, out, _err = run(["zeros", "--nu", "1", "--nu", "2", "--count", "3"], capsys)
    assert status == 0
    rows = {int(r[0]): r[1:] for r in _table_rows(out)}
    assert sorted(rows) == [1, 2, 3]
    for k, (j1, j2) in published.items():
        for ours, ref in zip(rows[k], (j1, j2)):
            assert abs(Fraction(ours) - Fraction(ref)) <= Fraction(1, 10**10), (k, ours, ref)


def test_the_quarter_periods_are_the_sources(capsys):
    # 002_19b336b29bb1f03b.txt, last page: the first quarter periods (unit v0/(4 g)),
    # inward then outward: 22.8438, 21.6315, 32.6495, 31.5213
    status, out, _err = run(["quarter-periods", "--count", "2"], capsys)
    assert status == 0
    rows = _table_rows(out)
    ours = [cell for row in rows for cell in row[1:]]
    for mine, src in zip(ours, ["22.8438", "21.6315", "32.6495", "31.5213"]):
        assert abs(Fraction(mine) - Fraction(src)) <= Fraction(1, 20000), (mine, src)
    assert len(ours) == 4


def test_the_eq12_limits_are_the_sources(capsys):
    # 000 eq. 12: sqrt(2) (I/(m l^2)) omega0/omega < a/l
    #             < sqrt(2) (I/(m l^2)) sqrt(omega^2 + pi^2 omega0^2)/(pi omega), point: I = m l^2
    status, out, _err = run(["stability", "--body", "point", "--points", "3",
                             "--methods", "eq12"], capsys)
    assert status == 0
    rows = _table_rows(out)
    assert len(rows) == 6  # three ratios, lower then upper
    import math
    for cells, side in zip(rows, ["lower"] * 3 + ["upper"] * 3):
        r = float(cells[0])
        ref = (math.sqrt(2) * r if side == "lower"
               else math.sqrt(2) * math.sqrt(1 + math.pi**2 * r**2) / math.pi)
        assert abs(float(cells[1]) - ref) < 6e-5, (side, cells, ref)
