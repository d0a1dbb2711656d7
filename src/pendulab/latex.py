"""LaTeX text that stays on the page: width estimates and line filling.

SymPy's ``latex`` prints one long line; notes need long sums broken across
the rows of an ``align*`` environment.  :func:`visible_width` estimates how
wide a math fragment prints (in characters: a fraction counts its wider
part, commands such as ``\\left`` count nothing, ``\\theta`` counts one);
:func:`fill` packs tokens greedily into lines of at most ``width``;
:func:`sum_rows` turns ``lhs = expr`` into align rows.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> rows = sum_rows("f", sum(x**k / (k + 1) for k in range(12)), "", width=30)
>>> len(rows) > 1 and all(visible_width(r) <= 36 for r in rows)
True
"""

import re

#: Width (in visible characters) of one line of display math in an 11pt
#: article with 2.5 cm margins; measured by compiling (tests/test_latex.py).
LINE_WIDTH = 64

_GREEK = r"\\(alpha|beta|gamma|delta|epsilon|theta|vartheta|lambda|mu|nu|xi|pi|rho|sigma|tau|phi|psi|omega|Omega|Theta|Delta|Lambda|Psi|Phi|mathcal\{L\}|cdot|partial|infty)"


#: operator names that print as their letters (\\sin is three characters wide)
_OPERATOR = r"\\(sin|cos|tan|cot|sec|csc|sinh|cosh|tanh|exp|log|ln)(?![a-zA-Z])"


def brace_group(tex, start):
    """(content, index after) of the brace group opening at ``tex[start]``."""
    depth = 0
    for i in range(start, len(tex)):
        if tex[i] == "{":
            depth += 1
        elif tex[i] == "}":
            depth -= 1
            if depth == 0:
                return tex[start + 1:i], i + 1
    return tex[start + 1:], len(tex)


def visible_width(tex):
    """Approximate printed width of a math fragment, in characters."""
    i = tex.find("\\frac{")
    if i >= 0:
        numer, j = brace_group(tex, i + 5)
        denom, k = brace_group(tex, j)
        return visible_width(tex[:i]) + max(visible_width(numer), visible_width(denom)) + 1 \
            + visible_width(tex[k:])
    t = re.sub(_GREEK, "x", tex)
    t = re.sub(_OPERATOR, r"\1", t)  # \sin prints its three letters
    t = re.sub(r"\\(quad)", "xx", t)
    t = re.sub(r"\\\\", "", t)
    t = re.sub(r"\\[a-zA-Z]+|\\[,;!]|&", "", t)
    t = re.sub(r"[{}^_]", "", t)
    return len(re.sub(r"\s+", "", t))


def fill(tokens, width=LINE_WIDTH, measure=None, gap=2):
    """Greedy packing of ``tokens`` into lines whose width stays within ``width``: each token
    counts ``measure(token) + gap`` (``measure`` is :func:`visible_width` unless given)."""
    measure = measure or visible_width
    lines, current, used = [], [], 0
    for tok in tokens:
        w = measure(tok) + gap
        if current and used + w > width:
            lines.append(current)
            current, used = [], 0
        current.append(tok)
        used += w
    if current:
        lines.append(current)
    return lines


def _signed(tex, first):
    """``tex`` as the token of a term: "- x" or "+ x" (nothing before the first, unless "-")."""
    if tex.startswith("-"):
        return "- " + tex[1:].lstrip()
    return tex if first else "+ " + tex


def _term_tokens(expr, width=None):
    """Signed LaTeX tokens of the terms of ``expr`` in SymPy's print order.

    A term wider than ``width`` that is a product with one sum among its factors,
    ``c (x + y + ...) f``, is written ``c \\biggl( x + y + ... \\biggr) f`` with the
    sum's terms as tokens of their own, so that the rows may break inside it
    (``\\left( ... \\right)`` cannot span rows).
    """
    import sympy as sp  # here, not at the top: the series command prints without SymPy

    terms = expr.as_ordered_terms() if isinstance(expr, sp.Add) else [expr]
    tokens = []
    for k, term in enumerate(terms):
        tex = sp.latex(term)
        sums = [f for f in term.args if isinstance(f, sp.Add)] if isinstance(term, sp.Mul) else []
        if width is None or visible_width(tex) <= width or len(sums) != 1:
            tokens.append(_signed(tex, k == 0))
            continue
        inner = sums[0]
        rest = sp.Mul(*[f for f in term.args if f is not inner])
        sign = ""
        if rest.could_extract_minus_sign():
            sign, rest = "-", -rest
        coefficient, factors = rest.as_coeff_Mul()
        head = "" if coefficient == 1 else sp.latex(coefficient) + " "
        tail = "" if factors == 1 else " " + sp.latex(factors)
        parts = _term_tokens(inner, width)
        parts[0] = head + r"\biggl(" + parts[0]
        parts[-1] = parts[-1] + r" \biggr)" + tail
        lead = (sign + " " if sign else ("" if k == 0 else "+ "))
        parts[0] = lead + parts[0]
        tokens.extend(parts)
    return tokens


