"""The API's results show themselves in a notebook: ``_repr_latex_`` and ``_repr_html_``.

Each result type's ``_repr_latex_()`` is compiled in a bare article that loads amsmath and
nothing else (two pdflatex passes, the strict check of tests/test_latex.py: no error, no
overfull line, ...), and what it shows is checked against facts from outside pendulab: the
sources' equations (000 eqs. 3-7, 002 eqs. 4, 7), DLMF 28.6.1 and 28.15.1 for the series,
sqrt(theta0) for the exponent at theta1 = 0, plain mpmath (besseljzero) for the zeros and
quarter periods, SciPy's Mathieu functions for the stability limits.  ``_repr_html_`` is
parsed with html.parser: well formed, one body row per entry.
"""

import re
from html.parser import HTMLParser

import mpmath
import pytest
import sympy as sp

from pendulab import canonical, equations, symbols as S, systems
from pendulab.analyses import bessel, stability
from pendulab.analyses.bessel_identities import ENGINES, RULES, check_identities
from pendulab.analyses.bessel_periods import quarter_periods
from pendulab.analyses.bessel_zeros import bessel_zeros
from pendulab.analyses.floquet import characteristic_exponent, first_band
from pendulab.analyses.mathieu_branch import branch_point
from pendulab.analyses.series import characteristic_series, mathieu_series
from pendulab.analyses.stability_map import stability_limits
from test_latex import needs_pdflatex, strict_problems

#: what the brief's bare document loads
AMSMATH_ONLY = ("amsmath",)


# -- the results, built once ---------------------------------------------------------------

@pytest.fixture(scope="module")
def rod():
    return equations.derive(systems.DrivenPivot(body="rod"))


@pytest.fixture(scope="module")
def string():
    return equations.derive(systems.VariableLength())


def _results():
    """name -> a function building one result of that type (cheap options)."""
    def rod_eqs():
        return equations.derive(systems.DrivenPivot(body="rod"))

    def string_eqs():
        return equations.derive(systems.VariableLength())

    def bessel_form():
        return canonical.length_form(string_eqs())

    return {
        "Equations (driven pivot)": rod_eqs,
        "Equations (variable length)": string_eqs,
        "PeriodicForm": lambda: canonical.periodic_form(rod_eqs()),
        "BesselForm": bessel_form,
        "BesselSolution": lambda: bessel.closed_form(bessel_form(), systems.VariableLength().length),
        "MathieuSeries": lambda: mathieu_series(6),
        "CharacteristicSeries": lambda: characteristic_series("a0", 12),
        "FloquetResult (stable, arb)": lambda: characteristic_exponent("1/5", "1/10", dps=25),
        "FloquetResult (gap, arb)": lambda: characteristic_exponent("13/10", "9/10", dps=25),
        "FloquetResult (double)": lambda: characteristic_exponent(0.2, 0.1),
        # numbers wider than a line: the imaginary parts go on rows of their own
        "FloquetResult (45 digits)": lambda: characteristic_exponent("1/5", "1/10", dps=45),
        "FloquetResult (gap, 60 digits)": lambda: characteristic_exponent(-2, 0, dps=60),
        "Limits (stability_limits, 50 digits)": lambda: stability_limits("1/10", "4/3", dps=50),
        "Limits (first_band)": lambda: first_band("-1/100", dps=30),
        "Limits (stability_limits)": lambda: stability_limits("1/10", "4/3", dps=20),
        "ZeroSet": lambda: bessel_zeros("1/3", 5, 25),
        "QuarterPeriods": lambda: quarter_periods(4, 15),
        "ZeroSet (70 digits)": lambda: bessel_zeros(1, 3, 70),
        "QuarterPeriods (40 digits)": lambda: quarter_periods(3, 40),
        "ComparisonTable": lambda: stability.comparison([0, 0.1, "1/5"], "4/3",
                                                         ["exact", "eq12", "eq19"]),
        "ComparisonTable (6 methods)": lambda: stability.comparison(
            [0, 0.1], "4/3", ["exact", "eq12", "eq19", "eq19-corrected", "eq28", "series:4"]),
        "IdentityReport": lambda: check_identities(2, 15, [0.5, 3.0, 10.0]),
        "BranchPoint": lambda: branch_point("a1", 15),
        "SwingList": lambda: bessel.quarter_periods(4, 20),
    }


