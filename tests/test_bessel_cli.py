"""`pendulab bessel ...` and the scene products "bessel" / "quarter_periods".

References: 002_19b336b29bb1f03b.txt (the quarter-period table and the zeros as
printed); A&S Table 9.5 for j_{2,3}^2 (the shortening string's time to L = 0).
"""

import json
from fractions import Fraction

import pytest

from pendulab.cli import main


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_zeros_json(capsys):
    code, out, _ = _run(capsys, "bessel", "zeros", "--order", "2", "--count", "4", "--dps", "6", "--json")
    assert code == 0
    assert json.loads(out)["zeros"] == ["5.13562", "8.41724", "11.6198", "14.7960"]  # 002 prints 14.796


def test_quarter_periods_json(capsys):
    code, out, _ = _run(capsys, "bessel", "quarter-periods", "--count", "3", "--dps", "6", "--json")
    doc = json.loads(out)
    assert code == 0
    assert doc["inward"] == ["22.8438", "32.6495", "42.5001"]  # 002's table
    assert doc["outward"] == ["21.6315", "31.5213", "41.3994"]
    assert doc["claim_holds"] is True


def test_identities_json(capsys):
    code, out, _ = _run(capsys, "bessel", "identities", "--nmax", "2", "--dps", "20", "--points", "5", "--json")
    doc = json.loads(out)
    assert code == 0 and isinstance(doc["worst_relative_error"], str)
    assert float(doc["worst_relative_error"]) < 1e-20 and doc["worst_z"] > 0


@pytest.mark.parametrize("argv, fragment", [
    (["zeros", "--order", "-1", "--count", "3"], "order"),
    (["zeros", "--order", "1", "--count", "-3"], "count"),
    (["zeros", "--order", "1", "--count", "2.5"], "count"),
    (["zeros", "--order", "1", "--count", "3", "--dps", "0"], "dps"),
    (["zeros", "--order", "1", "--count", "3", "--dps", "10001"], "dps"),
    (["quarter-periods", "--count", "0"], "count"),
    (["quarter-periods", "--count", "3", "--dps", "-5"], "dps"),
    (["identities", "--nmax", "2", "--z", "0"], "--z must be a number above 0"),
    (["identities", "--nmax", "2", "--z", "-3"], "--z must be a number above 0"),
    (["identities", "--nmax", "1.5"], "nmax"),
])
def test_bad_input_one_line_exit_2(capsys, argv, fragment):
    code, out, err = _run(capsys, "bessel", *argv)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error:") and fragment in lines[0]


def _scene(tmp_path, length, table="[products.quarter_periods]\ncount = 3\ndps = 8\n"):
    p = tmp_path / "vl.toml"
    p.write_text(f'system = "variable-length"\n[parameters]\nlength = "{length}"\n{table}')
    return p


def test_shortening_scene_gets_its_own_quarter_periods(tmp_path, capsys):
    grow = _scene(tmp_path, "L0 + v0*t")
    assert main(["build", str(grow), "--out", str(tmp_path / "g")]) == 0
    shrink = _scene(tmp_path, "L0 - v0*t")
    assert main(["build", str(shrink), "--out", str(tmp_path / "s")]) == 0
    g = json.loads((tmp_path / "g" / "vl" / "quarter_periods.json").read_text())
    s = json.loads((tmp_path / "s" / "vl" / "quarter_periods.json").read_text())
    assert g["direction"] == "growing" and s["direction"] == "shortening"
    assert s["inward"] != g["inward"] and s["claim_holds"] is False
    # z0 = j_{2,2}: L reaches 0 at t = j_{2,2}^2 v0/(4g) (A&S 9.5: j_{2,2} = 8.4172441404)
    assert abs(Fraction(s["time_to_zero_length"]) - Fraction("8.4172441404") ** 2) < Fraction(1, 10 ** 5)


def test_rate_of_unknown_sign_is_refused(tmp_path, capsys):
    scene = _scene(tmp_path, "L0 + c*t")
    code, out, err = _run(capsys, "build", str(scene), "--out", str(tmp_path / "o"))
    assert code == 2 and "sign of the rate" in err and not (tmp_path / "o" / "vl").exists()


def test_bessel_product_options_checked(tmp_path, capsys):
    scene = _scene(tmp_path, "L0 + v0*t", "[products.bessel]\ndps = 0\nnmax = 50\n")
    code, out, err = _run(capsys, "build", str(scene), "--out", str(tmp_path / "o"))
    assert code == 2 and "dps: must be an integer from 1 to 1000" in err and "nmax" in err
    assert not (tmp_path / "o" / "vl").exists()


def test_bessel_product_writes_json_and_tables(tmp_path):
    scene = _scene(tmp_path, "L0 + v0*t", "[products.bessel]\nzeros = 3\ncount = 2\ndps = 12\nnmax = 1\npoints = 4\n")
    assert main(["build", str(scene), "--out", str(tmp_path / "o")]) == 0
    d = tmp_path / "o" / "vl"
    doc = json.loads((d / "bessel.json").read_text())
    assert doc["zeros"]["J1"][0] == "3.83170597021"
    assert doc["quarter_periods"]["inward"][0].startswith("22.8438")
    assert doc["large_k"]["limit_margin_after"] == "6 - pi**2/2"
    for name in ("bessel_zeros.tex", "bessel_quarter_periods.tex", "bessel_identities.tex"):
        assert "\\begin{tabular}" in (d / name).read_text()


def test_zeros_beyond_4300_digits_and_tiny_orders(capsys):
    # found by an audit: str() of an int stops at 4300 digits, and float() of
    # the exact phase coefficients overflowed for an order of 1e-20.
    # (the command line stops at 1000 digits, pendulab.limits; the Python API goes to 10000)
    from pendulab.analyses.bessel_zeros import bessel_zeros
    from pendulab.cli import main
    zero = bessel_zeros(1, 1, 4400).strings[0]
    # A&S Table 9.5: j_{1,1} = 3.8317059702
    assert zero.startswith("3.8317059702") and len(zero.replace(".", "")) == 4400
    assert main(["bessel", "zeros", "--order", "1e-20", "--count", "2", "--json"]) == 0
    zeros = json.loads(capsys.readouterr().out)["zeros"]
    # j_{nu,1} -> j_{0,1} = 2.4048255577 (A&S Table 9.5) as nu -> 0
    assert zeros[0].startswith("2.4048255576957727686")


@pytest.mark.parametrize("argv", [
    ["zeros", "--order", "99.9", "--count", "3", "--dps", "100"],
    ["zeros", "--order", "299.99", "--count", "3"],
    ["zeros", "--order", "100", "--count", "3", "--dps", "1"],
    ["zeros", "--order", "300", "--count", "3", "--dps", "1"],
    ["identities", "--nmax", "2", "--dps", "1"],
    ["identities", "--nmax", "2", "--dps", "3"],
])
def test_audited_commands_succeed(capsys, argv):
    """The audit's failing commands (non-integer orders above 75, dps 1 for orders 100 and
    300, identities at dps 1 to 3) now print their result; the digits themselves are checked
    against mpmath in test_bessel_zeros.py and test_bessel_identities.py."""
    code, out, err = _run(capsys, "bessel", *argv)
    assert code == 0 and err == "" and out
    if argv[0] == "zeros":
        lines = out.strip().splitlines()
        assert len(lines) == 4 and "every digit certified" in lines[0]