def sum_rows(lhs, expr, rhs="", width=LINE_WIDTH):
    """align* rows for ``lhs = expr`` (or ``expr = rhs`` when ``lhs`` is empty).

    One row when it fits; otherwise the terms of the sum continue on rows that
    start with ``&\\quad``.
    """
    import sympy as sp

    if lhs:
        head, tail = f"{lhs} &= ", ""
    else:
        head, tail = "& ", f" = {rhs}" if rhs != "" else ""
    tokens = _term_tokens(sp.sympify(expr), width - visible_width(head) - 2)
    lines = fill(tokens, width - visible_width(head) - 2)
    rows = []
    for k, line in enumerate(lines):
        text = " ".join(line)
        prefix = head if k == 0 else "&\\quad "
        rows.append(prefix + text + (tail if k == len(lines) - 1 else ""))
    return rows


# -- tables that fit a page -------------------------------------------------------------------

#: Most rows of data one table float holds (a bare 10pt article's page holds about 43
#: lines; two stacked tabulars of this many rows, their headings and a caption fit,
#: tests/test_latex.py compiles them).
FLOAT_ROWS = 15

#: Most data columns beside the first one in one tabular (a column of 4-decimal numbers
#: is about 45pt wide with its separation; a bare article's text is 345pt wide).
FLOAT_COLUMNS = 6

#: Floats in a row after which a long fragment starts a new page (``\clearpage``): LaTeX
#: holds at most 18 unplaced floats, and a fragment of floats only gives it no text to
#: place them beside.
FLOATS_PER_PAGE_RUN = 8


