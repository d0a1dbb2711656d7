"""pendulab: symbolic-numeric derivations for parametrically driven pendulums.

Two systems are modelled, following the two source documents
(000_8cba66c4fdf94ac6.txt: the inverted pendulum on a vertically driven pivot;
002_19b336b29bb1f03b.txt: the variable-length pendulum).

The package is import-light: heavy modules (analyses, numerics) are imported
only when asked for.
"""

__version__ = "0.7.0"

import os as _os

# SymPy picks its ground types (the integers and rationals under its
# polynomials) when it is first imported: "flint" by itself when python-flint
# is installed (SymPy 1.14), else "gmpy".  Pin one choice so that generated/
# is the same whichever is installed; a user's explicit SYMPY_GROUND_TYPES is
# kept.  This only works when pendulab is imported before SymPy.
_os.environ.setdefault("SYMPY_GROUND_TYPES", "gmpy")

from pendulab.errors import (  # noqa: F401
    PendulabError,
    InputError,
    SceneError,
    PrecisionError,
    ConvergenceError,
    SeriesDomainError,
    AccuracyWarning,
)


def __getattr__(name):
    """``pendulab.load_expr`` and ``pendulab.dump_expr``, imported on first use.

    They live in :mod:`pendulab.exprs`, which imports SymPy; importing them
    lazily keeps ``import pendulab`` (and ``pendulab --help``) free of SymPy.
    """
    if name in ("load_expr", "dump_expr"):
        from pendulab import exprs
        return getattr(exprs, name)
    raise AttributeError(f"module 'pendulab' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + ["load_expr", "dump_expr"])
