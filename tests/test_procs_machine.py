"""pendulab on another machine: one without a C compiler, one without AVX-512.

Without a compiler, found as pendulab finds one.  No ``$PENDULAB_CC``, no ``$CC`` and a PATH on which there is no ``cc`` (an empty directory):
the lookup itself finds nothing, not a variable that names a missing file.  Then the kernels
take the NumPy path (after one notice), the tests marked ``needs_cc`` skip (tests/conftest.py
asks the same lookup), and the work limits of ``pendulab sweep`` and ``pendulab simulate`` are
those of the NumPy path: a sweep that the C kernel would finish within the budget, and the
NumPy path not, is refused at once instead of running for 25 minutes.

Without AVX-512: NumPy's float64 pow, log and exp loops for AVX-512 differ from the C
library's in the last bits, and NumPy calls the C library elsewhere; the committed outputs
must come out the same either way.  NumPy's dispatch is switched off in a child process by
``NPY_DISABLE_CPU_FEATURES`` (only where this machine has AVX-512 to switch off).
"""

import os
import subprocess
import sys
import time

from pathlib import Path

import numpy as np
import pytest

from pendulab.numerics import ckernel, integrate
from pendulab.numerics import sweep as S


@pytest.fixture
def no_cc(tmp_path, monkeypatch):
    """An empty directory as the whole PATH, no compiler variable, a temporary kernel cache."""
    empty = tmp_path / "bin"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.delenv("PENDULAB_CC", raising=False)
    monkeypatch.setenv("PENDULAB_CACHE_DIR", str(tmp_path / "cache"))
    ckernel.clear_loaded()
    yield empty
    ckernel.clear_loaded()


SRC = str(Path(__file__).resolve().parents[1] / "src")


def _env(no_cc):
    env = {k: v for k, v in os.environ.items() if k not in ("CC", "PENDULAB_CC")}
    env.update(PATH=str(no_cc), PYTHONPATH=SRC)
    return env


def test_without_cc_on_the_path_the_kernel_is_numpy_after_one_notice(no_cc, capsys):
    from conftest import c_compiler
    from pendulab.commands.sweep import backend_estimate
    assert ckernel.compiler_command() == ["cc"] and ckernel.compiler_found() is None
    assert c_compiler() is None  # so the needs_cc tests skip here
    assert backend_estimate() == "numpy"
    fos = S.first_order_system(S.SystemSpec("rod"))
    args = (fos, [[0.06, 0.01], [0.3, -0.2]], [0.2, 0.05], 0.0, 0.1, 50)
    got = [integrate.ensemble_rk4(*args) for _ in range(2)]
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert "'cc' not found" in lines[0] and lines[0].endswith("using the NumPy path")
    assert integrate.c_kernel_available() is False
    ref = integrate.ensemble_rk4(*args, backend="numpy")
    for r in got:
        assert r.backend == "numpy"
        for name in ("y", "mean_theta", "mean_abs_theta", "max_abs_theta"):
            assert np.array_equal(getattr(r, name), getattr(ref, name)), name
    assert not list((no_cc.parent / "cache").rglob("*.so"))


def test_a_cc_on_the_path_is_found_and_a_broken_one_still_falls_back(no_cc, capsys):
    """The lookup can also answer yes: an executable named cc on the PATH is the compiler
    (the cost model then expects C); this one fails, so the kernel is NumPy's all the same."""
    from pendulab.commands.sweep import backend_estimate
    cc = no_cc / "cc"
    cc.write_text("#!/bin/sh\necho 'cc: broken on purpose' >&2\nexit 1\n")
    cc.chmod(0o755)
    assert ckernel.compiler_found() == str(cc)
    assert backend_estimate() == "c"
    fos = S.first_order_system(S.SystemSpec("rod"))
    r = integrate.ensemble_rk4(fos, [[0.06, 0.01]], [0.2, 0.05], 0.0, 0.1, 10)
    assert r.backend == "numpy"
    assert integrate.c_kernel_available() is False
    assert "broken on purpose" in capsys.readouterr().err


@pytest.mark.parametrize("argv, why", [
    # 100^2 cells x 1000 periods x 100 steps: about 30 s with the C kernel, 1500 s on NumPy
    (["sweep", "--grid", "100", "--periods", "1000", "--quiet"], "trajectories x"),
    # 10^6 RK4 steps of one trajectory: about 1 s with the C kernel, 400 s on NumPy
    (["simulate", "--a-over-l", "0.2", "--w0-over-w", "0.05", "--periods", "10000",
      "--steps-per-period", "100"], "RK4 steps would take"),
])
def test_without_cc_the_work_limit_is_the_numpy_paths(no_cc, argv, why):
    start = time.monotonic()
    run = subprocess.run([sys.executable, "-m", "pendulab", *argv], env=_env(no_cc),
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stdout == "", run.stderr[-2000:]
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and why in lines[0] and "no C compiler found" in lines[0], lines
    assert time.monotonic() - start < 30


ROOT = Path(SRC).parent


def _avx512_dispatch():
    """NumPy's dispatched AVX-512 targets that are on here (names as NPY_DISABLE_CPU_FEATURES
    takes them), or [] where there are none or NumPy does not say."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:
        return []
    return [f for f in __cpu_dispatch__
            if __cpu_features__.get(f) and (f.startswith("AVX512") or f == "X86_V4")]


@pytest.mark.slow
def test_the_variable_length_outputs_do_not_depend_on_numpys_avx512_loops(tmp_path):
    """The committed variable-length scene built as it is here and with NumPy's AVX-512 loops
    switched off gives the committed generated/ both times (its envelope figure took NumPy's
    pow, log and matplotlib's log axes: 3 PDF coordinates and 70 PNG pixels moved)."""
    off = _avx512_dispatch()
    if not off:
        pytest.skip("NumPy takes no AVX-512 loops here: there is no second path to compare")
    committed = ROOT / "generated" / "variable-length"
    check = ("from numpy._core._multiarray_umath import __cpu_features__ as f; "
             f"print(sum(bool(f.get(k)) for k in {off!r}))")
    for name, extra in (("as-is", {}), ("no-avx512", {"NPY_DISABLE_CPU_FEATURES": " ".join(off)})):
        env = dict(os.environ, PYTHONPATH=SRC, PENDULAB_CACHE_DIR=str(tmp_path / "cache"), **extra)
        on = subprocess.run([sys.executable, "-c", check], env=env, capture_output=True,
                            text=True, timeout=60)
        assert on.stdout.strip() == ("0" if extra else str(len(off))), on
        out = tmp_path / name
        run = subprocess.run([sys.executable, "-m", "pendulab", "build",
                              str(ROOT / "derivations" / "variable-length.toml"), "--force",
                              "--out", str(out)], env=env, capture_output=True, text=True,
                             timeout=300)
        assert run.returncode == 0, run.stderr[-2000:]
        built = out / "variable-length"
        names = sorted(p.name for p in committed.iterdir())
        assert sorted(p.name for p in built.iterdir()) == names
        differ = [n for n in names if (built / n).read_bytes() != (committed / n).read_bytes()]
        assert differ == [], f"{name}: {differ}"
