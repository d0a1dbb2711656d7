"""Messages a newcomer met with about 260 bad inputs (2026-12-04): each must say what is
wrong, and only what is wrong, in one line, with exit status 2 and nothing written.

The command line runs in-process (:func:`pendulab.cli.main`) unless a test needs a clean
stderr (warnings), where it runs as a subprocess.
"""

import subprocess
import sys

import pytest

from pendulab.cli import main
from test_cli_limits import NUMERIC, _argv


def _one_error(capsys, argv):
    """The single ``pendulab: error:`` line of ``argv`` (exit status 2, nothing on stdout)."""
    assert main(argv) == 2
    out = capsys.readouterr()
    lines = out.err.splitlines()
    assert out.out == "" and len(lines) == 1 and lines[0].startswith("pendulab: error: "), out
    return lines[0]


# ---------------------------------------------------------------------------
# one rule for the digits of every integer and number option
# ---------------------------------------------------------------------------

#: Three written the digits of other scripts: int() reads the first two (and the
#: Devanagari one) as 3, and str.isdigit() is True for all of them.
UNICODE_THREES = {
    "arabic-indic": "\u0663",
    "fullwidth": "\uff13",
    "superscript": "\u00b3",
    "devanagari": "\u0969",
    "extended-arabic-indic in a number": "1\u06f3",
}


@pytest.mark.parametrize("kind", sorted(UNICODE_THREES))
@pytest.mark.parametrize("command, option, name", NUMERIC, ids=lambda v: str(v))
def test_digits_of_other_scripts_are_refused_by_every_numeric_option(command, option, name,
                                                                    kind, capsys, tmp_path,
                                                                    monkeypatch):
    monkeypatch.chdir(tmp_path)  # the animate commands name a file relative to it
    text = UNICODE_THREES[kind]
    line = _one_error(capsys, _argv(command, option, text))
    assert line.startswith(f"pendulab: error: {option} must be"), line
    assert repr(text) in line and "ASCII" in line
    assert list(tmp_path.iterdir()) == []  # nothing written (the animation's --out)


def test_the_same_options_accept_ascii_digits(capsys):
    # the neighbour of the refusal: ASCII 3 (with a sign and spaces) is read
    assert main(["sweep", "--grid", " +3 ", "--periods", "1", "--steps-per-period", "20",
                 "--processes", "1", "--quiet", "--json"]) == 0
    assert '"cells": 9' in capsys.readouterr().out
    line = _one_error(capsys, ["sweep", "--grid", "1_0"])  # int() would read 10
    assert "--grid must be an integer" in line and "ASCII" not in line


# ---------------------------------------------------------------------------
# backend = "auto" is costed as what it will run
# ---------------------------------------------------------------------------

def _fig3_scene(tmp_path, backend):
    """One Fig. 3 map (the text's initial conditions) at 100 x 100, 300 periods x 100 steps:
    3e8 RK4 steps, 450 s at NumPy's 1.5 us a step, 9 s at the C kernel's 30 ns."""
    path = tmp_path / f"fig3-{backend}.toml"
    path.write_text('system = "kapitza"\n[products.experiments]\nmaps = ["text"]\ngrid = 100\n'
                    f'backend = "{backend}"\n', encoding="utf-8")
    return path


def _no_compiler(monkeypatch, tmp_path):
    """The compiler look-up made to fail (both variables pendulab reads name a missing file)."""
    for var in ("PENDULAB_CC", "CC"):
        monkeypatch.setenv(var, str(tmp_path / "no-such-cc"))


@pytest.mark.needs_cc
def test_auto_is_costed_as_the_c_kernel_where_a_compiler_is_found(tmp_path):
    from pendulab.commands.sweep import backend_estimate
    from pendulab.errors import SceneError
    from pendulab.scene import load_scene
    assert load_scene(_fig3_scene(tmp_path, "auto")).products["experiments"]["backend"] == "auto"
    assert backend_estimate() == "c"
    # the same map on NumPy is refused: the acceptance above is the cost model's choice
    with pytest.raises(SceneError, match="about 450 s"):
        load_scene(_fig3_scene(tmp_path, "numpy"))


def test_auto_without_a_compiler_is_costed_as_numpy(tmp_path, monkeypatch, capsys):
    from pendulab.commands.sweep import backend_estimate
    _no_compiler(monkeypatch, tmp_path)
    assert backend_estimate() == "numpy"
    out = tmp_path / "out"
    line = _one_error(capsys, ["build", str(_fig3_scene(tmp_path, "auto")), "--out", str(out)])
    assert "about 450 s" in line and "'auto', NumPy: no C compiler found" in line
    assert not out.exists() or not any(out.iterdir())
    # the sweep command's estimate says the same
    line = _one_error(capsys, ["sweep", "--grid", "100", "--periods", "300"])
    assert "about 450 s" in line and "NumPy backend (no C compiler found)" in line