RESULTS = _results()


@needs_pdflatex
@pytest.mark.parametrize("name", sorted(RESULTS))
def test_each_result_compiles_in_a_bare_article_with_amsmath(name, tmp_path):
    tex = RESULTS[name]()._repr_latex_()
    assert isinstance(tex, str) and tex.strip()
    assert strict_problems(tex, tmp_path, packages=AMSMATH_ONLY) == []


@needs_pdflatex
def test_the_compile_check_refuses_a_table_that_needs_booktabs(tmp_path):
    # the check of the check: what the products' booktabs tables need does not pass here
    from pendulab.latex import tabular
    assert strict_problems(tabular("rl", ["k", "x"], [["1", "2"]]), tmp_path,
                           packages=AMSMATH_ONLY) != []


def test_every_result_type_with_a_latex_repr_is_tested():
    # the classes that have a _repr_latex_ in src/ are the ones built above
    import pathlib
    src = pathlib.Path(__file__).resolve().parents[1] / "src" / "pendulab"
    owners = set()
    for path in src.rglob("*.py"):
        text = path.read_text()
        for m in re.finditer(r"^class (\w+)", text, re.M):
            body = text[m.end():].split("\n", 1)[-1]
            nxt = re.search(r"^\S", body, re.M)
            if "def _repr_latex_" in body[:nxt.start() if nxt else None]:
                owners.add(m.group(1))
    built = {type(make()).__name__ for make in RESULTS.values()}
    assert owners == built


# -- what each shows -----------------------------------------------------------------------

def _terms_appear(tex, expr):
    """Every term of ``expr`` (typed from a source) appears in ``tex`` as SymPy prints it."""
    missing = [t for t in sp.Add.make_args(sp.expand(expr))
               if sp.latex(t).lstrip("- ") not in tex]
    assert not missing, (missing, tex)


def test_the_driven_pivot_shows_000_eqs_3_and_4(rod):
    tex = rod._repr_latex_()
    th = S.theta(S.t)
    # 000 eq. 3: omega0^2 = m g l / I and the drive's term (m l a omega^2 / I) cos(omega t)
    assert r"\omega_0^2 &= " + sp.latex(S.m * S.g * S.l / S.I) in tex
    assert sp.latex(S.a * S.l * S.m * S.omega**2 * sp.cos(S.omega * S.t) / S.I) in tex
    # 000 eq. 4: linear in theta about theta = 0 (the inverted position)
    assert r"\theta = 0" in tex and sp.latex(th) + " + " + sp.latex(th.diff(S.t, 2)) in tex
    assert r"\sin{\left(\theta{\left(t \right)} \right)}" in tex  # eq. 3 keeps sin(theta)


def test_the_variable_length_shows_002_eq_4(string):
    tex = string._repr_latex_()
    th, ell = S.theta(S.t), S.L(S.t)
    # 002 eq. 4: L theta'' + 2 L' theta' + g theta = 0
    _terms_appear(tex, ell * th.diff(S.t, 2) + 2 * ell.diff(S.t) * th.diff(S.t) + S.g * th)


def test_the_mathieu_form_shows_000_eqs_5_to_7(rod):
    tex = canonical.periodic_form(rod)._repr_latex_()
    assert "Mathieu" in tex and r"\cos{\left(2 \tau \right)}" in tex          # 000 eq. 7
    assert r"\theta_0 &= " + sp.latex(-4 * S.omega0**2 / S.omega**2) in tex   # 000 eq. 5
    assert r"\theta_1 &= " + sp.latex(2 * S.a * S.m * S.l / S.I) in tex       # 000 eq. 6


