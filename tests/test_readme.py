"""The README's Quick tour works as typed after the README's first command.

The first command makes ``.venv`` in the project directory; the tour's lines
are then run by a shell in a copy of the project (scenes and committed
outputs) whose ``.venv`` is the environment running the tests, exactly as
written in README.md.
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def _block(title):
    """The indented command lines of the README section ``title``."""
    section = README.split(f"## {title}\n", 1)[1].split("\n## ", 1)[0]
    return [line[4:] for line in section.splitlines() if line.startswith("    ")]


def test_the_first_two_commands_are_unchanged():
    """Setup + main job and setup + tests, as the project's card fixes them."""
    assert ("    python3 -m venv .venv && .venv/bin/pip install -q -c constraints.txt -e "
            "'.[figures]' && .venv/bin/pendulab build derivations/\n") in README
    assert ("    python3 -m venv .venv && .venv/bin/pip install -q -c constraints.txt -e "
            "'.[test,figures]' && .venv/bin/python -m pytest -q\n") in README


def test_every_tour_command_names_the_venvs_pendulab():
    """No bare `pendulab`: the first command never activates the virtual environment."""
    lines = _block("Quick tour")
    assert len(lines) >= 5
    for line in lines:
        assert line.startswith(".venv/bin/pendulab "), line


@pytest.mark.slow
def test_the_quick_tour_runs_as_typed(tmp_path):
    bindir = Path(sys.executable).parent
    if not (bindir / "pendulab").exists():
        pytest.fail(f"the console script pendulab is not installed beside {sys.executable}")
    project = tmp_path / "project"
    project.mkdir()
    shutil.copytree(ROOT / "derivations", project / "derivations")
    shutil.copytree(ROOT / "generated", project / "generated",
                    ignore=shutil.ignore_patterns(".*"))
    (project / ".venv").symlink_to(bindir.parent)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV",)}
    env["PATH"] = "/usr/bin:/bin"  # no pendulab on the PATH: only .venv/bin/pendulab works
    for line in _block("Quick tour"):
        command = re.sub(r"\s+#.*$", "", line)
        res = subprocess.run(command, shell=True, cwd=project, env=env, capture_output=True,
                             text=True, timeout=300)
        assert res.returncode == 0, (command, res.stderr)
        assert res.stdout.strip() and "Traceback" not in res.stderr, command
