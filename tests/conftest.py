"""Shared fixtures: mpmath's global precision is reset around every test; tests marked
``needs_cc`` (they build C kernels) skip where no C compiler is found.

To run the suite as on a machine without a compiler, name a missing one in both variables
pendulab reads, e.g. ``PENDULAB_CC=/nonexistent CC=/nonexistent``: the C tests skip and
every other test runs on the NumPy path (fixtures that unset PENDULAB_CC still meet $CC).
"""

import mpmath
import pytest


def c_compiler():
    """The C compiler pendulab would run ($PENDULAB_CC, else $CC, else cc) where it is found
    on this machine, else None."""
    from pendulab.numerics.ckernel import compiler_found
    return compiler_found()


def pytest_runtest_setup(item):
    if item.get_closest_marker("needs_cc") is not None and c_compiler() is None:
        pytest.skip("no C compiler found ($PENDULAB_CC, $CC or cc): the C kernels cannot be "
                    "built here (pendulab takes the NumPy path, which its own tests cover)")


@pytest.fixture(autouse=True)
def _reset_mpmath():
    dps, pretty = mpmath.mp.dps, mpmath.mp.pretty
    yield
    mpmath.mp.dps, mpmath.mp.pretty = dps, pretty


@pytest.fixture
def rng():
    """A seeded generator: random points are reproducible."""
    import numpy as np
    return np.random.default_rng(20261122)


@pytest.fixture
def band_kernel_cache(tmp_path_factory, monkeypatch):
    """The vectorised Floquet band kernel compiles into a per-session temporary cache,
    never the user's, with the compiler and the C path as the environment leaves them
    by default (PENDULAB_CC, PENDULAB_BAND_NUMPY unset)."""
    from pendulab.analyses.floquet import _vectorised as V
    from pendulab.numerics import ckernel
    monkeypatch.setenv("PENDULAB_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "kcache"))
    monkeypatch.delenv("PENDULAB_CC", raising=False)
    monkeypatch.delenv("PENDULAB_BAND_NUMPY", raising=False)
    ckernel.clear_loaded()
    V._C_STATE.clear()
    yield
    ckernel.clear_loaded()
    V._C_STATE.clear()


def scipy_mathieu_limits(ratio, inertia_ratio):
    """The limits of a/l from SciPy's characteristic values, an engine independent of
    pendulab's: the lower limit solves a_0(q) = theta0, the upper b_1(q) = theta0
    (scipy.special.mathieu_a(0, q), mathieu_b(1, q)), with theta0 = -4 (omega0/omega)^2 and
    q = theta1 = 2 (a/l)/(I/(m l^2)) (000 eqs. 5-6 in tau = omega t/2), so a/l = q I/(2 m l^2).
    SciPy's values are trusted only for q <= 3 (they fail at large q: scipy issues 4479, 14526);
    beyond that this raises."""
    from scipy.optimize import brentq
    from scipy.special import mathieu_a, mathieu_b

    theta0, q_max = -4.0 * ratio**2, 3.0
    f_low = lambda q: mathieu_a(0, q) - theta0  # noqa: E731
    f_up = lambda q: mathieu_b(1, q) - theta0  # noqa: E731
    if f_low(q_max) > 0 or f_up(q_max) > 0:
        raise ValueError(f"omega0/omega = {ratio} needs q > {q_max}, beyond SciPy's trusted range")
    low = 0.0 if ratio == 0 else brentq(f_low, 0.0, q_max, xtol=1e-15, rtol=1e-14)
    up = brentq(f_up, 0.0, q_max, xtol=1e-15, rtol=1e-14)
    return low * inertia_ratio / 2, up * inertia_ratio / 2


@pytest.fixture
def scipy_limits():
    """:func:`scipy_mathieu_limits`, the independent reference of the stability limits."""
    return scipy_mathieu_limits


# mutmut (docs/mutation.md) forks each mutant's test run from the process that collected the
# coverage statistics, so every per-process cache that process filled is inherited: a result
# cached there is served without calling the mutated function, and the mutant "survives"
# untested.  Under mutmut (MUTANT_UNDER_TEST set) the caches of computed results are emptied
# before every test; the derivations (_STAGES, _SYSTEMS: seconds each) only when the mutant
# is in the functions that fill them.
_RESULT_CACHES = {
    "pendulab.numerics.sweep": ("_PAIRS", "_VERDICTS", "_EXPONENTS", "_MONODROMY_MAPS"),
    "pendulab.numerics.step_check": ("_COEFFICIENTS",),
    "pendulab.numerics.monodromy": ("_LAMBDIFIED",),
}
_DERIVATION_FILLERS = ("x__derive_", "x__stages_", "x_stages_", "x_first_order_system_",
                       "x_use_stages_")


@pytest.fixture(autouse=True)
def _fresh_caches_under_mutmut():
    import os
    import sys

    mutant = os.environ.get("MUTANT_UNDER_TEST", "")
    if mutant:
        for name, caches in _RESULT_CACHES.items():
            module = sys.modules.get(name)
            for cache in caches if module is not None else ():
                getattr(module, cache).clear()
        if any(f in mutant for f in _DERIVATION_FILLERS) and "pendulab.numerics.sweep" in sys.modules:
            sys.modules["pendulab.numerics.sweep"]._STAGES.clear()
            sys.modules["pendulab.numerics.sweep"]._SYSTEMS.clear()
    yield
