"""docs/tradeoffs.md cannot drift: its commands are the script's, its defaults the code's.

The page is written by ``python benchmarks/tradeoffs.py`` (not run here: it takes minutes).
This test reads the committed page and checks, without running any measurement:

* every command it prints (`python benchmarks/tradeoffs.py ...`) is accepted by the script's
  own argument parser, every table is preceded by one, and every row of the task table has one;
* every default in the table "The project's defaults against these tables" equals the value
  the code has now (pendulab.limits.LIMITS, a function's signature, a module attribute), so a
  changed default makes this test fail until the page is measured again.
"""

import ast
import importlib
import importlib.util
import inspect
import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "tradeoffs.md"
SCRIPT = ROOT / "benchmarks" / "tradeoffs.py"
COMMAND = re.compile(r"`python benchmarks/tradeoffs\.py([^`]*)`")


def _script():
    spec = importlib.util.spec_from_file_location("tradeoffs_script", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _text():
    assert DOC.exists(), "docs/tradeoffs.md is missing: run python benchmarks/tradeoffs.py"
    return DOC.read_text()


def _tables(text):
    """[(index of the header line, header line, [rows as lists of cells])] of the tables."""
    lines = text.splitlines()
    out, i = [], 0
    while i < len(lines):
        rule = i + 1 < len(lines) and re.match(r"^\|[-| ]+\|$", lines[i + 1])
        if lines[i].startswith("|") and rule:
            start, rows = i, []
            i += 2
            while i < len(lines) and lines[i].startswith("|"):
                rows.append([c.strip() for c in lines[i].strip().strip("|").split(" | ")])
                i += 1
            out.append((start, lines[start], rows))
        else:
            i += 1
    return out


def _accepted(parser, args):
    try:
        parser.parse_args(shlex.split(args))
    except SystemExit:
        return False
    return True


def test_every_command_of_the_page_is_accepted_by_the_script():
    text = _text()
    parser = _script().build_parser()
    commands = COMMAND.findall(text)
    assert len(commands) >= 10
    refused = [c for c in set(commands) if not _accepted(parser, c)]
    assert not refused, f"commands the script refuses: {refused}"


def test_a_refused_command_is_noticed():
    parser = _script().build_parser()
    assert _accepted(parser, " --part rk4 --quick")
    assert not _accepted(parser, " --part runge-kutta")
    assert not _accepted(parser, " --steps 400")


def test_every_table_names_its_command():
    text = _text()
    lines = text.splitlines()
    measured = 0
    for start, head, rows in _tables(text):
        if head.startswith(("| part |", "| default |")):  # the run log; the defaults' verdicts
            continue
        if head.startswith("| task |"):
            for row in rows:
                assert COMMAND.search(row[-1]), f"task row without a command: {row}"
            continue
        # a measured table: the last "Reproduce: <command>" since its section's heading
        heading = max(i for i in range(start) if lines[i].startswith("#"))
        said = "\n".join(lines[heading:start])
        assert "Reproduce: " in said and COMMAND.search(said.split("Reproduce: ")[-1][:120]), \
            f"table without a command before it: {head}"
        measured += 1
    assert measured >= 6


def _code_default(where):
    if where.startswith("limits:"):
        from pendulab.limits import LIMITS
        return LIMITS[where[len("limits:"):]][3]
    module, name = where.split(":")
    mod = importlib.import_module(module)
    if "(" in name:
        fn, param = name[:-1].split("(")
        return inspect.signature(getattr(mod, fn)).parameters[param].default
    if name.startswith("OPTIONS["):  # a product option: (type, default, help)
        return mod.OPTIONS[name[len("OPTIONS["):-1]][1]
    return getattr(mod, name)


def _defaults(text):
    tables = [rows for _, head, rows in _tables(text) if head.startswith("| default |")]
    assert len(tables) == 1, "the page has no (or more than one) table of defaults"
    out = []
    for row in tables[0]:
        where, value = row[0].strip("`"), row[1].strip("`")
        out.append((where, ast.literal_eval(value)))
    return out


def test_the_defaults_on_the_page_are_the_codes():
    rows = _defaults(_text())
    assert len(rows) >= 8
    names = {w for w, _ in rows}
    assert {"limits:experiments.steps_per_period", "limits:series.order", "limits:floquet.dps",
            "limits:bessel.dps"} <= names
    stale = [(w, v, _code_default(w)) for w, v in rows if _code_default(w) != v]
    assert not stale, ("defaults changed since docs/tradeoffs.md was measured (rerun "
                       f"python benchmarks/tradeoffs.py): {stale}")


def test_a_changed_default_is_noticed(monkeypatch):
    from pendulab import limits
    rows = _defaults(_text())
    where, value = next((w, v) for w, v in rows if w == "limits:experiments.steps_per_period")
    kind, low, high, default, help_ = limits.LIMITS["experiments.steps_per_period"]
    monkeypatch.setitem(limits.LIMITS, "experiments.steps_per_period",
                        (kind, low, high, default + 1, help_))
    assert _code_default(where) != value


def test_every_table_row_has_the_cells_of_its_header():
    for _, head, rows in _tables(_text()):
        width = head.count(" | ") + 1
        for row in rows:
            assert len(row) == width, f"a row of '{head}' has {len(row)} cells: {row}"


def test_every_checked_default_has_a_verdict():
    for _, head, rows in _tables(_text()):
        if head.startswith("| default |"):
            for row in rows:
                assert row[-1] and row[-1] != "not measured in this run", row


@pytest.mark.parametrize("where", ["limits:series.order",
                                   "pendulab.numerics.integrate:reference_trajectory(rtol)",
                                   "pendulab.analyses.variable_length_motion:RTOL",
                                   "pendulab.products.floquet:OPTIONS[method]"])
def test_the_script_and_the_test_read_a_default_alike(where):
    assert _script().default_value(where) == _code_default(where)


def test_the_front_and_the_cheapest_setting_are_picked_as_the_page_says():
    script = _script()
    # (cost, error): (3, 4) is beaten by (2, 3); (5, 1) ties (4, 1) in error at a higher cost
    points = [(1, 5), (2, 3), (3, 4), (4, 1), (5, 1)]
    assert script.pareto(points) == [0, 1, 3]
    rows = [{"time": 1, "error": 1e-3}, {"time": 5, "error": 1e-9},
            {"time": 3, "error": 1e-7, "refused": True}, {"time": 4, "error": 1e-7}]
    assert script.cheapest(rows, 1e-6) is rows[3]   # the refused value does not count
    assert script.cheapest(rows, 1e-12) is None
