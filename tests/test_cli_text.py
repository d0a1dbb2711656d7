"""The commands' text output reads as text: no Python reprs (None, dicts, lists) a user
would have to decode."""

from pendulab.cli import main


def _run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr().out
    return code, out


def test_stability_with_an_inertia_ratio_prints_no_body_none(capsys):
    code, out = _run(capsys, "stability", "--ratio", "0.1", "--inertia-ratio", "4/3")
    assert code == 0 and "None" not in out and "inertia_ratio: 1.333" in out
    code, out = _run(capsys, "stability", "--ratio", "0.1", "--body", "point")
    assert code == 0 and "body: point" in out


def test_a_hill_drives_fourier_coefficients_are_lines_not_a_dict(capsys):
    code, out = _run(capsys, "derive", "kapitza", "--drive", "a*cos(omega*t) + b*cos(2*omega*t)")
    assert code == 0
    assert "{" not in out and "['" not in out, out
    # the drive's second harmonic: 16 b l m / I in front of cos(4 tau) (tau = omega t/2)
    assert "4: cos: 16*b*l*m/I, sin: 0" in out


def test_one_shortening_quarter_period_does_not_claim_the_claim_holds(capsys):
    # one inward swing and no outward one (the string reaches zero length): nothing to compare
    code, out = _run(capsys, "bessel", "quarter-periods", "--count", "1", "--shortening")
    assert code == 0
    assert "outward (none)" in out and "outward -" not in out
    assert "not tested" in out and "holds for every k shown" not in out


def test_a_sweep_names_only_the_symbols_the_user_wrote(capsys):
    # b is the second harmonic's amplitude; l enters only through the groups (b/l)
    code = main(["sweep", "--drive", "a*cos(omega*t)+b*cos(2*omega*t)", "--grid", "2"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "uses b:" in err[0] and " l " not in err[0].split("uses")[1][:12]


def test_stability_says_why_a_limit_is_missing_or_unresolved(capsys):
    code, out = _run(capsys, "stability", "--ratio", "1000")
    # a band narrower than double precision is not printed as two equal numbers
    assert code == 0 and "lower: none" in out and "upper: none" in out
    assert "not resolvable in double precision" in out
    code, out = _run(capsys, "stability", "--ratio", "0.1", "--method", "eq19")
    assert "upper: none" in out and "note: upper none: the averaging gives only a lower limit" in out
    code, out = _run(capsys, "stability", "--ratio", "0.1", "--method", "series:40")
    assert "upper: none" in out and "no fold before its pole" in out
    code, out = _run(capsys, "stability", "--ratio", "0.1")
    assert "note:" not in out  # two resolved limits need no word
