"""Stage 4 (analyses): Floquet theory, perturbation series, averaging, stability limits."""
