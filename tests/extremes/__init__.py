"""Numerical stability at the extremes (docs/extremes.md): one module per topic."""
