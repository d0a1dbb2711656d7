"""The numerics stage: what computes from the derivations.

* :mod:`pendulab.numerics.model` - first-order systems (state, parameters,
  right-hand sides, Jacobians) read from the equations and canonical stages;
  the one road from a derivation to a number.

Nothing here re-types an equation of the sources.
"""
