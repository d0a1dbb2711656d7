"""Stability limits that double precision cannot resolve, and the reason of every "none".

The band's ends are checked against an independent computation written here: Sturm counts
(the signs of the LDL^T pivots) of the truncated tridiagonal matrices whose eigenvalues are
Mathieu's characteristic values (DLMF 28.4: the recurrences of the Fourier coefficients
A_2m of ce_2n and B_2m+1 of se_2n+1), in plain mpmath at more digits than the answer.
The map to the Mathieu plane is the source's (000 eqs. 5-6): theta0 = -4 (omega0/omega)^2
and q = theta1 = 2 (a/l)/(I/(m l^2)) = (3/2) a/l for the rod (I/(m l^2) = 4/3).
"""

import json
import math

import mpmath
import pytest

from pendulab.cli import main
from pendulab.analyses import stability as st


def _count_below(diag, off, x):
    """Eigenvalues < x of the symmetric tridiagonal matrix (diag, off): negative pivots."""
    count, pivot = 0, None
    for k, d in enumerate(diag):
        pivot = d - x if k == 0 else d - x - off[k - 1] ** 2 / pivot
        if pivot == 0:
            pivot = mpmath.mpf(10) ** (-mpmath.mp.dps)
        count += pivot < 0
    return count


def a0_below(q, x, n):
    """How many even pi-periodic characteristic values a_2m(q) lie below x (DLMF 28.4.5):
    diag (2m)^2, off-diagonal sqrt(2) q then q."""
    diag = [mpmath.mpf(4 * m * m) for m in range(n)]
    off = [mpmath.sqrt(2) * q] + [q] * (n - 2)
    return _count_below(diag, off, x)


def b1_below(q, x, n):
    """How many odd 2pi-periodic characteristic values b_2m+1(q) lie below x (DLMF 28.4.8):
    diag 1 - q, 9, 25, ..., off-diagonal q."""
    diag = [1 - q] + [mpmath.mpf((2 * m + 1) ** 2) for m in range(1, n)]
    off = [q] * (n - 1)
    return _count_below(diag, off, x)


