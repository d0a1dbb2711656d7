"""The floquet command and the floquet scene product."""

import json

import mpmath
import pytest

from pendulab.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_output_keys_and_full_precision(capsys):
    code, out, err = run(capsys, "floquet", "--theta0", "-0.002", "--theta1", "1/5",
                         "--dps", "40", "--json")
    assert code == 0 and err == ""
    rec = json.loads(out)
    assert set(rec) >= {"lambda", "multipliers", "stable", "depth", "method", "dps"}
    # with --dps the default is the ball-arithmetic route, which says what it proved
    assert rec["stable"] is True and rec["method"] == "arb" and rec["dps"] == 40
    assert rec["certified_digits"] == 40
    assert len(rec["lambda"].replace("0.", "", 1)) >= 38
    # the same number as the API with the other method
    from pendulab.analyses.floquet import characteristic_exponent
    cf = characteristic_exponent("-0.002", "0.2", dps=40, method="cf")
    with mpmath.workdps(45):
        assert abs(mpmath.mpf(rec["lambda"]) - cf.lam) < mpmath.mpf(10) ** -39
        from pendulab.analyses.floquet_format import parse_number
        m1 = parse_number(rec["multipliers"][0])
        assert abs(abs(m1) - 1) < mpmath.mpf(10) ** -38


def test_unstable_point_in_text_and_complex_lambda(capsys):
    code, out, _ = run(capsys, "floquet", "--theta0", "3", "--theta1", "10", "--method", "cf")
    assert code == 0 and "unstable" in out and "lambda" in out
    code, out, _ = run(capsys, "floquet", "--theta0", "3", "--theta1", "10", "--json")
    lam = complex(json.loads(out)["lambda"])
    assert lam.real == 2.0 and lam.imag > 1
    from pendulab.analyses.floquet_format import number_text, parse_number
    with mpmath.workdps(30):
        z = mpmath.mpc("2", "-1.6367238408939779635")
        assert parse_number(number_text(z, 30)) == z


@pytest.mark.parametrize("argv,word", [
    (["--theta0", "1e", "--theta1", "0.2"], "theta0"),
    (["--theta0", "0.1", "--theta1", "__import__('os')"], "theta1"),
    (["--theta0", "0.1", "--theta1", "0.2", "--dps", "0"], "dps"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, word):
    code, out, err = run(capsys, "floquet", *argv)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and word in err


def _scene(tmp_path, extra):
    path = tmp_path / "fl.toml"
    path.write_text('name = "fl"\nsystem = "kapitza"\n[parameters]\nbody = "rod"\n'
                    '[products.floquet]\n' + extra, encoding="utf-8")
    return path


def test_product_is_deterministic_and_correct(tmp_path, capsys):
    scene = _scene(tmp_path, 'dps = 20\npoints = [["-0.002", "0.2"], ["3", "10"]]\n'
                             'ratios = ["0.1"]\n')
    out = tmp_path / "gen"
    assert main(["build", str(scene), "--out", str(out)]) == 0
    first = (out / "fl" / "floquet.json").read_bytes()
    assert main(["build", str(scene), "--out", str(out), "--force"]) == 0
    assert (out / "fl" / "floquet.json").read_bytes() == first
    doc = json.loads(first)
    assert [p["stable"] for p in doc["points"]] == [True, False]
    assert doc["I_over_ml2"] == "4/3"
    from pendulab.analyses.floquet import stability_limits
    lo, up = stability_limits("0.1", "4/3", dps=20)
    with mpmath.workdps(25):
        assert abs(mpmath.mpf(doc["limits"][0]["lower"]) - lo) < 1e-19
        assert abs(mpmath.mpf(doc["limits"][0]["upper"]) - up) < 1e-19
    # the default route proves its digits and says so, for points and limits
    assert doc["method"] == "auto"                       # the API's choice, point by point:
    assert [p["method"] for p in doc["points"]] == ["arb", "arb"]   # small points with dps
    assert [p["certified_digits"] for p in doc["points"]] == [20, 20]
    assert doc["limits"][0]["certified_digits"] == 20
    # the mpmath limits at 30 digits agree with the certified 20
    ref = stability_limits("0.1", "4/3", dps=30, method="mpmath")
    with mpmath.workdps(35):
        for key, r in zip(("lower", "upper"), ref):
            assert abs(mpmath.mpf(doc["limits"][0][key]) - r) <= 5e-20 * r
    capsys.readouterr()


def test_text_output_says_what_is_certified(capsys):
    code, out, _ = run(capsys, "floquet", "--theta0", "-0.002", "--theta1", "0.2", "--dps", "25")
    assert code == 0 and "(arb, 25 digits" in out
    assert "certified   = 25 significant digits of lambda proved" in out
    code, out, _ = run(capsys, "floquet", "--theta0", "-0.002", "--theta1", "0.2", "--dps", "25",
                       "--method", "hill")
    assert code == 0 and "certified   = no" in out
    # double precision: arb by default (docs/tradeoffs.md: the cheapest route there), rounded
    code, out, _ = run(capsys, "floquet", "--theta0", "-0.002", "--theta1", "0.2")
    assert code == 0 and "(arb, double precision" in out and "rounded to a double" in out
    code, out, _ = run(capsys, "floquet", "--theta0", "-0.002", "--theta1", "0.2", "--method", "hill")
    assert code == 0 and "(hill, double precision" in out and "not a ball-arithmetic" in out


def test_product_bad_point_writes_nothing(tmp_path, capsys):
    scene = _scene(tmp_path, 'points = [["-0.002"]]\n')
    out = tmp_path / "gen"
    assert main(["build", str(scene), "--out", str(out)]) == 2
    assert not (out / "fl").exists()
    err = capsys.readouterr().err
    assert "points[0]" in err
