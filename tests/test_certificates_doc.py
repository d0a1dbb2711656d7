"""docs/certificates.md names, for each proof step, where it lives and the test that sees it
refuse a wrong candidate.  These tests keep that list true: every named test exists, every
named place imports, and the reader is never pointed at something that is not there."""

import importlib
import re
from pathlib import Path


ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "certificates.md"

ROW = re.compile(r"^\|(?P<proves>[^|]+)\|(?P<where>[^|]+)\|(?P<test>[^|]+)\|\s*$")
HEADER = ("proves", "---")


def rows(text):
    """(section, proves, where, test) for each table row of the doc."""
    section = None
    out = []
    for line in text.splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
            continue
        m = ROW.match(line)
        if not m or m["proves"].strip().startswith(HEADER):
            continue
        out.append((section, m["proves"].strip(), m["where"].strip(), m["test"].strip()))
    return out


def problems(text, root=ROOT):
    """Each way a row of the doc fails to point at real code and a real test."""
    found = []
    for section, proves, where, test in rows(text):
        if section is None:
            found.append(f"row outside a section: {proves}")
        name = where.strip("`")
        if not re.fullmatch(r"pendulab(\.\w+)+", name):
            found.append(f"{proves}: where is not a dotted name: {where}")
        else:
            parts = name.split(".")
            for cut in range(len(parts), 0, -1):
                try:
                    obj = importlib.import_module(".".join(parts[:cut]))
                except ImportError:
                    continue
                try:
                    for attr in parts[cut:]:
                        obj = getattr(obj, attr)
                except AttributeError:
                    found.append(f"{proves}: {name} does not exist")
                break
            else:
                found.append(f"{proves}: {name} does not import")
        m = re.fullmatch(r"`?(tests/[\w/]+\.py)::(\w+)`?", test)
        if not m:
            found.append(f"{proves}: test is not tests/FILE.py::NAME: {test}")
            continue
        path = root / m[1]
        if not path.is_file() or not re.search(rf"^\s*def {m[2]}\(", path.read_text(), re.M):
            found.append(f"{proves}: no test {m[1]}::{m[2]}")
    return found


def test_every_row_names_a_real_place_and_a_real_test():
    text = DOC.read_text()
    assert rows(text), "docs/certificates.md lists no certificate"
    assert problems(text) == []


def test_the_check_sees_a_missing_test_and_a_missing_place():
    # A row naming a test that does not exist and a function that does not exist must be
    # reported, or the check above could pass on a doc that points nowhere.
    bad = ("## S\n\n| proves | where | the test that sees it refuse |\n|---|---|---|\n"
           "| x | `pendulab.limits.no_such_function` | `tests/test_certificates_doc.py::test_nope` |\n"
           "| y | `pendulab.no_such_module` | `tests/test_certificates_doc.py::"
           "test_the_check_sees_a_missing_test_and_a_missing_place` |\n"
           "| z | pendulab.limits | tests/nowhere |\n")
    found = problems(bad)
    assert any("no_such_function does not exist" in p for p in found)
    assert any("test_nope" in p for p in found)
    assert any("no_such_module" in p for p in found)
    assert any("not tests/FILE.py::NAME" in p for p in found)
    assert len(found) == 4


def test_every_section_lists_its_proof_steps():
    # each section of the doc names at least one step with its negative test; an emptied
    # section (its rows lost in an edit) fails here, not silently
    text = DOC.read_text()
    sections = [line[3:].strip() for line in text.splitlines() if line.startswith("## ")]
    assert len(sections) >= 5
    listed = {s for s, *_ in rows(text)}
    assert [s for s in sections if s not in listed] == []
