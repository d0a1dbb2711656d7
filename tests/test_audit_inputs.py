"""Inputs an audit of the command line (2026-12-03) found giving a traceback, hanging or a wrong message.

Each case must now give one ``pendulab: error:`` line with exit status 2 (command line) or a
PendulabError (API), naming what is wrong; the accepted neighbours of each case still work.
The numbers of digits come from Python's own limit (4300 digits per int-to-text conversion,
sys.get_int_max_str_digits) and pendulab.exprs.MAX_NUMBER_DIGITS.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from pendulab import limits, symbols as S
from pendulab.build import build, check_out_root
from pendulab.cli import main
from pendulab.errors import InputError, PendulabError
from pendulab.exprs import MAX_NUMBER_DIGITS, dump_expr, parse
from pendulab.scene import load_scene, parse_scene

ROOT = Path(__file__).resolve().parents[1]


def _one_error(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("pendulab: error: "), err
    return err[0]


@pytest.mark.parametrize("drive", ["a*cos(omega*t)*10**900", "a*cos(omega*t)*9**1000",
                                   "a*cos(omega*t)*10**1000", "a*cos(omega*t)*1e1000",
                                   "a*cos(omega*t)*1e-1000", "a*cos(omega*t)*0.1**1000"])
def test_numbers_up_to_ten_to_the_thousand_are_accepted(drive):
    # 10**1000 is the largest numerator or denominator (its log2 is 3321.93: the power check
    # estimates 10**900 by log2(10) per factor, not by 10's four bits)
    assert parse(drive).has(S.a)  # parsed, not refused


@pytest.mark.parametrize("drive, what", [
    ("a*cos(omega*t) + 1e5000", "out of range"),
    ("a*cos(omega*t) + 1e999999999", "out of range"),  # hung in sympy.Rational before
    ("a*cos(omega*t)*1e-999999", "out of range"),
    ("a*cos(omega*t)" + "*(10**400)" * 5, "larger than"),  # a product, not a power, of numbers
    ("a*cos(omega*t)*1.5e-1000", "larger than"),  # its denominator is 10**1001
    ("a*cos(omega*t) + 1" + "0" * 1001, "larger than"),
    ("a*cos(omega*t)*(10**600)**2", "too large"),
    ("a*cos(omega*t)*(10**400*a)**3", "too large"),  # a number inside the base
])
def test_numbers_beyond_the_digit_limit_are_refused(drive, what, capsys):
    line = _one_error(capsys, ["derive", "kapitza", "--drive", drive])
    assert what in line and "--drive" in line and f"10**{MAX_NUMBER_DIGITS}" in line


def test_numbers_within_the_limit_derive_and_print_whole(capsys):
    # 10**999 has 1000 digits; squared in the Lagrangian (the drive's rate squared) it passes
    # Python's 4300-digit printing limit only when the command lifts it, as it does
    code = ("import sys; from pendulab.cli import console; "
            "console(['derive', 'kapitza', '--drive', 'a*cos(omega*t)*1e999', '--json'])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "1" + "0" * 999 in out.stdout and "Traceback" not in out.stderr


def test_printing_beyond_pythons_limit_is_one_line_in_the_api():
    before = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(4300)
    try:
        big = sp.Integer(10) ** 5000  # built directly, as a derivation could
        with pytest.raises(InputError, match="more than 4300 digits"):
            dump_expr(big * sp.Symbol("x"))
    finally:
        sys.set_int_max_str_digits(before)


@pytest.mark.parametrize("argv", [
    ["stability", "--ratio", "0.05", "--method", "series:\u00b3"],  # superscript three
    ["stability", "--ratio", "0.05", "--method", "integer-series:\u00b2"],
    ["stability", "--ratio", "0.05", "--method", "series:\u0663"],  # Arabic-Indic three
    ["series", "--order", "3", "--kind", "b\u00b2"],
])
def test_digits_other_than_ascii_are_not_orders(argv, capsys):
    line = _one_error(capsys, argv)
    assert "order" in line or "kind" in line


def test_undecodable_bytes_on_the_command_line():
    # a byte that is not UTF-8 reaches Python as a surrogate escape; the command says so
    drive = b"a*cos(omega*t)\xff"
    code = "from pendulab.cli import console; import sys; console(sys.argv[1:])"
    out = subprocess.run([sys.executable, "-c", code, "derive", "kapitza", "--drive", drive],
                         capture_output=True, timeout=120)
    err = out.stderr.decode("utf-8", "replace").strip().splitlines()
    assert out.returncode == 2 and len(err) == 1 and "not UTF-8" in err[0], err


@pytest.mark.parametrize("digits, what", [
    (5000, "must be an integer from"),  # read (the command reads up to 100000 digits), refused
    (2_000_000, "more than 100000 digits"),  # not even read: quadratic to convert (65 s)
])
def test_huge_integer_in_a_scene_file(tmp_path, digits, what):
    scene = tmp_path / "big.toml"
    scene.write_text('system = "kapitza"\n[products.series]\norder = 1' + "0" * digits + "\n")
    code = "from pendulab.cli import console; import sys; console(sys.argv[1:])"
    out = subprocess.run([sys.executable, "-c", code, "build", str(scene), "--out",
                          str(tmp_path / "out")], capture_output=True, text=True, timeout=60)
    err = out.stderr.strip().splitlines()
    assert out.returncode == 2 and len(err) == 1 and "big.toml" in err[0], err
    assert what in err[0] and len(err[0]) < 400
    assert not (tmp_path / "out").exists()


def test_byte_order_mark_is_named(tmp_path, capsys):
    scene = tmp_path / "bom.toml"
    scene.write_text('\ufeffsystem = "kapitza"\n[products.equations]\n', encoding="utf-8")
    line = _one_error(capsys, ["build", str(scene), "--out", str(tmp_path / "out")])
    assert "byte-order mark" in line


@pytest.mark.parametrize("text, what", [
    ("Piecewise((a, t > 0), (0, True))*cos(omega*t)", "Piecewise"),
    ("sqrt(-1)*a*cos(omega*t)", "not real"),
    ("(-8)**Rational(1, 3)*a*cos(omega*t)", "not real"),  # complex, with no I in it
    ("asin(2)*a*cos(omega*t)", "not real"),
    ("a*cos(omega*t)*log(-2)", "not real"),
    ("Integer(1.5)*a*cos(omega*t)", "whole number"),
])
def test_expressions_refused_for_their_real_cause(text, what):
    with pytest.raises(InputError, match=what):
        parse(text)


def test_integer_of_a_whole_number_still_works():
    assert parse("Integer(3)*a") == 3 * parse("a")


@pytest.mark.parametrize("call", [
    lambda: parse_scene({1: 2, "system": "kapitza", "products": {"equations": {}}}),
    lambda: parse_scene({"system": "kapitza", "products": {"equations": {3: 1}}}),
    lambda: load_scene(None),
    lambda: load_scene(""),
    lambda: build(None, "/nonexistent-never-written"),
    lambda: limits.check("no-such-limit", 5),
])
def test_api_calls_raise_pendulab_errors(call):
    with pytest.raises(PendulabError):
        call()


def test_empty_scene_path_is_refused(tmp_path, capsys):
    line = _one_error(capsys, ["build", "", "--out", str(tmp_path / "out")])
    assert "scene" in line
    assert not (tmp_path / "out").exists()


def test_out_names_longer_than_the_file_system_allows(tmp_path):
    with pytest.raises(InputError, match="longer than"):
        check_out_root(tmp_path / ("x" * 300))


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc")
def test_out_where_nothing_can_be_created_is_refused_before_work(capsys):
    # os.access answers yes for /proc as root; the check tries to create something there
    line = _one_error(capsys, ["build", str(ROOT / "derivations" / "kapitza-point.toml"),
                               "--out", "/proc/pendulab-cannot-be-here"])
    assert "cannot create" in line or "not writable" in line


def test_derive_names_its_options_not_scene_keys(capsys):
    line = _one_error(capsys, ["derive", "kapitza", "--drive", "a*cos(omega*t) + 1e5000"])
    assert "--drive:" in line and "parameters.drive" not in line and "command line" not in line


def test_sweep_says_how_to_write_the_drive(capsys):
    line = _one_error(capsys, ["sweep", "--drive", "b*cos(omega*t)", "--grid", "2"])
    # the user wrote b, not l (l enters only through the groups b/l)
    assert "drive b*cos(omega*t) uses b:" in line and "amplitude with a" in line and "scene" not in line


def test_work_refusals_suggest_only_what_would_change():
    from pendulab.products.experiments import OPTIONS
    options = {key: default for key, (_, default, _) in OPTIONS.items()}
    options.update(grid=400, backend="c", prune=True)
    problem = limits.work_problem("experiments", options)
    assert problem and "backend" in problem and 'backend = "c"' not in problem
    assert "prune = true" not in problem and "smaller grid" in problem
    points = [[str(-2000000 + k), "1000000"] for k in range(100)]
    problem = limits.work_problem("floquet", {"points": points, "ratios": [], "dps": 30,
                                              "method": "hill"})
    assert problem and "method 'hill'" not in problem and "fewer points" in problem
    problem = limits.work_problem("floquet", {"points": points[:1], "ratios": [], "dps": 1000,
                                              "method": "monodromy"})
    assert problem and "method 'hill'" in problem


def test_non_integer_orders_have_a_smaller_zero_budget(capsys):
    # 1000 zeros of J_299.99 at 1000 digits took over 75 s of CPU (an audit); refused at once
    line = _one_error(capsys, ["bessel", "zeros", "--order", "299.99", "--count", "1000",
                               "--dps", "1000"])
    assert "non-integer order" in line and str(limits.BESSEL_ZERO_WORK //
                                               limits.BESSEL_NON_INTEGER_FACTOR) in line
    # just off an integer too (2.01 at 1000 digits ran past 100 s in a review)
    line = _one_error(capsys, ["bessel", "zeros", "--order", "2.01", "--count", "1000",
                               "--dps", "1000"])
    assert "non-integer order" in line


def test_extreme_motion_values_give_one_line_not_numpy_warnings(tmp_path):
    # L0 = g = 1e-300 are inside their ranges; the closed form's values overflow to NaN.  A
    # subprocess: pytest would catch NumPy's warnings that the command prints
    scene = tmp_path / "tiny.toml"
    scene.write_text('system = "variable-length"\n[parameters]\nlength = "L0 + v0*t"\n'
                     "[products.motion]\nfigures = false\nL0 = 1e-300\ng = 1e-300\n")
    code = "from pendulab.cli import console; import sys; console(sys.argv[1:])"
    out = subprocess.run([sys.executable, "-c", code, "build", str(scene), "--out",
                          str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    err = out.stderr.strip().splitlines()
    assert out.returncode == 2 and len(err) == 1 and "products.motion" in err[0], err


def test_experiments_refuse_a_criterion_or_map_listed_twice():
    from pendulab.products.experiments import OPTIONS, check_options
    options = {key: default for key, (_, default, _) in OPTIONS.items()}
    options.update(criteria=["mean", "mean"], maps=["text", "fig4", "text"])
    with pytest.raises(InputError) as info:
        check_options(options)
    text = "; ".join(getattr(info.value, "problems", [str(info.value)]))
    assert "criteria: 'mean' listed twice" in text and "maps: 'text' listed twice" in text
