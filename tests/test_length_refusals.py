"""Lengths L(t) that reach zero, pass a pole or only become tiny: refused fast, named right.

Regression tests of two bugs of the motion product: (1) a periodic L(t) reaching 0 went into
the Floquet verdict (minutes of DOP853, then a step-size error); (2) exp(-k t) underflowing
to 0.0 at k t = 745.4 was reported as a zero.
Each CLI run is a subprocess with a timeout: a regression hangs into the timeout and fails.
"""

import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from pendulab.analyses import variable_length_motion as vm
from pendulab.exprs import parse

SRC = str(Path(__file__).resolve().parents[1] / "src")
#: the refusals take about 2 s (most of it the start of Python and SymPy); the bug took 90 s
TIMEOUT = 40


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=SRC)
    return subprocess.run([sys.executable, "-m", "pendulab", *args], capture_output=True,
                          text=True, timeout=TIMEOUT, env=env)


def _motion_scene(tmp_path, length, values, extra=""):
    p = tmp_path / "s.toml"
    p.write_text(f'name = "s"\nsystem = "variable-length"\n[parameters]\nlength = "{length}"\n'
                 f"[products.motion]\nfigures = false\nvalues = {values}\n{extra}")
    return p


def _refused(tmp_path, scene):
    out = tmp_path / "out"
    run = _cli("build", str(scene), "--out", str(out))
    assert run.returncode == 2 and run.stdout == ""
    err = run.stderr.strip()
    assert "\n" not in err and err.startswith("pendulab: error:") and "Traceback" not in err
    assert "products.motion" in err
    assert not out.exists()  # nothing partial written
    return err


def _time(err, what):
    return float(re.search(what + r" at t = ([0-9.e+-]+)", err).group(1))


# -- 1. a periodic L(t) that reaches 0: refused before the Floquet verdict ---------

@pytest.mark.parametrize("length, values, extra, zero", [
    # L0 (1 + 2 sin(Omega t)) = 0 first where sin(Omega t) = -1/2: Omega t = 7 pi/6
    ("L0*(1+eps*sin(Omega*t))", "{eps = 2, Omega = 6.26}", "", 7 * math.pi / 6 / 6.26),
    # L0 cos(w t) = 0 first at w t = pi/2
    ("L0*cos(w*t)", "{w = 1}", "", math.pi / 2),
    # t_end before the zero: the Floquet verdict still integrates the whole period 2 pi
    ("L0*cos(w*t)", "{w = 1}", "t_end = 1.0", math.pi / 2),
])
def test_motion_periodic_length_reaching_zero_is_refused_fast(tmp_path, length, values, extra, zero):
    err = _refused(tmp_path, _motion_scene(tmp_path, length, values, extra))
    assert "reaches 0" in err and _time(err, "reaches 0") == pytest.approx(zero, rel=1e-11)
    if extra:
        assert "Floquet verdict" in err and "T = 6.28318530718" in err  # 2 pi / w


def test_motion_periodic_length_touching_zero_is_refused_fast(tmp_path):
    # L0 (1 + sin(Omega t)) touches 0 at Omega t = 3 pi/2 without a change of sign: it
    # falls to 1e-6 L0 just before, at sin(Omega t) = -1 + 1e-6
    omega = 6.26
    err = _refused(tmp_path, _motion_scene(tmp_path, "L0*(1+eps*sin(Omega*t))",
                                           f"{{eps = 1, Omega = {omega}}}", "t_end = 1.0"))
    before = (math.pi + math.asin(1 - 1e-6)) / omega
    assert "falls to 1e-06 L(0)" in err and _time(err, "L\\(0\\)") == pytest.approx(before, rel=1e-9)


# -- 2. underflow is not a zero ---------------------------------------------------

def test_exponential_length_underflow_is_not_a_zero(tmp_path):
    values = {"L0": 1.0, "k": 1.0}
    length = parse("L0*exp(-k*t)")
    # exp(-t) is 0.0 in doubles from t = 745.2 on, but never 0
    assert vm.length_zero_time(length, values, horizon=1000.0) is None
    err = _refused(tmp_path, _motion_scene(tmp_path, "L0*exp(-k*t)", "{k = 1}", "t_end = 1000.0"))
    assert "reaches 0" not in err and "too short, relative to L(0)" in err
    # L = 1e-6 L0 at t = ln(1e6)/k
    assert _time(err, "falls to 1e-06 L\\(0\\)") == pytest.approx(math.log(1e6), rel=1e-9)


def test_length_through_a_pole_is_not_a_zero():
    values = {"L0": 1.0}
    length = parse("L0*(1 + tan(t))")
    assert vm.length_zero_time(length, values, horizon=3.0) is None  # the pole at pi/2
    with pytest.raises(vm.LengthReachesZeroError) as info:
        vm.length_check(length, values, 3.0, t_end=3.0)
    assert "not a finite positive length" in str(info.value)
    assert info.value.time == pytest.approx(math.pi / 2, rel=1e-9)


@pytest.mark.parametrize("length, zero", [
    ("L0*exp(-10*t)", None),                # 0.0 in floats past t = 74.5: underflow, no zero
    ("exp(-t) - exp(-2)", 2.0),             # a true zero at t = 2 (exp(-t) = exp(-2))
])
def test_length_note_does_not_take_underflow_for_a_zero(length, zero):
    from pendulab.systems import VariableLength, length_zero_note
    note = length_zero_note(VariableLength(parse(length)))
    if zero is None:
        assert note is None
    else:
        found = re.search(r"reaches zero at about t = ([0-9.e+-]+)", note or "")
        assert found and float(found.group(1)) == pytest.approx(zero, rel=1e-5)
