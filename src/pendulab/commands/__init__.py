"""Sub-commands of the ``pendulab`` command line (one module each)."""
