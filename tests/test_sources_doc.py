"""docs/sources.md has an entry for every equation of the sources that the project cites.

Citations are "000 eq. 19", "(002 eq. 4)", "000 eqs. 20-24", "000 eqs. 12, 19, 28",
"000 eqs. 3, 4, 7", and, for unnumbered formulas, "000, after eq. 19" or
"002, before eq. 7".  They are collected from src/, tests/, docs/ and README.md
and compared with the headings of docs/sources.md ("### 000 eq. 19",
"### 000, after eq. 19 ...").  Both sources' numbered equations (000: 1-28,
002: 1-7, as the documents number them) must all be there.
"""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES_MD = ROOT / "docs" / "sources.md"
SCANNED = [ROOT / "src", ROOT / "tests", ROOT / "docs", ROOT / "README.md"]
SUFFIXES = {".py", ".md", ".j2", ".toml", ".txt", ".tex"}
#: how many equations each document numbers (000_8cba66c4fdf94ac6.txt: (1)-(28),
#: 002_19b336b29bb1f03b.txt: (1)-(7))
NUMBERED = {"000": 28, "002": 7}

# an equation number: one or two digits, not the start of "002" or of a file name
_N = r"\d{1,2}(?![\d_])"
_ITEM = rf"{_N}(?:\s*(?:-{{1,2}}|–|to)\s*{_N})?"
CITATION = re.compile(
    r"(?<![\d_])(000|002)(?:_[0-9a-f]{16}\.txt)?"      # the source, by number or file name
    r"(?:\s+sec\.\s*[\d.]*\d)?,?\s+"                    # "000 sec. 2.3, eqs. 13-19"
    r"(?:(?:[A-Za-z]+\s+){0,3}?(after|before)\s+)?"       # "000, the Lagrangian after eq. 2"
    r"eqs?\.(?:\s|~)*"                                   # "eq. 7", LaTeX's "eq.~7"
    rf"({_ITEM}(?:\s*(?:,|and)\s*(?!00[02]\b){_ITEM})*)")
HEADING = re.compile(r"^### (000|002)\b(.*)$", re.M)


def _numbers(items):
    out = []
    for item in re.split(r"\s*(?:,|and)\s*", items.strip()):
        ends = [int(x) for x in re.findall(r"\d+", item)]
        out.extend(range(ends[0], ends[-1] + 1) if len(ends) == 2 else ends)
    return out


def citations(text):
    """({(source, n)}, {(source, "after"|"before", n)}) cited in ``text``."""
    numbered, placed = set(), set()
    for source, place, items in CITATION.findall(text):
        for n in _numbers(items):
            if place:
                placed.add((source, place, n))
            else:
                numbered.add((source, n))
    return numbered, placed


def documented():
    """The same two sets, from the headings of docs/sources.md: "### 000 eq. 19" is an
    equation, "### 000, after eq. 26 (before eq. 27)" a place named both ways."""
    numbered, placed = set(), set()
    for source, rest in HEADING.findall(SOURCES_MD.read_text()):
        number = re.match(r" eq\. (\d+)\b", rest)
        if number:
            numbered.add((source, int(number.group(1))))
        for place, n in re.findall(r"\b(after|before) eq\. (\d+)\b", rest):
            placed.add((source, place, int(n)))
    return numbered, placed


def _project_citations():
    numbered, placed, where = set(), set(), {}
    for base in SCANNED:
        files = [base] if base.is_file() else sorted(p for p in base.rglob("*") if p.suffix in SUFFIXES)
        for path in files:
            if "__pycache__" in path.parts:
                continue
            n, p = citations(path.read_text(errors="replace"))
            for key in n | p:
                where.setdefault(key, path.relative_to(ROOT))
            numbered |= n
            placed |= p
    return numbered, placed, where


def test_the_parser_reads_ranges_lists_and_places():
    # built by concatenation so that this file itself cites nothing it does not mean
    text = ("see (000" + " eqs. 20-22, 27 and 31) and 002" + " eq. 4; 000," + " after eq. 10; 002,"
            + " before eq. 7 and 000_8cba66c4fdf94ac6.txt" + " eq. 5; 000" + " eq. 19 and 002"
            + " eq. 3; 000" + " sec. 2.3, eqs. 13-14; 002" + " eqs.~5--6; 000," + " the text before eq. 11")
    numbered, placed = citations(text)
    assert numbered == {("000", 20), ("000", 21), ("000", 22), ("000", 27), ("000", 31),
                        ("002", 4), ("000", 5), ("000", 19), ("002", 3), ("000", 13), ("000", 14),
                        ("002", 5), ("002", 6)}
    assert placed == {("000", "after", 10), ("002", "before", 7), ("000", "before", 11)}


def test_every_numbered_equation_has_an_entry():
    numbered, _ = documented()
    assert numbered == {(s, n) for s, top in NUMBERED.items() for n in range(1, top + 1)}


def test_every_citation_has_an_entry():
    numbered, placed, where = _project_citations()
    assert len(numbered) > 30 and len(placed) > 5          # the scan sees the project's citations
    doc_numbered, doc_placed = documented()
    missing = sorted((numbered - doc_numbered) | (placed - doc_placed))
    assert not missing, [(m, str(where[m])) for m in missing]


def test_a_citation_without_an_entry_is_seen():
    doc_numbered, doc_placed = documented()
    numbered, placed = citations("000" + " eqs. 27-29 and 002," + " after eq. 3")
    assert numbered - doc_numbered == {("000", 29)}
    assert placed - doc_placed == {("002", "after", 3)}


def test_the_errata_are_listed():
    text = SOURCES_MD.read_text()
    section = text.split("\n## Errata\n", 1)[1]
    assert "pendulab.products.errata" in section
    rows = [line.split("|")[1:3] for line in section.splitlines() if re.match(r"^\| 00[02] \|", line)]
    from pendulab.products import errata
    code = Path(errata.__file__).read_text()
    assert len(rows) == len(errata._BUILDERS)
    for source, where in rows:   # each row is an entry's "where", as errata.py writes it
        assert f'"{where.strip()}"' in code, where


def test_the_readme_and_the_architecture_link_it():
    assert "docs/sources.md" in (ROOT / "README.md").read_text()
    assert "docs/sources.md" in (ROOT / "docs" / "architecture.md").read_text()
