"""Property-based fuzzing of scene files and command lines (hypothesis).

Whatever the input, ``pendulab`` either succeeds (exit 0) or prints one or
more lines, each ``pendulab: error: ...``, and exits with status 2: never a
traceback, never a hang.  The CLI runs in-process (pendulab.cli.main with
stdout/stderr captured) so that a hundred cases take seconds; each case has
an alarm (CASE_SECONDS) that turns a hang into a failure.  A few cases run
in a subprocess to see exactly what a user sees.

The values are drawn from pools of good and bad input (NaN, infinities,
negative numbers, huge numbers, junk text, deep nesting, injections) and from
a small expression grammar; the good values are cheap by construction (small
orders, few points), so a valid scene builds in a second or two.
"""

import contextlib
import io
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from pendulab.cli import main

ROOT = Path(__file__).resolve().parents[1]
CASE_SECONDS = 25

# -- expressions ---------------------------------------------------------------------------

_ATOMS = ["t", "a", "b", "omega", "m", "l", "L0", "v0", "I0", "g", "0", "1", "2", "0.5", "-1",
          "1/2", "pi", "inf", "nan", "oo", "zoo", "theta", "theta(t)", "y0(t)", "x", "1e999",
          "__import__('os')", "''", "E", "I",
          # found by the 2026-12-03 audit: numbers past Python's 4300 printed digits or its
          # Rational's patience, unicode digits, a byte-order mark
          "1e5000", "1e999999999", "1e-999999", "(10**1000)", "\u00b3", "\u0663", "\ufeffa"]
_FUNCS = ["sin", "cos", "tan", "exp", "log", "sqrt", "Abs", "besselj", "Eq", "Tuple",
          "Rational", "Derivative", "f", "Matrix"]
_OPS = ["+", "-", "*", "/", "**", "^", "%", "<", ","]


def _expressions():
    atom = st.sampled_from(_ATOMS)
    return st.recursive(
        atom,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(_OPS), inner).map(lambda x: f"({x[0]}{x[1]}{x[2]})"),
            st.tuples(st.sampled_from(_FUNCS), inner).map(lambda x: f"{x[0]}({x[1]})"),
            st.tuples(st.sampled_from(_FUNCS), inner, inner).map(
                lambda x: f"{x[0]}({x[1]}, {x[2]})"),
            inner.map(lambda x: f"-{x}"),
        ),
        max_leaves=8,
    )


_SPECIAL_EXPRESSIONS = [
    "a*cos(omega*t)", "L0 + v0*t", "L0 - v0*t", "L0*cos(t)", "3 - 2*t", "m*l**2/2",
    "m*l**2 + I0", "Rational(1, 0)*cos(t)", "(a+b+c+d+t)**200", "t**999.5*cos(t)**999",
    "Derivative(Derivative(cos(t), (t, 20)), (t, 20))", "-" * 3990 + "a", "+".join(["a"] * 70),
    "Eq(t, 1)", "Tuple(1, 2)", "cos(t)**999", "a*cos(omega*t)**2", "1/(t - t)",
    "(" * 300 + "t" + ")" * 300, "a*" * 1500 + "t",
    "a*cos(omega*t)" + "*(10**1000)" * 5, "a*cos(omega*t)*(10**3000*a)**1000",
    "Piecewise((a, t > 0), (0, True))", "sqrt(-1)*a*cos(omega*t)", "Integer(1.5)*t",
]


_GOOD_EXPRESSIONS = ["a*cos(omega*t)", "a*sin(omega*t) + b*cos(2*omega*t)", "y0(t)", "a*t**2",
                     "L0 + v0*t", "L0*(2 + cos(t))", "m*l**2 + I0", "m", "2", "-a*cos(omega*t)"]


def expressions():
    return st.one_of(st.sampled_from(_GOOD_EXPRESSIONS), st.sampled_from(_SPECIAL_EXPRESSIONS),
                     _expressions())


# -- TOML values ------------------------------------------------------------------------------

def _toml_values():
    scalars = st.one_of(
        st.sampled_from(["nan", "inf", "-inf", "0", "-1", "1", "2", "8", "30", "1001", "20000",
                         "10000000000000000000", "0.5", "-0.25", "1e400", "true", "false",
                         "1" + "0" * 5000,
                         '""', '"x"', '"1/2"', '"-1/5"', '"abc"', '"0"', '"nan"']),
        expressions().map(lambda e: '"' + e.replace("\\", "").replace('"', "'") + '"'),
    )
    return st.recursive(scalars, lambda inner: st.lists(inner, max_size=3).map(
        lambda xs: "[" + ", ".join(xs) + "]"), max_leaves=6)


