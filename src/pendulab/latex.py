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
    t = re.sub(r"\\(quad)", "xx", t)
    t = re.sub(r"\\\\", "", t)
    t = re.sub(r"\\[a-zA-Z]+|\\[,;!]|&", "", t)
    t = re.sub(r"[{}^_]", "", t)
    return len(re.sub(r"\s+", "", t))


def fill(tokens, width=LINE_WIDTH):
    """Greedy packing of ``tokens`` into lines whose visible width stays within ``width``."""
    lines, current, used = [], [], 0
    for tok in tokens:
        w = visible_width(tok) + 2
        if current and used + w > width:
            lines.append(current)
            current, used = [], 0
        current.append(tok)
        used += w
    if current:
        lines.append(current)
    return lines


def _term_tokens(expr):
    """Signed LaTeX tokens of the terms of ``expr`` in SymPy's print order."""
    import sympy as sp  # here, not at the top: the series command prints without SymPy

    terms = expr.as_ordered_terms() if isinstance(expr, sp.Add) else [expr]
    tokens = []
    for k, term in enumerate(terms):
        tex = sp.latex(term)
        if k == 0:
            tokens.append(tex)
        elif tex.startswith("-"):
            tokens.append("- " + tex[1:].lstrip())
        else:
            tokens.append("+ " + tex)
    return tokens


def sum_rows(lhs, expr, rhs="", width=LINE_WIDTH):
    """align* rows for ``lhs = expr`` (or ``expr = rhs`` when ``lhs`` is empty).

    One row when it fits; otherwise the terms of the sum continue on rows that
    start with ``&\\quad``.
    """
    import sympy as sp

    tokens = _term_tokens(sp.sympify(expr))
    if lhs:
        head, tail = f"{lhs} &= ", ""
    else:
        head, tail = "& ", f" = {rhs}" if rhs != "" else ""
    lines = fill(tokens, width - visible_width(head) - 2)
    rows = []
    for k, line in enumerate(lines):
        text = " ".join(line)
        prefix = head if k == 0 else "&\\quad "
        rows.append(prefix + text + (tail if k == len(lines) - 1 else ""))
    return rows
