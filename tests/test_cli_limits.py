"""Every numeric option of the command line has its range in pendulab.limits.LIMITS.

The parsers are introspected: each option that takes a value is either a
numeric option registered with :func:`pendulab.limits.argument` (its argparse
action carries ``limit``, the LIMITS entry) or listed in NOT_NUMERIC with the
reason.  For each numeric option the help shows the entry's range, a value
just above the maximum (or below the minimum) is refused in one line, and the
maximum itself is accepted (run where that is cheap).
"""

import argparse
import json
import subprocess
import sys
from fractions import Fraction

import pytest

from pendulab import limits
from pendulab.cli import main, make_parser

#: Options that take a value but are not numbers, with what they are.
NOT_NUMERIC = {
    ("build", "--out"): "a directory",
    ("derive kapitza", "--inertia"): "an expression (pendulab.exprs limits)",
    ("derive kapitza", "--drive"): "an expression (pendulab.exprs limits, MAX_HARMONICS)",
    ("derive variable-length", "--length"): "an expression",
    ("derive variable-length", "--mass"): "an expression",
    ("series", "--kind"): "a kind name (nu, a0, b1, ...)",
    ("stability", "--method"): "a method name; N of series:N has its own entries",
    ("sweep", "--drive"): "an expression",
    ("simulate", "--drive"): "an expression",
    ("sweep", "--criterion"): "a criterion name",
    ("sweep", "--dask"): "a scheduler address",
    ("latex series", "--kind"): "a kind name (nu, a0, b1, ...)",
    ("latex eom", "--inertia"): "an expression",
    ("latex eom", "--drive"): "an expression",
    ("latex eom", "--length"): "an expression",
    ("latex eom", "--mass"): "an expression",
    ("latex stability", "--methods"): "method names; N of series:N has its own entries",
    ("latex quarter-periods", "--length"): "an expression",
    ("animate kapitza", "--drive"): "an expression",
    ("animate kapitza", "--out"): "a file name",
    ("animate variable-length", "--length"): "an expression",
    ("animate variable-length", "--out"): "a file name",
    ("sweep", "--plot"): "a file name (pendulab.plots.check_target)",
    ("simulate", "--plot"): "a file name (pendulab.plots.check_target)",
    ("stability", "--plot"): "a file name (pendulab.plots.check_target)",
    ("bessel zeros", "--plot"): "a file name (pendulab.plots.check_target)",
    ("bessel quarter-periods", "--plot"): "a file name (pendulab.plots.check_target)",
}