def test_the_bessel_form_and_solution_show_002(string):
    form = canonical.length_form(string)
    tex = form._repr_latex_()
    # 002 eq. 7 and the Bessel parameters: z = k L^(1/2), k = 2 sqrt(g)/v0, order p = 1
    assert r"p = 1" in tex and sp.latex(2 * sp.sqrt(S.g) / S.v0) in tex
    sol = bessel.closed_form(form, systems.VariableLength().length)._repr_latex_()
    assert r"J_{1}" in sol and r"Y_{1}" in sol
    assert r"z &= " + sp.latex(2 * sp.sqrt(S.Lvar) * sp.sqrt(S.g) / S.v0) in sol


def test_a_bessel_solution_not_yet_solved_has_no_latex():
    form = canonical.length_form(equations.derive(systems.VariableLength()))
    assert bessel.BesselSolution(form, S.L0 + S.v0 * S.t)._repr_latex_() is None


def test_the_nu_series_shows_dlmf_28_15_1():
    tex = mathieu_series(4)._repr_latex_()
    # DLMF 28.15.1 with q = -theta1: a = nu^2 + q^2/(2(nu^2-1)) + (5nu^2+7) q^4/(32(nu^2-1)^3(nu^2-4))
    assert r"\alpha_{2} &= \frac{1}{2 (\nu - 1) (\nu + 1)}" in tex
    assert (r"\alpha_{4} &= \frac{5 \nu^{2} + 7}{32 (\nu - 2) (\nu - 1)^{3} (\nu + 1)^{3} "
            r"(\nu + 2)}") in tex
    assert r"\alpha_{1} &= 0" in tex and r"\alpha_{3} &= 0" in tex


def test_the_nu_series_beyond_the_latex_order_shows_no_latex():
    from pendulab.limits import LIMITS
    top = LIMITS["latex.nu_order"][2]
    assert mathieu_series(top + 1)._repr_latex_() is None


def test_the_integer_series_shows_dlmf_28_6_1():
    tex = characteristic_series("a0", 8)._repr_latex_()
    # DLMF 28.6.1: a_0(q) = -q^2/2 + 7q^4/128 - 29q^6/2304 + 68687q^8/18874368 + ...
    for power, value in ((2, r"-\frac{1}{2}"), (4, r"\frac{7}{128}"), (6, r"-\frac{29}{2304}"),
                         (8, r"\frac{68687}{18874368}")):
        assert f"c_{{{power}}} &= {value}" in tex
    assert "O(q^{9})" in tex
    # the radius: the branch point nearest 0 of a_0, |q| = 1.4687686... (DLMF Table 28.6.1)
    assert re.search(r"\|q\| < 1\.468768", tex)


def _row(tex, label):
    """The align* row that starts ``label &= ``."""
    row = next(line for line in tex.splitlines() if line.startswith(label + " &= "))
    return row


def test_the_exponent_shows_its_certified_digits():
    # theta1 = 0: lam = sqrt(theta0) exactly (DLMF 28.2.16 with q = 0)
    with mpmath.workdps(40):
        root2 = mpmath.nstr(mpmath.sqrt(2), 22)
    stable = characteristic_exponent(2, 0, dps=22)._repr_latex_()
    assert _row(stable, r"\lambda") == r"\lambda &= " + root2 + r" \\"
    assert r"stable; 22 significant digits of }\lambda\text{ proved" in stable
    gap = characteristic_exponent(-2, 0, dps=22)._repr_latex_()
    assert root2 + r"\,i" in _row(gap, r"\lambda") and "unstable" in gap


def test_the_exponent_in_a_gap_says_the_digits_are_the_imaginary_parts():
    tex = characteristic_exponent("13/10", "9/10", dps=20)._repr_latex_()
    assert r"\lambda &= 1.0 + " in tex and r"of the imaginary part of }\lambda" in tex


def test_an_exponent_without_a_proof_claims_no_digits():
    for result in (characteristic_exponent(0.2, 0.1), characteristic_exponent("1/5", "1/10", dps=20,
                                                                              method="cf")):
        assert result.certified_digits is None
        tex = result._repr_latex_()
        assert "no digit proved" in tex and "significant digits" not in tex


