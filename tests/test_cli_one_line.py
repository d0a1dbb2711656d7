"""Usage errors of every command are one line, ``pendulab: error: ...``, exit status 2.

argparse itself would print the usage text first; and accepted options must
not ask for hours of work (bounded work).
"""

import pytest

from pendulab.cli import main


@pytest.mark.parametrize("argv", [
    ["nope"],
    ["sweep", "--body", "foo"],
    ["sweep", "--body", "rod", "--inertia-ratio", "2"],
    ["floquet", "--theta0", "0.1"],
    ["simulate", "--a-over-l", "0.2"],
    ["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--json", "--csv"],
    ["derive", "kapitza", "--body", "foo"],
    ["bessel", "zeros", "--order"],
])
def test_usage_errors_are_one_line(argv, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("pendulab: error: ")
    assert "Traceback" not in err and "usage:" not in err


@pytest.mark.parametrize("argv", [
    ["floquet", "--theta0", "0.1", "--theta1", "0.2", "--dps", "2.5"],
    ["series", "--order", "x"],
    ["bessel", "zeros", "--order", "1", "--count", "1e3"],
])
def test_bad_numbers_are_one_line(argv, capsys):
    # numeric options are read by the command (pendulab.limits.parse), not by argparse
    assert main(argv) == 2
    out = capsys.readouterr()
    assert out.out == "" and out.err.count("\n") == 1 and out.err.startswith("pendulab: error: --")


@pytest.mark.parametrize("argv,what", [
    (["sweep", "--grid", "400", "--periods", "100000", "--steps-per-period", "10000"], "RK4 steps"),
    (["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "100000",
      "--steps-per-period", "100", "--reference", "--json"], "--reference"),
])
def test_hours_of_work_are_refused_at_once(argv, what, capsys):
    assert main(argv) == 2
    out = capsys.readouterr()
    assert out.out == ""
    assert out.err.count("\n") == 1 and what in out.err


@pytest.mark.parametrize("argv", [
    ["simulate", "--a-over-l", "1e300", "--w0-over-w", "0.05", "--json"],
    ["sweep", "--theta-init", "1e308", "--grid", "2", "--json"],
])
def test_absurd_sizes_are_refused_not_integrated(argv, capsys):
    # found by an audit: these integrated to overflow and exited 0
    assert main(argv) == 2
    out = capsys.readouterr()
    assert out.out == "" and out.err.count("\n") == 1 and "to 10000, got '1e" in out.err
