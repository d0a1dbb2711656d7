"""Products: what a scene can ask for.  Each module defines OPTIONS, SYSTEMS and produce()."""