_OPTIONS = {
    "equations": {"x": None},
    "series": {"order": ["0", "1", "2", "3", "61", "-1", "true", '"4"'],
               "kinds": ['["nu"]', '["a0", "b1"]', '["x1"]', "[]", '["nu", "nu"]', '"nu"',
                         '["a\u00b2"]']},
    "floquet": {"points": ['[["-0.002", "0.2"]]', '[["-1/5", "1/10"]]', "[[nan, 0.2]]",
                           "[[1]]", '[["1e9", "1"]]', "[]", '[["a", "b"]]', "[[0.1, -0.2]]"],
                "ratios": ['["0"]', "[]", '["-1"]', '["x"]', "[inf]", '["0.1", "0.2"]'],
                "dps": ["1", "15", "0", "101", "20000", "-5", '"30"'],
                "method": ['"hill"', '"cf"', '"monodromy"', '"eval"', "3"]},
    "stability": {"points": ["2", "3", "1", "402", "1001", "-3", "2.5"],
                  "max_ratio": ['"1/2"', '"0"', '"11"', '"abc"', '"1/0"', "0.5"],
                  "methods": ['["eq12"]', '["eq12", "eq19"]', '["eq99"]', '["series:0"]', '["series:\u00b3"]',
                              '["series:41"]', "[]", '["integer-series:3"]'],
                  "figure": ["false", "true", '"no"']},
    "quarter_periods": {"count": ["1", "4", "0", "201", "-1"], "dps": ["5", "15", "4", "101"]},
    "nonsense": {"x": None},
}


@st.composite
def scene_texts(draw):
    """A scene file's text: mostly the right shape, with good and bad values."""
    lines = []
    if draw(st.integers(0, 4)) == 0:
        lines.append(f'name = "{draw(st.sampled_from(["fz", "FZ", "../x", "", "a" * 70]))}"')
    system = draw(st.sampled_from(["kapitza"] * 4 + ["variable-length"] * 3 + ["sled", None]))
    if system is not None:
        lines.append(f'system = "{system}"')
    if draw(st.integers(0, 9)) == 0:
        lines.append(f"colour = {draw(_toml_values())}")
    params = draw(st.lists(st.sampled_from(["body", "drive", "angle", "inertia", "length",
                                            "mass", "other"]), max_size=3, unique=True))
    if params:
        lines.append("[parameters]")
        for key in params:
            if key in ("body", "angle"):
                value = draw(st.sampled_from(['"rod"', '"point"', '"explicit"', '"up"',
                                              '"down"', "3", "nan"]))
            elif draw(st.integers(0, 5)) == 0:
                value = draw(_toml_values())
            else:
                value = '"' + draw(expressions()).replace('"', "'") + '"'
            lines.append(f"{key} = {value}")
    products = draw(st.lists(st.sampled_from(sorted(_OPTIONS)), min_size=draw(st.sampled_from(
        [0, 1, 1, 1])), max_size=2, unique=True))
    for product in products:
        lines.append(f"[products.{product}]")
        for key, pool in _OPTIONS[product].items():
            if draw(st.booleans()):
                value = draw(_toml_values()) if pool is None or draw(st.integers(0, 9)) == 0 \
                    else draw(st.sampled_from(pool))
                lines.append(f"{key} = {value}")
    return "\n".join(lines) + "\n"


# -- command lines ------------------------------------------------------------------------------

_NUMBERS = ["-1/5", "-0.002", "0.2", "1/5", "0", "-1", "1e-3", "-1e-3", "0.1", "2", "-3/7",
            "inf", "nan", "-inf", "1e999", "abc", "", " ", "--", "-", "1/0", "0x10",
            "__import__('os')", "100"]


@st.composite
def command_lines(draw):
    command = draw(st.sampled_from(["derive"] * 3 + ["floquet"] * 3 + ["series"] * 2
                                   + ["stability"] * 3 + ["build", "nope"]))
    argv = [command]
    if command == "derive":
        system = draw(st.sampled_from(["kapitza", "variable-length", "sled"]))
        argv.append(system)
        for opt in draw(st.lists(st.sampled_from(["--drive", "--inertia", "--body", "--angle",
                                                  "--length", "--mass", "--json", "--latex"]),
                                 max_size=3, unique=True)):
            if opt in ("--json", "--latex"):
                argv.append(opt)
            elif opt in ("--body", "--angle"):
                argv += [opt, draw(st.sampled_from(["rod", "point", "explicit", "up", "x"]))]
            else:
                argv += [opt, draw(expressions())]
    elif command == "floquet":
        for opt in ("--theta0", "--theta1"):
            if draw(st.integers(0, 8)):
                argv += [opt, draw(st.sampled_from(_NUMBERS))]
        if draw(st.booleans()):
            argv += ["--dps", draw(st.sampled_from(["15", "0", "101", "20000", "-3", "x"]))]
        if draw(st.booleans()):
            argv += ["--method", draw(st.sampled_from(["hill", "cf", "monodromy", "x"]))]
        if draw(st.booleans()):
            argv.append("--json")
    elif command == "series":
        if draw(st.integers(0, 8)):
            argv += ["--order", draw(st.sampled_from(["0", "1", "3", "61", "-2", "x", "1e3"]))]
        if draw(st.booleans()):
            argv += ["--kind", draw(st.sampled_from(["nu", "a0", "b1", "b0", "c2", "-a1", ""]))]
        argv += draw(st.sampled_from([[], ["--json"], ["--latex"], ["--json", "--latex"]]))
    elif command == "stability":
        if draw(st.integers(0, 8)):
            argv += ["--ratio", draw(st.sampled_from(_NUMBERS))]
        choice = draw(st.integers(0, 2))
        if choice == 1:
            argv += ["--body", draw(st.sampled_from(["rod", "point", "x"]))]
        elif choice == 2:
            argv += ["--inertia-ratio", draw(st.sampled_from(_NUMBERS))]
        if draw(st.booleans()):
            argv += ["--method", draw(st.sampled_from(["exact", "eq12", "series:0", "series:4",
                                                       "integer-series:41", "eq99", "-1"]))]
    elif command == "build":
        argv.append(draw(st.sampled_from(["missing.toml", "", "-x"])))
    return argv