# ---------------------------------------------------------------------------
# the bessel product reports all its problems at once
# ---------------------------------------------------------------------------

def test_the_bessel_scene_reports_a_bad_option_and_the_work_of_the_others(tmp_path, capsys):
    scene = tmp_path / "b.toml"
    # nmax out of range; zeros x dps = 1e7 digits, ten times the work budget
    scene.write_text('system = "variable-length"\n[products.bessel]\nnmax = 99\nzeros = 10000\n'
                     'dps = 1000\npoints = 1\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["build", str(scene), "--out", str(out)]) == 2
    got = capsys.readouterr()
    lines = got.err.splitlines()
    assert got.out == "" and all(line.startswith("pendulab: error: ") for line in lines)
    assert sum("products.bessel.nmax: must be an integer from 0 to 20, got 99" in x for x in lines) == 1
    assert sum("products.bessel.points: must be an integer from 2 to 400, got 1" in x
               for x in lines) == 1
    assert sum("about 10000 zeros at dps = 1000" in x for x in lines) == 1
    assert len(lines) == 3
    assert not out.exists() or not any(out.iterdir())


def test_the_bessel_product_called_directly_lists_every_problem():
    from pendulab.errors import InputError
    from pendulab.pipeline import Context
    from pendulab.products import bessel
    from pendulab.scene import parse_scene
    scene = parse_scene({"system": "variable-length", "parameters": {"length": "L0 - v0*t"},
                         "products": {"bessel": {}}}, path="s.toml")
    options = dict(scene.products["bessel"], nmax=99, zeros=10000, dps=1000, start=3, count=10)
    with pytest.raises(InputError) as info:
        bessel.produce(Context(scene), options)
    text = str(info.value)
    assert "\n" not in text and len(info.value.problems) == 3, text
    assert "nmax must be an integer from 0 to 20, got 99" in text
    assert "about 10000 zeros at dps = 1000" in text
    # a shortening string from j_2,3 has 2*3 - 1 = 5 quarter periods before L = 0 (002)
    assert "count = 10 is more than the 5 quarter periods" in text


# ---------------------------------------------------------------------------
# a Hill drive with the mean criterion: pruning is what needs Mathieu's equation
# ---------------------------------------------------------------------------

HILL = "a*cos(omega*t) + a*cos(2*omega*t)"
SMALL_SWEEP = ["sweep", "--drive", HILL, "--grid", "2", "--periods", "1", "--steps-per-period",
               "20", "--criterion", "mean", "--processes", "1", "--quiet"]


def test_sweep_prune_with_a_hill_drive_names_the_option_not_the_floquet_criterion(capsys):
    line = _one_error(capsys, SMALL_SWEEP + ["--prune"])
    assert "--prune" in line and "Hill" in line and "leave out --prune" in line
    assert "floquet criterion" not in line
    # with the work of the options refused too: both in the one line
    line = _one_error(capsys, ["sweep", "--drive", HILL, "--prune", "--grid", "400",
                               "--periods", "100000"])
    assert "RK4 steps would take about" in line and "leave out --prune" in line
    # the mean criterion itself takes the drive
    assert main(SMALL_SWEEP + ["--json"]) == 0
    assert '"count"' in capsys.readouterr().out


def test_pruned_sweep_of_a_hill_drive_says_pruning_needs_mathieu():
    from pendulab.errors import InputError
    from pendulab.numerics import sweep as S
    spec = S.make_spec(S.SystemSpec("rod", drive=HILL), 2, periods=1, steps_per_period=4)
    with pytest.raises(InputError, match="pruning needs Mathieu's equation") as info:
        S.pruned_sweep(spec, executor="serial", quiet=True)
    assert "floquet criterion" not in str(info.value)


def test_an_experiments_scene_with_a_hill_drive_and_prune_is_told_to_drop_prune(tmp_path, capsys):
    scene = tmp_path / "hill.toml"
    text = (f'system = "kapitza"\nparameters = {{drive = "{HILL}"}}\n[products.experiments]\n'
            'criteria = ["mean"]\nmaps = ["text"]\ngrid = 2\nperiods = 1\nsteps_per_period = 20\n'
            'fig5 = false\nfig2 = false\nfigures = false\n')
    scene.write_text(text + "prune = true\n", encoding="utf-8")
    out = tmp_path / "out"
    line = _one_error(capsys, ["build", str(scene), "--out", str(out)])
    assert "products.experiments: prune:" in line and "set prune = false" in line
    assert "floquet criterion" not in line
    assert not out.exists() or not any(out.iterdir())
    scene.write_text(text + "prune = false\n", encoding="utf-8")
    assert main(["build", str(scene), "--out", str(out)]) == 0, capsys.readouterr().err


# ---------------------------------------------------------------------------
# a scene refused for its name is named as the user gave it
# ---------------------------------------------------------------------------

def test_a_scene_refused_for_its_name_is_named_as_given(tmp_path, monkeypatch, capsys):
    scene = 'name = "pivot"\nsystem = "kapitza"\n[products.equations]\n'
    (tmp_path / "one").mkdir()
    (tmp_path / "deep" / "two").mkdir(parents=True)
    (tmp_path / "one" / "a.toml").write_text(scene, encoding="utf-8")
    (tmp_path / "deep" / "two" / "b.toml").write_text(scene, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["build", "one/a.toml", "--out", "out"]) == 0
    capsys.readouterr()
    before = sorted(p.name for p in (tmp_path / "out" / "pivot").iterdir())
    line = _one_error(capsys, ["build", "deep/two/b.toml", "--out", "out"])
    # the file as given (relative to the working directory), never its last two parts alone
    assert line.startswith("pendulab: error: deep/two/b.toml: name: out/pivot holds")
    assert "two/b.toml" not in line.replace("deep/two/b.toml", "")
    # the owner as its manifest records it, said to be that record
    assert "recorded as one/a.toml in its manifest.json" in line
    assert sorted(p.name for p in (tmp_path / "out" / "pivot").iterdir()) == before


# ---------------------------------------------------------------------------
# the drive's help names the symbol a user writes; the Hill drive prints as text
# ---------------------------------------------------------------------------

def _drive_helps():
    """(command, help text) of every --drive option of the command line (derive and latex too)."""
    from pendulab.cli import make_parser
    from test_cli_limits import _commands
    found = []
    for command, parser in _commands(make_parser()):
        for action in parser._actions:
            if "--drive" in action.option_strings:
                found.append((command, " ".join(parser._get_formatter()._expand_help(action).split())
                              if action.help else ""))
    return found


def test_every_drive_help_speaks_of_omega_as_written():
    helps = dict(_drive_helps())
    # derive, latex eom, sweep, simulate, animate kapitza at least
    assert {"derive kapitza", "latex eom", "sweep", "simulate", "animate kapitza"} <= set(helps)
    for command, text in helps.items():
        assert "Omega" not in text, (command, text)
        assert "omega" in text, (command, text)


def test_derive_and_latex_help_have_no_omega_the_user_cannot_write():
    from pendulab.cli import make_parser
    from test_cli_limits import _commands
    for command, parser in _commands(make_parser()):
        if command.startswith(("derive", "latex")):
            assert "Omega" not in parser.format_help(), command


def test_a_hill_drive_prints_as_readable_text(capsys):
    assert main(["derive", "kapitza", "--drive", HILL]) == 0
    out = capsys.readouterr().out
    fourier = out[out.index("fourier:"):].splitlines()
    # the coefficients of cos(2 k tau): the drive's harmonics omega and 2 omega give k = 1, 2
    assert [line.split(":")[0].strip() for line in fourier[1:4]] == ["0", "2", "4"]
    assert all("cos: " in line and ", sin: " in line for line in fourier[1:4])
    assert not any(ch in out for ch in "{}[]") and "('" not in out  # no dict, list, tuple repr
    assert "\nnote: \n" not in out and not any(line.endswith(": ") for line in out.splitlines())


# ---------------------------------------------------------------------------
# a drive's free symbols: only the user's own, and what a drive may use
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("argv", [
    ["sweep", "--grid", "2"],
    ["simulate", "--a-over-l", "0.1", "--w0-over-w", "0.1"],
])
@pytest.mark.parametrize("drive, named", [
    ("a*cos(omega*t)+b*cos(2*omega*t)", "b"),             # l enters only through b/l
    ("a*cos(omega*t)+g*cos(2*omega*t)", "g"),             # the groups turn g into omega
    ("a*cos(omega*t)+b*cos(2*omega*t)+l*cos(3*omega*t)", "b, l"),  # l written by the user
    ("a*cos(omega*x)", "x"),                              # constant in t: drops out, still named
    ("a*cos(omega*t)+b", "b"),                            # a constant term: the same
    ("a*cos(omega*t)+I*a", "I"),                          # I is the moment of inertia, not sqrt(-1)
])
def test_a_drive_names_only_the_users_free_symbols(argv, drive, named, capsys):
    line = _one_error(capsys, argv + ["--drive", drive])
    assert f"the drive {drive} uses {named}:" in line
    assert "a drive may use only t, a and omega" in line
    # the message is the command's, not a sweep's, and names no symbol the user did not write
    assert "sweep" not in line and "a_over_l" not in line
    if "l*cos" not in drive:
        assert ", l" not in line and " l:" not in line


@pytest.mark.parametrize("drive", ["a*t**2", "a*cos(2*pi*t)", "0"])
def test_a_drive_without_omega_is_refused_for_that(drive, capsys):
    # the runs set omega0/omega and measure time in tau = omega t/2: a drive must have omega
    line = _one_error(capsys, ["simulate", "--a-over-l", "0.1", "--w0-over-w", "0.1",
                               "--drive", drive])
    assert f"the drive {drive} has no omega" in line and "without a value" not in line


# ---------------------------------------------------------------------------
# stability --inertia-ratio: the body is said, not None
# ---------------------------------------------------------------------------

def test_stability_with_an_inertia_ratio_says_what_the_body_is(capsys):
    assert main(["stability", "--ratio", "0.1", "--inertia-ratio", "4/3", "--method", "eq12"]) == 0
    out = capsys.readouterr().out
    assert "body: custom, I/(m l^2) = 4/3\n" in out and "None" not in out


# ---------------------------------------------------------------------------
# quarter periods: with nothing (or one thing) to compare, no sweeping claim
# ---------------------------------------------------------------------------

def test_one_quarter_period_claims_nothing_it_did_not_compare(capsys):
    assert main(["bessel", "quarter-periods", "--count", "1", "--shortening", "--dps", "10"]) == 0
    out = capsys.readouterr().out
    assert "outward (none)" in out and " -" not in out.replace("--count", "")
    assert "not tested" in out and "holds" not in out
    # growing, one k: one comparison (inward 0 against outward 0), said as such
    assert main(["bessel", "quarter-periods", "--count", "1", "--dps", "10"]) == 0
    out = capsys.readouterr().out
    assert "holds for the one comparison shown" in out and "every k" not in out
    assert main(["bessel", "quarter-periods", "--count", "2", "--dps", "10"]) == 0
    assert "holds for every k shown" in capsys.readouterr().out


# ---------------------------------------------------------------------------
# simulate --reference with huge states: one line, no SciPy or NumPy warnings
# ---------------------------------------------------------------------------

def _stderr_lines(run):
    """stderr without the one-line notice of a machine where no C kernel can be built."""
    return [line for line in run.stderr.splitlines()
            if not (line.startswith("pendulab: notice: C kernel") and "NumPy path" in line)]


@pytest.mark.parametrize("extra, fragment", [
    (["--theta-init", "1e300"], "--theta-init must be a number from -10000 to 10000, got '1e300'"),
    (["--omega-init", "-1e300", "--theta-init", "1e300"], "--omega-init must be a number"),
    # the linear equation at omega0/omega = 1000 grows like exp(2000 tau): both overflow
    (["--linear", "--w0-over-w", "1000", "--steps-per-period", "10000"], "overflowed"),
])
def test_simulate_reference_with_huge_states_answers_in_one_line(extra, fragment):
    argv = ["simulate", "--a-over-l", "0", "--w0-over-w", "0", "--periods", "1", "--reference"]
    run = subprocess.run([sys.executable, "-m", "pendulab", *argv, *extra], capture_output=True,
                         text=True, timeout=120)
    err = _stderr_lines(run)
    assert run.returncode == 2 and run.stdout == "", run.stderr
    assert len(err) == 1 and err[0].startswith("pendulab: error: ") and fragment in err[0], err
    assert "Warning" not in run.stderr and "Traceback" not in run.stderr


def test_a_name_taken_from_the_file_name_says_so(tmp_path, monkeypatch, capsys):
    (tmp_path / "lessons").mkdir()
    (tmp_path / "lessons" / "My Pivot.toml").write_text('system = "kapitza"\n[products.equations]\n',
                                                         encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    line = _one_error(capsys, ["build", "lessons/My Pivot.toml", "--out", "out"])
    assert line.startswith("pendulab: error: lessons/My Pivot.toml: name: must be")
    assert "got 'My Pivot' (from the file name" in line and 'name = "..."' in line
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    # a name written in the scene is not said to come from the file name
    (tmp_path / "lessons" / "ok.toml").write_text('name = "My Pivot"\nsystem = "kapitza"\n'
                                                  '[products.equations]\n', encoding="utf-8")
    line = _one_error(capsys, ["build", "lessons/ok.toml", "--out", "out"])
    assert "got 'My Pivot'" in line and "file name" not in line
