"""``pendulab --help`` and usage errors import neither SymPy, SciPy, NumPy nor matplotlib.

Not a timing test (the times are in benchmarks/bench_startup.py): a fresh
interpreter imports pendulab.cli, builds the parser, runs the command line
given, and reports which heavy packages ended up in sys.modules.
"""

import json
import subprocess
import sys

import pytest

HEAVY = ("sympy", "scipy", "numpy", "matplotlib", "mpmath", "flint")

_PROBE = """
import contextlib, io, json, sys
import pendulab.cli as cli
cli.make_parser()
argv = json.loads(sys.argv[1])
err = io.StringIO()
code = None
if argv:
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            code = cli.main(argv)
        except SystemExit as exc:
            code = exc.code
heavy = sorted({m.split(".")[0] for m in sys.modules} & set(json.loads(sys.argv[2])))
print(json.dumps({"code": code, "heavy": heavy, "err": err.getvalue()}))
"""


def _probe(argv):
    run = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(argv), json.dumps(HEAVY)],
                         capture_output=True, text=True, check=True)
    return json.loads(run.stdout)


@pytest.mark.parametrize("argv, code", [
    ([], None),                                   # the parser alone
    (["--help"], 0),
    (["floquet", "--help"], 0),
    (["bessel", "identities", "--help"], 0),
    (["nope"], 2),                                # an unknown command (argparse)
    (["sweep", "--grid", "0"], 2),                # a range refused by pendulab.limits
    (["simulate", "--a-over-l", "-1", "--w0-over-w", "x"], 2),
    (["floquet", "--theta0", "1", "--theta1", "0", "--dps", "0"], 2),
    (["bessel", "zeros", "--order", "301", "--count", "1"], 2),
    (["series", "--order", "61"], 2),
    (["stability", "--ratio", "2000"], 2),
    (["stability", "--ratio", "0.1", "--method", "series:99"], 2),
])
def test_no_heavy_import(argv, code):
    res = _probe(argv)
    assert res["code"] == code, res["err"]
    assert res["heavy"] == []


def test_the_probe_sees_heavy_imports():
    # the check can fail: a command that computes does import them
    res = _probe(["bessel", "zeros", "--order", "1", "--count", "1", "--dps", "5"])
    assert res["code"] == 0 and "flint" in res["heavy"]


def test_ground_types_pin_survives_the_lazy_imports():
    # pendulab pins SymPy's ground types before SymPy is imported (pendulab/__init__.py);
    # with SymPy imported later (by a command), the pin must still be in force
    code = ("import os; os.environ.pop('SYMPY_GROUND_TYPES', None); import pendulab.cli; "
            "pendulab.cli.make_parser(); from pendulab import load_expr; "
            "import sympy.external.gmpy as g; print(g.GROUND_TYPES, load_expr('x + 1'))")
    import os
    env = {k: v for k, v in os.environ.items() if k != "SYMPY_GROUND_TYPES"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         check=True).stdout.split()
    assert out[0] == "gmpy" and out[1:] == ["x", "+", "1"]


@pytest.mark.parametrize("argv", [["series", "--order", "3"], ["series", "--order", "3", "--kind", "a0"],
                                  ["series", "--order", "3", "--json"]])
def test_the_series_command_prints_without_sympy(argv):
    # the exact series come from python-flint / Fractions and print as text (RatFun.text):
    # (--latex too: its TeX is written from the same exact data)
    res = _probe(argv)
    assert res["code"] == 0, res["err"]
    assert "sympy" not in res["heavy"]
