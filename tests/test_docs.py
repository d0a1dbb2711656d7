"""The interactive examples in docs/*.md run and print what the docs say they print."""

import doctest
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
WITH_EXAMPLES = sorted(p.name for p in DOCS.glob("*.md") if ">>>" in p.read_text())


def test_the_docs_have_examples():
    assert {"series.md", "stability.md", "averaging.md", "phelps_hunter.md"} <= set(WITH_EXAMPLES)


@pytest.mark.parametrize("name", WITH_EXAMPLES)
def test_doc_examples(name):
    result = doctest.testfile(str(DOCS / name), module_relative=False, report=True,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
