"""generated/ does not depend on SymPy's ground types.

SymPy 1.14 picks the integers and rationals under its polynomials when it is
first imported: "flint" by itself when python-flint is installed, else
"gmpy" (or "python"); the environment variable SYMPY_GROUND_TYPES overrides
the choice.  pendulab pins "gmpy" (``pendulab/__init__.py``, unless the user
set the variable), and its products must come out byte-identical under every
choice: each build below runs in a fresh interpreter with the ground type
forced, checks that SymPy really runs on it, and compares every file with the
committed generated/.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

_BUILD = """
import sys
import pendulab
import sympy.external.gmpy as g
print(g.GROUND_TYPES)
from pendulab.cli import main
sys.exit(main(["build", sys.argv[1], "--out", sys.argv[2], "--force"]))
"""


def _env(ground_types):
    env = {k: v for k, v in os.environ.items() if k != "SYMPY_GROUND_TYPES"}
    if ground_types is not None:
        env["SYMPY_GROUND_TYPES"] = ground_types
    return env


def _ground_types_of(code, ground_types):
    out = subprocess.run([sys.executable, "-c", code], env=_env(ground_types), capture_output=True,
                         text=True, check=True)
    return out.stdout.strip()


def test_pendulab_pins_gmpy_and_keeps_an_explicit_choice():
    flint_present = _ground_types_of("import importlib.util as u; print(bool(u.find_spec('flint')))", None)
    # SymPy on its own would choose flint here (python-flint is a dependency): the pin matters
    if flint_present == "True":
        assert _ground_types_of("import sympy.external.gmpy as g; print(g.GROUND_TYPES)", None) == "flint"
    assert _ground_types_of("import pendulab, sympy.external.gmpy as g; print(g.GROUND_TYPES)", None) == "gmpy"
    assert _ground_types_of("import pendulab, sympy.external.gmpy as g; print(g.GROUND_TYPES)",
                            "python") == "python"


@pytest.mark.slow
@pytest.mark.parametrize("ground_types", ["flint", "gmpy", "python"])
def test_build_is_byte_identical_under_every_ground_type(tmp_path, ground_types):
    out = tmp_path / "generated"
    run = subprocess.run([sys.executable, "-c", _BUILD, str(ROOT / "derivations"), str(out)],
                         env=_env(ground_types), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines()[0] == ground_types          # SymPy really ran on it
    committed = ROOT / "generated"
    def products(root):  # the build's lock file and other dot files are not products
        return sorted(p.relative_to(root) for p in root.rglob("*") if p.is_file()
                      and not any(part.startswith(".") for part in p.relative_to(root).parts))
    files = products(committed)
    assert files, "nothing committed to compare with"
    built = products(out)
    assert built == files
    for rel in files:
        assert (out / rel).read_bytes() == (committed / rel).read_bytes(), f"{rel} differs ({ground_types})"