def _number(tex, label):
    r"""The number on the row ``label &= ...``, its digits joined across the ``&\quad`` rows
    that continue it."""
    lines = [line.rstrip(" \\") for line in tex.splitlines()]
    k = next(i for i, line in enumerate(lines) if line.startswith(label + " &= "))
    out = lines[k][len(label) + 4:]
    for line in lines[k + 1:]:
        if not re.match(r"^&\\quad [0-9]", line):
            break
        out += line[len(r"&\quad "):]
    return out


def _ends(tex):
    """(lower, quantity, upper) of ``lower < quantity < upper`` on one row, or of the rows
    ``lower end of quantity = ...`` and ``upper end of quantity = ...``."""
    m = re.search(r"^(\S+) &< (.+?) < (\S+)$", tex, re.M)
    if m:
        return m.group(1), m.group(2), m.group(3)
    what = re.search(r"^\\text\{lower end of \}(.+?) &= ", tex, re.M).group(1)
    return (_number(tex, r"\text{lower end of }" + what), what,
            _number(tex, r"\text{upper end of }" + what))


def test_wide_numbers_are_continued_on_rows_with_every_digit():
    with mpmath.workdps(80):
        root2 = mpmath.nstr(mpmath.sqrt(2), 60)
    tex = characteristic_exponent(-2, 0, dps=60)._repr_latex_()
    # lam = i sqrt(2) (theta1 = 0): its 60 digits across rows, none lost
    lines = tex.splitlines()
    k = lines.index(r"\lambda &= 0.0 \\")
    joined = lines[k + 1].rstrip(" \\")[len(r"&\quad + "):] + "".join(
        line.rstrip(" \\")[len(r"&\quad "):] for line in lines[k + 2:k + 3])
    assert joined == root2 + r"\,i"
    lo, what, up = _ends(stability_limits("1/10", "4/3", dps=50)._repr_latex_())
    assert what == "a/l" and len(lo) == len(up) == 52   # "0." and 50 digits


def test_the_first_band_shows_30_proved_digits_that_scipy_confirms():
    special = pytest.importorskip("scipy.special")
    tex = first_band("-1/100", dps=30)._repr_latex_()
    lo, what, up = _ends(tex)
    assert what == r"|\theta_1|" and "30 significant digits of each end proved" in tex
    assert len(lo.replace("0.", "", 1)) == 30 and len(up.replace("0.", "", 1)) == 30
    # the ends solve a_0(q) = theta0 and b_1(q) = theta0 (SciPy, double precision)
    assert special.mathieu_a(0, float(lo)) == pytest.approx(-0.01, abs=1e-9)
    assert special.mathieu_b(1, float(up)) == pytest.approx(-0.01, abs=1e-9)


def test_the_stability_limits_bound_a_over_l():
    special = pytest.importorskip("scipy.special")
    optimize = pytest.importorskip("scipy.optimize")
    tex = stability_limits(0, "4/3", dps=20)._repr_latex_()
    lo, what, up = _ends(tex)
    assert what == "a/l" and "20 significant digits of each end proved" in tex
    # omega0/omega = 0: theta0 = 0 (000 eq. 5), upper end b_1(q) = 0 with
    # a/l = q (I/(m l^2))/2 (000 eq. 6), the rod's I/(m l^2) = 4/3
    q = optimize.brentq(lambda x: special.mathieu_b(1, x), 0.5, 1.5, xtol=1e-14)
    assert float(up) == pytest.approx(q * 4 / 3 / 2, rel=1e-9)
    assert float(lo) == 0


def test_limits_in_double_precision_do_not_claim_digits():
    tex = first_band(-0.01)._repr_latex_()
    assert "not counted" in tex and "proved" not in tex


class _Table(HTMLParser):
    """Rows of the body of the one table of a page, with a check that tags nest."""

    def __init__(self):
        super().__init__()
        self.stack, self.rows, self.caption, self._in_body, self._cell = [], [], "", False, None

    def handle_starttag(self, tag, attrs):
        self.stack.append(tag)
        if tag == "tbody":
            self._in_body = True
        elif tag == "tr" and self._in_body:
            self.rows.append([])
        elif tag == "td":
            self._cell = ""

    def handle_endtag(self, tag):
        assert self.stack and self.stack[-1] == tag, (self.stack, tag)
        self.stack.pop()
        if tag == "tbody":
            self._in_body = False
        elif tag == "td":
            self.rows[-1].append(self._cell)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data
        elif self.stack and self.stack[-1] == "caption":
            self.caption += data