def chunks(count, most):
    """``count`` items cut into the fewest runs of at most ``most``, as even as can be:
    a list of ``range`` objects.

    >>> [list(r) for r in chunks(5, 2)]
    [[0, 1], [2, 3], [4]]
    >>> [len(r) for r in chunks(21, 15)]
    [11, 10]
    """
    if count <= 0:
        return []
    parts = -(-count // most)
    size, extra = divmod(count, parts)
    out, start = [], 0
    for k in range(parts):
        stop = start + size + (1 if k < extra else 0)
        out.append(range(start, stop))
        start = stop
    return out


def tabular(spec, header, rows, title=None):
    """A booktabs ``tabular``: an optional title row spanning all columns, the header, the rows."""
    lines = [f"\\begin{{tabular}}{{{spec}}}", "\\toprule"]
    if title is not None:
        lines += [f"\\multicolumn{{{len(header)}}}{{c}}{{{title}}} \\\\", "\\midrule"]
    lines += [" & ".join(header) + " \\\\", "\\midrule"]
    lines += [" & ".join(row) + " \\\\" for row in rows]
    lines += ["\\bottomrule", "\\end{tabular}"]
    return "\n".join(lines) + "\n"


def table_float(caption, body, placement="htbp", size=None):
    """A ``table`` float: centred, an optional size command (``\\small``), the caption, ``body``."""
    head = [f"\\begin{{table}}[{placement}]", "\\centering"]
    if size:
        head.append(size)
    head.append(f"\\caption{{{caption}}}")
    return "\n".join(head) + "\n" + body + "\\end{table}\n"


def float_run(floats):
    """The floats one after another, with ``\\clearpage`` after every
    :data:`FLOATS_PER_PAGE_RUN` of them when there are more (see there)."""
    out = []
    for k, text in enumerate(floats, start=1):
        out.append(text)
        if k % FLOATS_PER_PAGE_RUN == 0 and k < len(floats):
            out.append("\\clearpage\n")
    return "".join(out)


def part_note(index, parts):
    """" (part 2 of 3)" when a table is cut into ``parts`` floats, else ""."""
    return "" if parts == 1 else f" (part {index + 1} of {parts})"


# -- what a fragment needs ----------------------------------------------------------------------

#: package -> commands or environments of it that a fragment may use
_PACKAGE_MARKS = {
    "amsmath": ("\\begin{align", "\\intertext", "\\text{", "\\allowdisplaybreaks",
                "\\begin{gather", "\\begin{multline", "\\dfrac", "\\tfrac", "\\operatorname"),
    "booktabs": ("\\toprule", "\\midrule", "\\bottomrule", "\\cmidrule"),
    "graphicx": ("\\includegraphics",),
}


def packages_needed(tex):
    """The packages of :data:`_PACKAGE_MARKS` whose commands ``tex`` uses outside its comment
    lines, in a fixed order.

    >>> packages_needed("\\\\begin{align*} x &= 1 \\\\end{align*}")
    ['amsmath']
    >>> packages_needed("\\\\toprule x \\\\\\\\ \\\\bottomrule")
    ['booktabs']
    """
    code = "\n".join(line for line in tex.splitlines() if not line.lstrip().startswith("%"))
    return [name for name, marks in _PACKAGE_MARKS.items() if any(m in code for m in marks)]


# -- the series' rational functions (000 eqs. 20-22; DLMF 28.6) ----------------------------------
# The printer of series.tex.  It lives on this floor so that the series objects of
# pendulab.analyses.series show themselves in a notebook with it (``_repr_latex_``), as
# the product "series" writes them (pendulab.products.series uses these functions).

def series_width(tex):
    """Width of a LaTeX math fragment of the series in characters, roughly as printed
    (a fraction: its wider part)."""
    i = tex.find("\\frac{")
    if i >= 0:
        numer, j = brace_group(tex, i + 5)
        denom, k = brace_group(tex, j)
        inner = max(series_width(numer), series_width(denom))
        return series_width(tex[:i]) + inner + series_width(tex[k:]) + 2
    t = re.sub(r"\\(nu|tau|theta|alpha|cdot|quad|qquad|left|right|bigl|bigr|Bigl|Bigr)", "x", tex)
    t = re.sub(r"\\\\\s*$", "", t.strip())
    t = re.sub(r"\\[a-zA-Z]+|\\,|&", "", t)
    t = re.sub(r"[{}^_]", "", t)
    return len(re.sub(r"\s+", " ", t).strip())


def int_tokens(value, first):
    """Tokens of a signed integer; long integers are split into digit groups."""
    sign = "-" if value < 0 else ("+" if not first else "")
    digits = str(abs(value))
    piece = LINE_WIDTH - 12  # digits of one row: with the widest name and \quad, within the text
    pieces = [digits[i:i + piece] for i in range(0, len(digits), piece)]
    out = []
    for i, ch in enumerate(pieces):
        prefix = (f"{sign} " if sign else "") if i == 0 else ""
        out.append(prefix + ch)
    return out


def poly_tokens(num, var=r"\nu"):
    """Tokens of sum_i num[i] var^i, highest power first (each token a term or a digit group)."""
    tokens = []
    first = True
    for i in range(len(num) - 1, -1, -1):
        c = num[i]
        if not c:
            continue
        power = "" if i == 0 else (var if i == 1 else f"{var}^{{{i}}}")
        if power and abs(c) == 1:
            tokens.append(("- " if c < 0 else ("" if first else "+ ")) + power)
        else:
            parts = int_tokens(c, first)
            if power:
                parts[-1] = parts[-1] + " " + power
            tokens.extend(parts)
        first = False
    return tokens or ["0"]


def factor_tokens(raw, var=r"\nu"):
    """Tokens of the denominator of ``raw``: its integer, then its linear factors (var + j)^e."""
    tokens = int_tokens(raw.den, True) if raw.den != 1 else []
    for j, e in raw.exps:
        f = f"({var} {'+' if j > 0 else '-'} {abs(j)})"
        tokens.append(f if e == 1 else f"{f}^{{{e}}}")
    return tokens or ["1"]


def series_lines(tokens, width):
    """Greedy line filling: lists of tokens whose :func:`series_width` stays within ``width``."""
    return fill(tokens, width, measure=series_width, gap=1)


def ratfun_rows(name, raw):
    """align* rows for ``name = raw``: one \\frac when it fits, else numerator and denominator
    broken.  ``raw`` has ``num`` (integer coefficients, lowest power first), ``den`` (an
    integer) and ``exps`` ((j, e): the factor (nu + j)^e of the denominator), as a
    :class:`~pendulab.analyses.series_ratfun.RatFun`."""
    num_tokens = poly_tokens(raw.num)
    den_tokens = factor_tokens(raw)
    num_text, den_text = " ".join(num_tokens), " ".join(den_tokens)
    sign = ""
    if len(num_tokens) == 1 and num_tokens[0].startswith("- "):
        sign, num_text = "-", num_text[2:]
    if raw.exps or raw.den != 1:
        short = rf"{sign}\frac{{{num_text}}}{{{den_text}}}"
    else:
        short = sign + num_text
    if series_width(name) + series_width(short) + 4 <= LINE_WIDTH and (
            series_width(num_text) <= LINE_WIDTH - 12 and series_width(den_text) <= LINE_WIDTH - 12):
        return [rf"{name} &= {short}"]
    rows = [rf"{name} &= \frac{{N}}{{D}}, \quad \text{{with}}"]
    for label, toks in (("N", num_tokens), ("D", den_tokens)):
        for i, line in enumerate(series_lines(toks, LINE_WIDTH - 6)):
            lhs = f"{label} &= " if i == 0 else r"&\quad "
            joiner = " " if label == "N" else r" \, "
            rows.append(lhs + joiner.join(line))
    return rows


def align(rows):
    """One ``align*`` environment of ``rows`` (amsmath)."""
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


class _Integer:
    """An exact rational c as the (num, den, exps) that :func:`ratfun_rows` prints."""

    def __init__(self, c):
        self.num, self.den, self.exps = (c.numerator,), c.denominator, ()


def mathieu_series_blocks(series):
    """The ``align*`` blocks of series.tex for a :class:`~pendulab.analyses.series.MathieuSeries`:
    for n = 1 .. order, alpha_n and the C_{n,k} (short coefficients share a block of at most
    12 rows; a long one gets its own)."""
    out = []
    for n in range(1, series.order + 1):
        blocks = [ratfun_rows(rf"\alpha_{{{n}}}", series.alpha_raw[n])]
        blocks += [ratfun_rows(rf"C_{{{n},{k}}}", v) for k, v in series.c_raw[n]]
        group = []
        for rows in blocks + [None]:
            if rows is None or (group and len(group) + len(rows) > 12):
                out.append(align(group))
                group = []
            if rows is not None:
                group.extend(rows)
    return out


def characteristic_series_block(series):
    """The ``align*`` block of series.tex for a
    :class:`~pendulab.analyses.series.CharacteristicSeries`: a_m(q) (or b_m(q)) = sum c_p q^p
    + O(q^(order+1)), then each c_p."""
    letter, m = series.kind[0], series.kind[1:]
    powers = [p for p, c in sorted(series.coefficients.items()) if c]
    terms = [f"c_{{{p}}}" + ("" if p == 0 else (" q" if p == 1 else f" q^{{{p}}}")) for p in powers]
    lines = series_lines([("" if i == 0 else "+ ") + t for i, t in enumerate(terms)] or ["0"],
                         LINE_WIDTH - 16)
    rows = [rf"{letter}_{{{m}}}(q) &= " + " ".join(lines[0])]
    rows += [r"&\quad " + " ".join(line) for line in lines[1:]]
    rows[-1] += r" + O(q^{" + str(series.order + 1) + "})"
    for p in powers:
        rows.extend(ratfun_rows(f"c_{{{p}}}", _Integer(series.coefficients[p])))
    return align(rows)


# -- results in a notebook: ``_repr_latex_`` and ``_repr_html_`` ---------------------------------
# The result objects of the API (equations, canonical forms, series, Floquet results, limits,
# zeros, quarter periods) show themselves typeset in Jupyter with these and the printers
# above.  What they return compiles in a bare article with amsmath alone (tests/test_repr_latex.py)
# and is display math that MathJax renders: align*, gather*, array, \text.

def text(words):
    """``words`` as a math-mode ``\\text{...}``, LaTeX's special characters escaped; ``<``,
    ``>`` and ``|`` are set in math between two texts (the text font has no such glyphs).

    >>> print(text("n <= 2, 5% of a_0"))
    \\text{n }<\\text{= 2, 5\\% of a\\_0}
    """
    out = []
    for ch in str(words):
        if ch in "<>|":
            out.append("}" + ch + r"\text{")
        elif ch in "#$%&_{}":
            out.append("\\" + ch)
        elif ch == "\\":
            out.append(r"\textbackslash{}")
        elif ch in "^~":
            out.append({"^": r"\^{}", "~": r"\~{}"}[ch])
        else:
            out.append(ch)
    return r"\text{" + "".join(out) + "}"


_COMPLEX_TEXT = re.compile(r"^(?P<re>[+-]?[0-9.]+(?:e[+-]?\d+)?)(?P<sign>[+-])(?P<im>[0-9.]+(?:e[+-]?\d+)?)j$")
_EXPONENT = re.compile(r"^(?P<mant>[+-]?[0-9.]+)e(?P<exp>[+-]?\d+)$")


def number_tex(value):
    """A number's text as LaTeX: ``1.5e-7`` -> ``1.5 \\cdot 10^{-7}``, ``0.5+2.0j`` (the
    text form of :mod:`pendulab.analyses.floquet_format`) -> ``0.5 + 2.0\\,i``.

    >>> number_tex("-2.5e-07"), number_tex("1.0-0.25j"), number_tex("3")
    ('-2.5 \\\\cdot 10^{-7}', '1.0 - 0.25\\\\,i', '3')
    """
    s = str(value).strip()
    m = _COMPLEX_TEXT.match(s)
    if m:
        return f"{number_tex(m.group('re'))} {m.group('sign')} {number_tex(m.group('im'))}\\,i"
    m = _EXPONENT.match(s)
    if m:
        return f"{m.group('mant')} \\cdot 10^{{{int(m.group('exp'))}}}"
    return s


def number_rows(lhs, number):
    r"""align* rows of ``lhs = number`` (``number`` from :func:`number_tex`): one row when it
    fits :data:`LINE_WIDTH`; else a complex number's imaginary part on a row of its own, and
    a run of digits too long for a row continued on the next ones (``&\quad`` rows), as the
    series' long integers are (:func:`int_tokens`).

    >>> number_rows("x", "0.5 + 2.0\\,i")
    ['x &= 0.5 + 2.0\\,i']
    >>> number_rows("x", "0." + "1" * 40 + " - 0." + "2" * 40 + "\\,i")[1][:14]
    '&\\quad - 0.222'
    >>> rows = number_rows("x", "3." + "1" * 70)
    >>> len(rows), "".join(r.split(" ")[-1] for r in rows) == "3." + "1" * 70
    (2, True)
    """
    row = f"{lhs} &= {number}"
    if visible_width(row) <= LINE_WIDTH:
        return [row]
    m = re.match(r"^(.*\S) ([+-]) (\S+\\,i)$", number)
    parts = [m.group(1), f"{m.group(2)} {m.group(3)}"] if m else [number]
    room = LINE_WIDTH - visible_width(lhs) - 8
    pieces = []
    for part in parts:
        d = re.match(r"^([+-] )?([0-9.]+)(.*)$", part)
        if d is None or len(d.group(2)) <= room:
            pieces.append(part)
            continue
        digits = d.group(2)
        runs = [digits[i:i + room] for i in range(0, len(digits), room)]
        runs[0] = (d.group(1) or "") + runs[0]
        runs[-1] += d.group(3)
        pieces.extend(runs)
    return [f"{lhs} &= {pieces[0]}"] + [rf"&\quad {piece}" for piece in pieces[1:]]


def gather(rows):
    """One ``gather*`` environment of ``rows`` (amsmath)."""
    return "\\begin{gather*}\n" + " \\\\\n".join(rows) + "\n\\end{gather*}"


def math_table(caption, header, rows):
    """A table as display math: ``caption`` (a line of LaTeX math, e.g. from :func:`text`, or
    a list of them) above an ``array`` whose first line is ``header``; every cell is math.
    Needs amsmath only (no float, no booktabs), so it is what a notebook shows;
    :func:`html_table` is its HTML twin."""
    spec = "r" + "l" * (len(header) - 1)
    lines = [f"\\begin{{array}}{{{spec}}}", " & ".join(header) + " \\\\", "\\hline"]
    room = max(12, (LINE_WIDTH - 8) // len(header))
    for row in rows:
        # a run of digits wider than its share of the line continues on the lines below,
        # the other cells of those lines empty
        runs = [[c[i:i + room] for i in range(0, len(c), room)]
                if re.fullmatch(r"[+-]?[0-9.]+", c) and len(c) > room else [c] for c in row]
        for k in range(max(len(r) for r in runs)):
            lines.append(" & ".join(r[k] if k < len(r) else "" for r in runs) + " \\\\")
    lines.append("\\end{array}")
    captions = [caption] if isinstance(caption, str) else list(caption)
    return gather(captions + ["\n".join(lines)])


def html_table(caption, header, rows):
    """An HTML ``<table>``: ``caption``, one header row, one ``<tr>`` per row of ``rows``.
    Cells are text (escaped); a cell between ``$...$`` is math that the notebook typesets.

    >>> html_table("Zeros", ["k", "$j_{1,k}$"], [["1", "3.83"]]).count("<tr>")
    2
    """
    from html import escape
    out = ["<table>", f"<caption>{escape(caption)}</caption>",
           "<thead><tr>" + "".join(f"<th>{escape(h)}</th>" for h in header) + "</tr></thead>",
           "<tbody>"]
    out += ["<tr>" + "".join(f"<td>{escape(str(c))}</td>" for c in row) + "</tr>" for row in rows]
    out += ["</tbody>", "</table>"]
    return "\n".join(out)