# -- running ------------------------------------------------------------------------------------

class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout(f"a case ran longer than {CASE_SECONDS} s")


def run_cli(argv):
    """(exit status, stdout, stderr) of pendulab.cli.main(argv), in-process, with an alarm."""
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(CASE_SECONDS)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse: usage errors exit 2 with its own message
                code = exc.code
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    return code, out.getvalue(), err.getvalue()


def assert_clean(code, stderr, argv):
    assert "Traceback" not in stderr, (argv, stderr)
    if code == 0:
        return
    assert code == 2, (argv, code, stderr)
    lines = stderr.strip().splitlines()
    assert lines, (argv, "exit 2 without a message")
    usage = lines[0].startswith("usage: ")  # argparse's own errors: usage line, then one error
    if usage:
        lines = [line for line in lines if not line.startswith(("usage: ", " "))]
        assert len(lines) == 1 and ": error: " in lines[0], (argv, stderr)
    else:
        assert all(line.startswith("pendulab: error: ") for line in lines), (argv, stderr)


_FUZZ = settings(max_examples=60, deadline=None, derandomize=True,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@_FUZZ
@given(scene_texts())
def test_any_scene_file_builds_or_fails_cleanly(text):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fz.toml"
        path.write_text(text, encoding="utf-8")
        argv = ["build", str(path), "--out", str(Path(tmp) / "out")]
        code, _out, err = run_cli(argv)
        assert_clean(code, err, text)


@_FUZZ
@given(command_lines())
def test_any_command_line_succeeds_or_fails_cleanly(argv):
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)  # a build command writes nothing outside the temporary directory
        try:
            code, _out, err = run_cli(argv)
        finally:
            os.chdir(cwd)
        assert_clean(code, err, argv)


# -- the examples of a newcomer's report, as a user runs them ---------------------------------------------

def _subprocess(args, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    return subprocess.run([sys.executable, "-m", "pendulab", *args], capture_output=True,
                          text=True, env=env, timeout=120, cwd=tmp_path)


@pytest.mark.parametrize("name, text, fragment", [
    ("nan", 'system = "kapitza"\n[products.floquet]\npoints = [[nan, 0.2]]\n', "NaN"),
    ("deep", 'system = "kapitza"\n[products.equations]\nx = ' + "[" * 10000 + "]" * 10000 + "\n",
     "nested too deeply"),
    ("minus", 'system = "kapitza"\n[parameters]\ndrive = "' + "-" * 3990 + 'a"\n'
              "[products.equations]\n", "nested too deeply"),
])
def test_subprocess_scenes_fail_with_one_line(tmp_path, name, text, fragment):
    scene = tmp_path / f"{name}.toml"
    scene.write_text(text, encoding="utf-8")
    res = _subprocess(["build", str(scene), "--out", str(tmp_path / "out")], tmp_path)
    assert res.returncode == 2 and "Traceback" not in res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error: ") and fragment in lines[0]
    assert not (tmp_path / "out").exists()


def test_subprocess_command_line_fails_with_one_line(tmp_path):
    res = _subprocess(["derive", "kapitza", "--drive", "inf"], tmp_path)
    assert res.returncode == 2 and res.stdout == "" and "Traceback" not in res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error: ")
    assert "'inf' is not allowed" in lines[0]


@pytest.mark.parametrize("argv, fragment", [
    (["derive", "kapitza", "--drive", "Rational(1, 0)*cos(t)"], "division by zero"),
    (["derive", "kapitza", "--drive", "Eq(t, 1)"], "a relation"),
    (["derive", "kapitza", "--drive", "nan"], "'nan' is not allowed"),
    (["derive", "kapitza", "--drive", "-" * 3990 + "a"], "nested too deeply"),
    (["floquet", "--theta0", "0.1", "--theta1", "0.1", "--dps", "20000"], "--dps"),
    (["floquet", "--theta0", "-1/5", "--theta1", "-1e-3", "--dps", "15"], None),
])
def test_issue_command_lines(argv, fragment):
    code, out, err = run_cli(argv)
    if fragment is None:
        assert code == 0 and err == "" and "lambda" in out
        return
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pendulab: error: ") and fragment in lines[0]
