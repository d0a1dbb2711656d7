"""docs/scenes.md lists every product and option as the products and pendulab.limits define them."""

import re
import tomllib
from pathlib import Path

import pytest

from pendulab import limits
from pendulab.pipeline import PRODUCTS, product_module
from pendulab.scene import parse_scene

DOC = Path(__file__).resolve().parents[1] / "docs" / "scenes.md"
TYPE_NAMES = {int: "integer", float: "number", list: "list", str: "string", bool: "boolean",
              dict: "table"}
SYSTEM_OF = {"quarter_periods": "variable-length", "bessel": "variable-length",
             "motion": "variable-length"}


def _rows():
    """The rows of the products-and-options table: dicts keyed by the header's columns."""
    lines = DOC.read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines)
                 if re.match(r"\|\s*product\s*\|\s*option\s*\|", line))
    header = [c.strip() for c in lines[start].strip().strip("|").split("|")]
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rows.append(dict(zip(header, cells)))
    return rows


def _code(cell):
    m = re.fullmatch(r"`(.*)`", cell)
    assert m, f"expected `code` in {cell!r}"
    return m.group(1)


def test_the_table_lists_exactly_the_products_and_options():
    documented = {(r["product"], r["option"]) for r in _rows()}
    expected = set()
    for name in PRODUCTS:
        options = product_module(name).OPTIONS
        expected |= {(name, key) for key in options} or {(name, "(none)")}
    assert documented == expected


def _row_problems(row):
    """What in ``row`` disagrees with the product's OPTIONS and pendulab.limits (empty: nothing)."""
    if row["option"] == "(none)":
        return [] if not product_module(row["product"]).OPTIONS else ["the product has options"]
    kind, default, _help = product_module(row["product"]).OPTIONS[row["option"]]
    problems = []
    if row["type"] != TYPE_NAMES[kind]:
        problems.append(f"type {row['type']!r}, the product says {TYPE_NAMES[kind]!r}")
    if tomllib.loads("x = " + _code(row["default"]))["x"] != default:
        problems.append(f"default {row['default']}, the product says {default!r}")
    name = f"{row['product']}.{row['option']}"
    if name in limits.LIMITS:
        if row["range"] != limits.describe(name):
            problems.append(f"range {row['range']!r}, the limits say {limits.describe(name)!r}")
    elif not row["range"]:
        problems.append("no range")
    return problems


@pytest.mark.parametrize("row", _rows(), ids=lambda r: f"{r['product']}.{r['option']}")
def test_each_row_matches_the_product_and_the_limits(row):
    assert _row_problems(row) == []


@pytest.mark.parametrize("column, wrong", [("type", "string"), ("default", "`9`"),
                                           ("range", "1 to 61")])
def test_a_changed_cell_is_caught(column, wrong):
    row = dict(next(r for r in _rows() if (r["product"], r["option"]) == ("series", "order")))
    row[column] = wrong
    assert len(_row_problems(row)) == 1


@pytest.mark.parametrize("row", _rows(), ids=lambda r: f"{r['product']}.{r['option']}")
def test_each_example_is_a_valid_scene(row):
    module = product_module(row["product"])
    per_system = getattr(module, "options_for", None)
    if per_system is not None:   # a product whose systems take different options
        system = next(s for s in module.SYSTEMS if row["option"] in per_system(s))
    else:
        system = SYSTEM_OF.get(row["product"], "kapitza")
    example = _code(row["example"])
    body = "" if example.startswith("[") else example
    data = tomllib.loads(f'system = "{system}"\n[products.{row["product"]}]\n{body}\n')
    scene = parse_scene(data, path="example.toml")
    if body:
        key, value = next(iter(tomllib.loads(body).items()))
        assert scene.products[row["product"]][key] == value


def _cli_rows():
    """The rows of the command-line table: (command, option, entry, range)."""
    lines = DOC.read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines)
                 if re.match(r"\|\s*command\s*\|\s*option\s*\|\s*entry\s*\|", line))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rows.append((_code(cells[0]).removeprefix("pendulab "), _code(cells[1]), _code(cells[2]),
                     cells[3]))
    return rows


def _cli_expected():
    """The same rows from the parsers (tests/test_cli_limits.py) and pendulab.limits."""
    from test_cli_limits import numeric_options
    return [(c, o, n, limits.describe(n)) for c, o, n in numeric_options()]


def test_the_command_line_table_lists_every_numeric_option_with_its_range():
    assert sorted(_cli_rows()) == sorted(_cli_expected())


def test_a_changed_command_line_row_is_caught():
    rows = _cli_rows()
    changed = [(c, o, n, "1 to 2001" if o == "--grid" else r) for c, o, n, r in rows]
    assert sorted(changed) != sorted(_cli_expected())