def parse_table(html):
    parser = _Table()
    parser.feed(html)
    parser.close()
    assert parser.stack == [], parser.stack
    return parser


def test_the_parser_refuses_a_badly_nested_table():
    with pytest.raises(AssertionError):
        parse_table("<table><tbody><tr><td>1</tr></td></tbody></table>")


def test_the_zeros_table_has_one_row_per_zero_and_mpmaths_digits():
    zeros = bessel_zeros("1/3", 5, 25)
    table = parse_table(zeros._repr_html_())
    assert len(table.rows) == 5 and "25 significant digits" in table.caption
    with mpmath.workdps(40):
        reference = [mpmath.nstr(mpmath.besseljzero(mpmath.mpf(1) / 3, k), 25) for k in range(1, 6)]
    assert [row[1] for row in table.rows] == reference
    assert [row[0] for row in table.rows] == ["1", "2", "3", "4", "5"]
    tex = zeros._repr_latex_()
    assert all(f"{k} & {value} \\\\" in tex for k, value in enumerate(reference, start=1))
    assert "j_{1/3,k}" in tex


def test_the_quarter_periods_table_has_one_row_per_k_and_002s_values():
    periods = quarter_periods(4, 15)
    table = parse_table(periods._repr_html_())
    assert len(table.rows) == 4 and "claim holds" in table.caption
    # 002's last page: 22.8438, 21.6315, 32.6495 (growing string, z0 = j_2,1)
    assert table.rows[0][1].startswith("22.8438") and table.rows[0][2].startswith("21.6315")
    assert table.rows[1][1].startswith("32.6494")  # 002 rounds 32.64945... up
    # inward[k] = j_1,k+2^2 - j_2,k+1^2, outward[k] = j_2,k+2^2 - j_1,k+2^2 (plain mpmath)
    with mpmath.workdps(40):
        j1 = [None] + [mpmath.besseljzero(1, k) for k in range(1, 7)]
        j2 = [None] + [mpmath.besseljzero(2, k) for k in range(1, 7)]
        for k, row in enumerate(table.rows):
            assert row[1] == mpmath.nstr(j1[k + 2] ** 2 - j2[k + 1] ** 2, 15)
            assert row[2] == mpmath.nstr(j2[k + 2] ** 2 - j1[k + 2] ** 2, 15)


def test_the_comparison_is_still_the_dict_and_a_table_of_one_row_per_ratio():
    special = pytest.importorskip("scipy.special")
    optimize = pytest.importorskip("scipy.optimize")
    table = stability.comparison([0, 0.1, "1/5"], "4/3", ["exact", "eq12", "eq19"])
    assert isinstance(table, dict) and set(table) == {"inertia_ratio", "w0_over_w", "methods",
                                                       "limits"}
    html = parse_table(table._repr_html_())
    assert len(html.rows) == 3 and [r[0] for r in html.rows] == ["0.000", "0.100", "0.200"]
    # ratio 0, exact: upper a/l = (4/3) q / 2 with b_1(q) = 0 (SciPy); eq19 has no upper limit
    q = optimize.brentq(lambda x: special.mathieu_b(1, x), 0.5, 1.5, xtol=1e-14)
    assert html.rows[0][1] == f"0.0000, {q * 2 / 3:.4f}"
    assert html.rows[1][3].endswith(", ---")
    # eq19 (000 eq. 19): lower a/l = sqrt(2 I/(m l^2)) omega0/omega, at 0.1 with the rod
    assert html.rows[1][3].startswith(f"{(2 * 4 / 3) ** 0.5 * 0.1:.4f}")
    assert r"\text{---}" in table._repr_latex_()


