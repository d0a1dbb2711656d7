"""Zeros of J1, J2 and the quarter periods of 002 (002_19b336b29bb1f03b.txt, last page)."""

import json

import mpmath
import pytest

from pendulab.analyses.bessel import quarter_periods, toward_swings_are_longer
from pendulab.errors import InputError

# 002's table of zeros (6 significant digits as printed).
SOURCE_J1 = ["3.83171", "7.01559", "10.1735", "13.3237", "16.4706", "19.6159", "22.7601", "25.9037"]
SOURCE_J2 = ["5.13562", "8.41724", "11.6198", "14.796", "17.9598", "21.117", "24.2701", "27.4206"]
# 002's quarter periods (differences of squares, unit v0/(4g)).
SOURCE_QUARTERS = ["22.8438", "21.6315", "32.6495", "31.5213", "42.5001", "41.3994"]
# Abramowitz & Stegun, Table 9.5 (zeros of J_n, 10 decimals).
AS_9_5 = {(1, 1): "3.8317059702", (1, 2): "7.0155866698", (1, 3): "10.1734681351",
          (2, 1): "5.1356223018", (2, 2): "8.4172441404", (2, 3): "11.6198411721"}


def test_durations_match_the_sources_table():
    qp = quarter_periods(6, dps=20)
    for rec, printed in zip(qp, SOURCE_QUARTERS):
        assert abs(rec["duration"] - mpmath.mpf(printed)) < 6e-5, (rec, printed)
    assert [r["direction"] for r in qp] == ["toward", "outward"] * 3


def test_zeros_match_the_source_and_abramowitz_stegun():
    with mpmath.workdps(30):
        for k, printed in enumerate(SOURCE_J1, start=1):
            assert mpmath.nstr(mpmath.besseljzero(1, k), len(printed.replace(".", ""))) == printed.rstrip("0")
        for k, printed in enumerate(SOURCE_J2, start=1):
            digits = len(printed.replace(".", ""))
            assert mpmath.nstr(mpmath.besseljzero(2, k), digits) == printed
        for (n, k), ref in AS_9_5.items():
            assert abs(mpmath.besseljzero(n, k) - mpmath.mpf(ref)) < 1e-10


def test_zeros_at_50_digits_by_an_independent_root_finder():
    """quarter_periods' zeros agree with a Newton iteration on J_n started from 002's table."""
    qp = quarter_periods(4, dps=50)
    with mpmath.workdps(60):
        for rec in qp:
            n = 2 if rec["from"].startswith("J2") else 1
            root = mpmath.findroot(lambda x: mpmath.besselj(n, x), rec["z_from"] + mpmath.mpf("1e-6"))
            assert abs(root - rec["z_from"]) < mpmath.mpf("1e-48")


def test_the_sources_claim_holds_for_many_swings():
    qp = quarter_periods(40, dps=20)
    verdict = toward_swings_are_longer(qp)
    assert len(verdict) == 20 and all(ok for _, ok in verdict)


def test_claim_check_can_fail():
    qp = quarter_periods(4, dps=15)
    qp[1]["duration"] = qp[0]["duration"] + 1  # an outward swing made longer
    assert not all(ok for _, ok in toward_swings_are_longer(qp))


@pytest.mark.parametrize("count, dps", [(0, 30), (3, 2), ("8", 30)])
def test_bad_arguments(count, dps):
    with pytest.raises(InputError):
        quarter_periods(count, dps)


def test_product_in_a_scene(tmp_path):
    from pendulab.build import build
    scene = tmp_path / "vl.toml"
    scene.write_text('system = "variable-length"\n[products.quarter_periods]\ncount = 4\ndps = 15\n')
    build(scene, tmp_path / "out", log=lambda m: None)
    doc = json.loads((tmp_path / "out" / "vl" / "quarter_periods.json").read_text())
    assert doc["toward_longer_than_neighbours"] and doc["cross_product_identity"]["holds"]
    assert len(doc["quarter_periods"]) == 4
