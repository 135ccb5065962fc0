"""flexslosh: liquid sloshing in tanks carried by flexible structures, from Python.

The package drives the C core (libflexslosh) through its PETSc objects, reads a run's output
directory into numpy arrays and makes the seed paper's figures.

Modules:
    damping   peaks of a decaying oscillation and the damping ratio per cycle
"""
from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__", "damping"]

from . import damping  # noqa: E402  (light: numpy only)