def test_the_identity_report_has_one_row_per_engine_and_identity():
    report = check_identities(2, 15, [0.5, 3.0, 10.0])
    table = parse_table(report._repr_html_())
    assert len(table.rows) == len(ENGINES) * len(RULES) == 8
    assert {(r[0], r[1]) for r in table.rows} == {(e, r.replace("_", " ")) for e in ENGINES
                                                  for r in RULES}
    # the identities hold exactly (DLMF 10.5.2, 10.6.2, 10.6.3): at 15 digits both engines
    # err by less than 10^-15, on the points asked for
    assert all(float(r[2]) < 1e-15 and float(r[3]) in (0.5, 3.0, 10.0) for r in table.rows)
    assert "every arb ball contains its exact value" in table.caption
    assert r"\text{every arb ball contains its exact value}" in report._repr_latex_()


@pytest.mark.parametrize("kind,column", [("a0", "rho1"), ("b2", "rho2"), ("a1", "rho3")])
def test_the_branch_point_shows_the_radius_of_dlmf_table_28_6_1(kind, column):
    import csv
    import pathlib
    data = pathlib.Path(__file__).resolve().parent / "data" / "dlmf_table_28_6_1.csv"
    rows = list(csv.DictReader(line for line in data.read_text().splitlines()
                               if not line.startswith("#")))
    radius = float(rows[0][column])            # the row "0 or 1", 10 decimals as printed
    tex = branch_point(kind, 15)._repr_latex_()
    shown = re.search(r"^\|q\| &= (\S+)$", tex, re.M)
    assert shown and abs(float(shown.group(1)) - radius) < 1e-10
    assert len(shown.group(1).replace(".", "")) == 15
    assert f"{kind[0]}_{{{kind[1:]}}}(q)" in tex


def test_the_swing_list_is_still_a_list_and_a_table_of_one_row_per_quarter_period():
    swings = bessel.quarter_periods(5, 20)
    assert isinstance(swings, list) and len(swings) == 5 and swings[0]["direction"] == "toward"
    table = parse_table(swings._repr_html_())
    assert len(table.rows) == 5
    assert [r[3] for r in table.rows] == ["toward", "outward", "toward", "outward", "toward"]
    # 002's last page: 22.8438, 21.6315, 32.6495; in general j_1,k+1^2 - j_2,k^2 (toward) and
    # j_2,k+1^2 - j_1,k+1^2 (outward), plain mpmath
    assert [r[4][:7] for r in table.rows[:2]] == ["22.8438", "21.6315"]
    with mpmath.workdps(40):
        z = [mpmath.besseljzero(2, 1)]
        for k in range(2, 5):
            z += [mpmath.besseljzero(1, k), mpmath.besseljzero(2, k)]
        reference = [mpmath.nstr(z[i + 1] ** 2 - z[i] ** 2, 15) for i in range(5)]
    assert [r[4] for r in table.rows] == reference


def test_a_long_zero_continues_on_the_lines_below_with_every_digit():
    tex = bessel_zeros(1, 2, 70)._repr_latex_()
    with mpmath.workdps(90):
        first = mpmath.nstr(mpmath.besseljzero(1, 1), 70)
    lines = [line.rstrip(" \\") for line in tex.splitlines()]
    k = next(i for i, line in enumerate(lines) if line.startswith("1 & "))
    digits = lines[k][4:]
    for line in lines[k + 1:]:
        if not line.startswith(" & "):
            break
        digits += line[3:]
    assert digits == first


def test_six_methods_are_two_arrays_of_three_with_every_cell():
    table = stability.comparison([0, 0.1], "4/3",
                                 ["exact", "eq12", "eq19", "eq19-corrected", "eq28", "series:4"])
    tex = table._repr_latex_()
    assert tex.count(r"\begin{array}") == 2 and "(part 2 of 2)" in tex
    html = parse_table(table._repr_html_())
    assert len(html.rows) == 2 and all(len(r) == 7 for r in html.rows)
    for row in html.rows:   # every cell of the HTML row is in the LaTeX too
        assert all(c.replace("---", r"\text{---}") in tex for c in row)
