"""Shared fixtures: mpmath's global precision is reset around every test."""

import mpmath
import pytest


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
