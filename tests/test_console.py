"""The ``pendulab`` command's entry point (pendulab.cli.console): it ends the process with
os._exit after flushing, so everything printed must still arrive, whole, with main's status."""

import os
import subprocess
import sys

import mpmath

CODE = "import sys; from pendulab.cli import console; console(sys.argv[1:])"


#: block-buffered standard streams, as on a user's machine (a PYTHONUNBUFFERED in the test's
#: environment would hide a missing flush)
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}


def _run(*argv):
    return subprocess.run([sys.executable, "-c", CODE, *argv], capture_output=True, text=True,
                          timeout=120, env=ENV)


def test_long_output_to_a_pipe_arrives_whole_with_status_0():
    # 400 zeros of J_1 at 40 digits: ~20 kB, more than one pipe buffer's flush
    p = _run("bessel", "zeros", "--order", "1", "--count", "400", "--dps", "40")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 401 and lines[-1].startswith("j_1,400 = ")
    # the last zero, independently: mpmath's besseljzero (DLMF 10.21)
    with mpmath.workdps(50):
        assert abs(mpmath.mpf(lines[-1].split("= ")[1]) - mpmath.besseljzero(1, 400)) < mpmath.mpf(10) ** -35


def test_an_error_keeps_status_2_and_its_one_line():
    p = _run("bessel", "zeros", "--order", "1", "--count", "0")
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1 and p.stderr.startswith("pendulab: error:")


def test_a_closed_pipe_is_status_1_without_a_traceback():
    p = subprocess.run(f"{sys.executable} -c '{CODE}' bessel zeros --order 1 --count 3000 --dps 30"
                       " | head -c 10 >/dev/null", shell=True, capture_output=True, text=True,
                       timeout=120, env=ENV)
    assert "Traceback" not in p.stderr and "Exception ignored" not in p.stderr, p.stderr
