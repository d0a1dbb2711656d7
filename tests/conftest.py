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
