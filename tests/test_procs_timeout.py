"""A hung test fails the run instead of stalling it (pytest-timeout, configured in the
[tool.pytest.ini_options] of pyproject.toml).

A child pytest reads the project's own pytest configuration (``-c pyproject.toml``), with
only the number of seconds made short (``-o timeout=...``), and runs one test that hangs
where SIGALRM cannot reach it: SIGALRM blocked, then a long sleep.  The configured method
("thread": a timer thread that dumps the stacks and ends the process) stops it; pytest-timeout's
default ("signal") would let it sleep to the end and pass.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Seconds the hung test sleeps; the child pytest must end well before (it is given SHORT s).
HANG = 30
SHORT = 2

STUCK = f"""\
import signal
import time


def test_stuck():
    signal.pthread_sigmask(signal.SIG_BLOCK, {{signal.SIGALRM}})
    time.sleep({HANG})
"""


@pytest.mark.skipif(not hasattr(signal, "pthread_sigmask"), reason="needs pthread_sigmask (POSIX)")
def test_a_test_that_sigalrm_cannot_reach_fails_within_the_timeout(tmp_path):
    (tmp_path / "test_stuck.py").write_text(STUCK)
    env = {k: v for k, v in os.environ.items() if k != "PYTEST_DISABLE_PLUGIN_AUTOLOAD"}
    argv = [sys.executable, "-m", "pytest", "-c", str(ROOT / "pyproject.toml"),
            "--rootdir", str(tmp_path), "-p", "no:cacheprovider", "-o", f"timeout={SHORT}",
            "-q", str(tmp_path / "test_stuck.py")]
    start = time.monotonic()
    run = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=HANG + 30)
    took = time.monotonic() - start
    assert run.returncode != 0, run.stdout[-2000:]
    assert took < HANG, f"the hung test ran {took:.1f} s: the timeout did not stop it"
    out = run.stdout + run.stderr
    assert "Timeout" in out and "test_stuck" in out, out[-2000:]
