"""flexslosh: liquid sloshing in tanks carried by flexible structures, from Python.

The package drives the C core (libflexslosh) through its PETSc objects, reads a run's output
directory into numpy arrays and makes the seed paper's figures.

Modules:
    damping   peaks of a decaying oscillation, the damping ratio per cycle, the envelope's fit
    output    read_run, read_csv, read_snapshot: an output directory as numpy arrays
    figures   the seed's Figs. 5-11 as PNG files (matplotlib, imported only when drawing)
    plot      the command line ``python3 -m flexslosh.plot OUTPUT_DIR ...`` (not imported here, so
              that ``-m`` runs it cleanly)
"""
from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__", "damping", "output", "figures"]

from . import damping  # noqa: E402  (light: numpy only)
from . import output  # noqa: E402  (numpy; h5py only when a snapshot is read)
from . import figures  # noqa: E402  (numpy; matplotlib only when a figure is drawn)