def _commands(parser, path=()):
    """(command path such as 'bessel zeros', its parser) for every leaf sub-command."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield " ".join(path), parser
        return
    for name, sub in subs[0].choices.items():
        yield from _commands(sub, path + (name,))


def _valued_options():
    """(command, option string, action) of every option that takes a value, with no choices."""
    out = []
    for command, parser in _commands(make_parser()):
        for action in parser._actions:
            if (action.option_strings and action.nargs != 0 and action.choices is None
                    and not isinstance(action, (argparse._HelpAction, argparse._VersionAction))):
                out.append((command, action.option_strings[-1], action))
    return out


def numeric_options():
    """(command, option, LIMITS name) of the numeric options of the command line."""
    return [(c, o, a.limit) for c, o, a in _valued_options() if getattr(a, "limit", None)]


NUMERIC = numeric_options()


def test_every_option_that_takes_a_value_is_numeric_with_an_entry_or_listed():
    unclassified = [(c, o) for c, o, a in _valued_options()
                    if not getattr(a, "limit", None) and (c, o) not in NOT_NUMERIC]
    assert unclassified == []
    assert all(name in limits.LIMITS for _c, _o, name in NUMERIC)
    # the listed exceptions exist and are not numeric
    present = {(c, o) for c, o, _a in _valued_options()}
    assert set(NOT_NUMERIC) <= present
    assert not {(c, o) for c, o, _n in NUMERIC} & set(NOT_NUMERIC)


def test_the_introspection_finds_the_numeric_options_it_should():
    # a check of the check: a few options known to be numeric are found with their entries
    found = {(c, o): n for c, o, n in NUMERIC}
    assert found[("sweep", "--grid")] == "experiments.grid"
    assert found[("simulate", "--periods")] == "experiments.periods"
    assert found[("bessel identities", "--dps")] == "bessel.dps"
    assert found[("floquet", "--dps")] == "floquet.dps"
    assert len(found) >= 30


def _help_of(command):
    parser = dict(_commands(make_parser()))[command]
    return " ".join(parser.format_help().split())


@pytest.mark.parametrize("command, option, name", NUMERIC, ids=lambda v: str(v))
def test_the_help_states_the_range(command, option, name):
    text = _help_of(command)
    start = text.index(option + " ", text.index("options:"))
    entry = text[start:start + 400]
    assert limits.describe(name) in entry


#: The smallest argv of each command to which one option is added (cheap to run).
BASE = {
    "series": ["series", "--order", "1"],
    "floquet": ["floquet", "--theta0", "0", "--theta1", "0"],
    "stability": ["stability", "--ratio", "0.1", "--method", "eq12"],
    "bessel zeros": ["bessel", "zeros", "--order", "1", "--count", "1", "--dps", "5"],
    "bessel quarter-periods": ["bessel", "quarter-periods", "--count", "1", "--dps", "5"],
    "bessel identities": ["bessel", "identities", "--nmax", "0", "--points", "2", "--dps", "5",
                          "--engine", "arb", "--cross-only"],
    "sweep": ["sweep", "--grid", "1", "--periods", "1", "--steps-per-period", "1",
              "--processes", "1", "--quiet"],
    "simulate": ["simulate", "--a-over-l", "0", "--w0-over-w", "0", "--periods", "1",
                 "--steps-per-period", "1", "--every", "1"],
    "latex series": ["latex", "series", "--order", "1", "--kind", "a0"],
    "latex stability": ["latex", "stability", "--points", "2", "--methods", "eq12"],
    "latex zeros": ["latex", "zeros", "--nu", "1", "--count", "1", "--dps", "5"],
    "latex quarter-periods": ["latex", "quarter-periods", "--count", "1", "--dps", "5"],
    # refused before anything is drawn, so nothing is written to the file named
    "animate kapitza": ["animate", "kapitza", "--periods", "1", "--out", "never-written.gif"],
    "animate variable-length": ["animate", "variable-length", "--t-end", "1",
                                "--out", "never-written.gif"],
}


def _argv(command, option, value):
    base = list(BASE[command])
    if option in base:
        i = base.index(option)
        base[i:i + 2] = []
    plain = command.startswith(("latex ", "animate "))  # no other format than their own
    return base + [f"{option}={value}"] + ([] if plain else ["--json"])


def _beyond(name):
    """Texts just outside the range of ``name`` (above the maximum; below the minimum)."""
    kind, low, high, _d, _h = limits.LIMITS[name]
    if kind is int:
        return [str(high + 1), str(low - 1)]
    step = Fraction(1, 1000)
    out = [str(Fraction(high) + step)]
    out.append(str(Fraction(low)) if kind == "positive" else str(Fraction(low) - step))
    return out


@pytest.mark.parametrize("command, option, name", NUMERIC, ids=lambda v: str(v))
def test_just_outside_the_range_is_refused_in_one_line(command, option, name, capsys):
    for value in _beyond(name):
        assert main(_argv(command, option, value)) == 2, value
        out = capsys.readouterr()
        assert out.out == ""
        assert out.err.count("\n") == 1 and out.err.startswith(f"pendulab: error: {option} must be")
        assert limits.describe(name).split(" ")[0] in out.err


#: Options whose maximum is cheap to run from BASE (the others, such as series --order 60,
#: take up to a minute: their worst cases are measured in docs/scenes.md instead).
AT_MAX = {
    ("floquet", "--theta0"): [],              # theta1 = 0: exact square root
    ("floquet", "--dps"): [],
    ("stability", "--ratio"): [],
    ("stability", "--inertia-ratio"): [],
    ("bessel zeros", "--order"): [],
    ("bessel zeros", "--dps"): [],
    ("bessel quarter-periods", "--dps"): [],
    ("bessel identities", "--nmax"): ["--dps", "3"],
    ("bessel identities", "--points"): ["--dps", "3"],
    ("bessel identities", "--z"): [],
    ("sweep", "--theta-init"): [],
    ("sweep", "--omega-init"): [],
    ("sweep", "--periods"): [],
    ("sweep", "--steps-per-period"): [],
    # at the largest a/l and omega0/omega, one step per period is refused as unstable
    # (pendulab.numerics.step_check): the steps that make it stable
    ("simulate", "--a-over-l"): ["--steps-per-period", "200"],
    ("simulate", "--w0-over-w"): ["--steps-per-period", "2300"],
    ("simulate", "--theta-init"): [],
    ("simulate", "--omega-init"): [],
    ("simulate", "--every"): [],
    ("simulate", "--steps-per-period"): [],
    ("simulate", "--periods"): ["--every", "1000"],
    ("simulate", "--inertia-ratio"): [],
    ("latex series", "--order"): [],          # kind a0: the integer series to q^60 in a second
    ("latex zeros", "--nu"): [],
    ("latex stability", "--max-ratio"): [],
}


@pytest.mark.parametrize("key", sorted(AT_MAX), ids=lambda k: " ".join(k))
def test_the_maximum_is_accepted(key, capsys):
    command, option = key
    name = dict(((c, o), n) for c, o, n in NUMERIC)[key]
    high = limits.LIMITS[name][2]
    argv = _argv(command, option, high) + AT_MAX[key]
    assert main(argv) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    if "--json" in argv:
        json.loads(out)


def test_the_accepted_maxima_cover_most_commands():
    commands = {c for c, _o in AT_MAX}
    assert commands >= {"floquet", "stability", "bessel zeros", "bessel identities", "sweep",
                        "simulate"}


def test_problems_of_several_options_come_in_one_line(capsys):
    assert main(["simulate", "--a-over-l", "-1", "--w0-over-w", "2000", "--periods", "0",
                 "--every", "x", "--inertia-ratio", "0.5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    for option in ("--a-over-l", "--w0-over-w", "--periods", "--every", "--inertia-ratio"):
        assert f"{option} must be" in err


def test_the_work_of_options_together_is_refused_before_any_work(capsys):
    # each option in range, their product not (the C kernel's or NumPy's cost model)
    assert main(["sweep", "--grid", "400", "--periods", "100000", "--steps-per-period", "10000"]) == 2
    assert "RK4 steps would take" in capsys.readouterr().err
    assert main(["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "100000",
                 "--steps-per-period", "10000"]) == 2
    assert "must be at most 1e+07" in capsys.readouterr().err
    assert main(["simulate", "--a-over-l", "10000", "--w0-over-w", "1000", "--periods", "100",
                 "--reference"]) == 2
    assert "DOP853 reference would need" in capsys.readouterr().err
    assert main(["bessel", "zeros", "--order", "1", "--count", "10000", "--dps", "1000"]) == 2
    assert "--count x --dps" in capsys.readouterr().err


def test_grid_above_its_maximum_is_reported_once(capsys):
    from pendulab.errors import InputError
    from pendulab.numerics import sweep as S
    with pytest.raises(InputError) as info:
        S.make_spec(S.SystemSpec("rod"), grid=401)
    assert str(info.value).count("grid must be") == 1


def _stderr(run):
    """The lines of ``run``'s stderr without the one-line notice that no C kernel could be
    built (a machine without a compiler: the NumPy path, by design)."""
    return [line for line in run.stderr.splitlines()
            if not (line.startswith("pendulab: notice: C kernel") and
                    line.endswith("using the NumPy path"))]


def test_simulate_reference_of_an_overflowing_run_is_one_line():
    # found by an audit: NumPy's and SciPy's RuntimeWarnings leaked on stderr.  The linear
    # equation at omega0/omega = 1000 grows like exp(2000 tau): RK4 overflows within a period.
    run = subprocess.run([sys.executable, "-m", "pendulab", "simulate", "--linear", "--w0-over-w",
                          "1000", "--a-over-l", "0", "--periods", "1", "--steps-per-period", "10000",
                          "--reference", "--json"], capture_output=True, text=True)
    assert run.returncode == 2 and run.stdout == ""
    err = _stderr(run)
    assert len(err) == 1 and "overflowed" in err[0], run.stderr


def test_the_reference_stops_at_its_evaluation_budget():
    import numpy as np

    from pendulab.errors import InputError
    from pendulab.numerics import integrate as I
    from pendulab.numerics import sweep as S
    spec = S.make_spec(S.SystemSpec("rod"), a_over_l=[0.2], w0_over_w=[0.05], periods=2)
    fos = S.first_order_system(spec.system)
    y0, params = S.cell_arrays(spec, np.arange(1))
    tau = np.linspace(0, 2 * np.pi, 201)
    with pytest.raises(InputError, match="passed 100 evaluations"):
        I.reference_trajectory(fos, y0[0], params[0], tau, max_evaluations=100)
    # the same run without the bound reaches the end (so the bound is what stopped it)
    assert I.reference_trajectory(fos, y0[0], params[0], tau).shape == (201, 2)


def test_simulate_reference_of_huge_states_answers_cleanly():
    # a fast rotation (|theta(0)|, |dtheta/dtau(0)| at their maxima): an answer, nothing on stderr
    run = subprocess.run([sys.executable, "-m", "pendulab", "simulate", "--a-over-l", "0",
                          "--w0-over-w", "0", "--theta-init", "10000", "--omega-init", "-10000",
                          "--periods", "2", "--steps-per-period", "1", "--every", "1", "--reference",
                          "--json"],
                         capture_output=True, text=True)
    assert run.returncode == 0 and _stderr(run) == [], run.stderr
    rec = json.loads(run.stdout)
    assert rec["theta"][0] == 10000.0 and len(rec["theta_reference"]) == 3


@pytest.mark.parametrize("theta0, theta1, method, limit", [
    ("-4000000", "1/3", "hill", 4e6), ("-5000", "0.0001", "monodromy", 5000),
    ("-30000.4", "0", "cf", 3e4)])
def test_a_size_just_above_the_limit_reads_as_above_it(theta0, theta1, method, limit, capsys):
    # found by an audit: "|theta0| + 2|theta1| = 4.0e+6 is too large (limit 4e+06)"
    assert main(["floquet", "--theta0", theta0, "--theta1", theta1, "--method", method]) == 2
    err = capsys.readouterr().err
    shown = err.split(" = ", 1)[1].split(" ", 1)[0]
    assert float(shown) > limit and f"limit {limit:g}" in err


def test_stability_at_the_largest_ratio_warns_nothing():
    # found by an audit: the series method's coefficients overflowed with NumPy's
    # RuntimeWarnings on stderr (the answer, no limit, was right)
    run = subprocess.run([sys.executable, "-m", "pendulab", "stability", "--ratio", "1000",
                          "--inertia-ratio", "1000", "--method", "series:40", "--json"],
                         capture_output=True, text=True)
    assert run.returncode == 0 and run.stderr == ""
    assert json.loads(run.stdout)["lower"] is None