def _json(capsys, *argv):
    assert main(["stability", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_sturm_counts_find_a_known_band():
    """The counts themselves: at omega0/omega = 0.1 the exact limits (resolved doubles) lie
    between a_0 = theta0 and b_1 = theta0 (to 1e-9 of a/l)."""
    lower, upper = st.limits(0.1, 4 / 3, "exact")
    with mpmath.workdps(30):
        theta0 = mpmath.mpf(-4) * mpmath.mpf("0.01")
        for a, side in ((lower * (1 - 1e-9), 0), (lower * (1 + 1e-9), 1)):
            assert a0_below(mpmath.mpf(a) * 3 / 2, theta0, 30) == side
        for a, side in ((upper * (1 - 1e-9), 0), (upper * (1 + 1e-9), 1)):
            assert b1_below(mpmath.mpf(a) * 3 / 2, theta0, 30) == side


def test_a_band_narrower_than_a_double_is_given_with_its_certified_digits(capsys):
    rec = _json(capsys, "--ratio", "10")
    assert rec["lower"] is None and rec["upper"] is None  # never two equal doubles
    assert "not resolvable in double precision" in rec["why"]["lower"]
    band = rec["band"]
    assert band["digits"] == 30 and band["certified_digits"] == 30
    with mpmath.workdps(60):
        lo, up = mpmath.mpf(band["lower"]), mpmath.mpf(band["upper"])
        assert lo < up and float(lo) == float(up) == band["near"]
        assert float((up - lo) / up) == pytest.approx(band["relative_width"], rel=1e-3)
        theta0 = mpmath.mpf(-400)
        eps = mpmath.mpf("1e-28")  # the printed 30 digits are good to ~1e-30; the band is 1e-25
        assert a0_below(lo * (1 - eps) * 3 / 2, theta0, 80) == 0
        assert a0_below(lo * (1 + eps) * 3 / 2, theta0, 80) == 1
        assert b1_below(up * (1 - eps) * 3 / 2, theta0, 80) == 0
        assert b1_below(up * (1 + eps) * 3 / 2, theta0, 80) == 1


def test_an_unresolvable_band_is_said_so_in_text_and_json(capsys):
    assert main(["stability", "--ratio", "1000"]) == 0
    out = capsys.readouterr().out
    assert "lower: none" in out and "upper: none" in out
    assert "not resolvable in double precision" in out and "1334276.39239701" in out
    rec = _json(capsys, "--ratio", "1000")
    assert rec["lower"] is None and rec["upper"] is None
    assert set(rec["why"]) == {"lower", "upper"}
    assert rec["band"]["lower"] is None and rec["band"]["both_ends"].startswith("1334276.39239701")


def test_the_shared_digits_of_an_unresolved_band_hold_both_ends(capsys):
    """omega0/omega = 100: the two ends agree in all 100 certified digits; the Sturm counts at
    130 digits put a_0 = theta0 and b_1 = theta0 both within 1e-97 of the digits given."""
    band = _json(capsys, "--ratio", "100")["band"]
    assert band["digits"] == 100 and band["lower"] is None
    with mpmath.workdps(130):
        at = mpmath.mpf(band["both_ends"])
        theta0 = mpmath.mpf(-40000)
        eps = mpmath.mpf("1e-97")
        n = 400  # (2m)^2 >> q = 2e4 long before m = 400
        assert a0_below(at * (1 - eps) * 3 / 2, theta0, n) == 0   # below the lower end
        assert b1_below(at * (1 + eps) * 3 / 2, theta0, n) == 1   # above the upper end


def test_two_different_ends_are_never_called_unresolved(monkeypatch):
    """A wrong candidate: ends that differ in the 25th digit at 30 digits are a resolved band,
    ends that differ only past the 100th are not; the report follows the digits it is given."""
    from pendulab.analyses import stability_map
    from pendulab.analyses.floquet._charvalues import Limits

    def fake(lo_text, up_text):
        def limits(ratio, inertia_ratio=1, dps=None, method=None):
            with mpmath.workdps(dps + 20):
                return Limits((mpmath.mpf(lo_text), mpmath.mpf(up_text)), dps)
        return limits

    monkeypatch.setattr(stability_map, "stability_limits", fake("7." + "0" * 23 + "1", "7." + "0" * 23 + "2"))
    dps, lo, up, width, proved, shared = st._resolved(10, 4 / 3)
    assert dps == 30 and lo != up and shared is None and width == pytest.approx(1e-24 / 7, rel=1e-6)
    monkeypatch.setattr(stability_map, "stability_limits", fake("7." + "0" * 110 + "1", "7." + "0" * 110 + "2"))
    dps, lo, up, width, proved, shared = st._resolved(10, 4 / 3)
    assert dps == 100 and lo is None and up is None and shared.startswith("7.0")


CASES = [("0.5", "series:40"), ("10", "series:40"), ("0.1", "series:40"), ("1", "integer-series:40"),
         ("0.5", "integer-series:40"), ("0.1", "eq19"), ("0.1", "eq19-corrected"), ("1000", "exact"),
         ("0.1", "exact"), ("0.1", "eq12")]


@pytest.mark.parametrize("ratio, method", CASES)
def test_every_none_says_why_in_text_and_json(ratio, method, capsys):
    rec = _json(capsys, "--ratio", ratio, "--method", method)
    missing = {k for k in ("lower", "upper") if rec[k] is None}
    assert set(rec.get("why", {})) == missing
    for k in missing:
        assert len(rec["why"][k]) > 30 and rec["why"][k] in rec["note"]
    assert main(["stability", "--ratio", ratio, "--method", method]) == 0
    out = capsys.readouterr().out
    for k in missing:
        assert f"{k}: none" in out
        assert rec["why"][k] in out
    if not missing:
        assert "note:" not in out and "why" not in rec


def test_the_reasons_name_what_failed(capsys):
    rec = _json(capsys, "--ratio", "0.5", "--method", "series:40")
    assert "nu = 0" in rec["why"]["lower"] and "fold" in rec["why"]["upper"]
    assert rec["why"]["lower"] != rec["why"]["upper"]
    rec = _json(capsys, "--ratio", "1", "--method", "integer-series:40")
    assert "radius of convergence" in rec["why"]["upper"]
    assert "does not reach theta0 = -4" in rec["why"]["lower"]
    rec = _json(capsys, "--ratio", "0.1", "--method", "eq19")
    assert rec["why"] == {"upper": "the averaging gives only a lower limit (000 eq. 19)"}


def test_a_closed_form_whose_two_limits_meet_says_so(capsys):
    # eq. 28 (000): sqrt(2) r rho < a/l < sqrt(2) r (1/4 + rho^2); the two sides meet at
    # rho = 1/2 (rho = 1/4 + rho^2), where the band is one point, not two limits
    from pendulab.cli import main
    r = 4 / 3
    assert main(["stability", "--method", "eq28", "--ratio", "0.5", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["lower"] == pytest.approx(math.sqrt(2) * r * 0.5, rel=1e-15)
    assert "limits meet at this ratio" in record["note"]
    # beside it the band is open again and nothing is said
    for rho in ("0.45", "0.55"):
        assert main(["stability", "--method", "eq28", "--ratio", rho, "--json"]) == 0
        record = json.loads(capsys.readouterr().out)
        width = math.sqrt(2) * r * (0.25 + float(rho) ** 2 - float(rho))
        assert record["upper"] - record["lower"] == pytest.approx(width, rel=1e-9)
        assert "note" not in record
