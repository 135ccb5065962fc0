"""flexslosh: liquid sloshing in tanks carried by flexible structures, from Python.

The package drives the C core (libflexslosh) through its PETSc objects, reads a run's output
directory into numpy arrays and makes the seed paper's figures.

Modules:
    damping   peaks of a decaying oscillation, the damping ratio per cycle, the envelope's fit
    output    read_run, read_csv, read_snapshot: an output directory as numpy arrays
    figures   the seed's Figs. 5-11 as PNG files (matplotlib, imported only when drawing)
    impact    impact pressures from a probe's record: a zero-phase low-pass, the peak in a window, the ringing
    movie     a run's animation (MP4 or GIF) or one frame of it: the particles coloured by a field,
              the walls, the tip's motion (``python3 -m flexslosh.plot movie OUTPUT_DIR``)
    plot      the command line ``python3 -m flexslosh.plot OUTPUT_DIR ...`` (not imported here, so
              that ``-m`` runs it cleanly)
    solver    Solver: one run of the C core, its TS and DMSwarm as petsc4py objects, fields as numpy
    structure Structure: structure models in Python, registered with register_structure
    sweep     sweep(): many runs (fill levels, tank shapes...) in sequence or over MPI ranks, damping per cycle
    waves     the linear viscous standing wave (Lamb) and the fit of a decaying oscillation to E_k(t)

petsc4py (and MPI) are initialized on first use of Solver or register_structure, not on import.
"""
from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__", "damping", "output", "figures", "impact", "movie", "solver", "structure", "sweep", "waves", "Solver",
           "Structure", "TankMotion", "register_structure"]

from . import damping  # noqa: E402  (light: numpy only)
from . import output  # noqa: E402  (numpy; h5py only when a snapshot is read)
from . import figures  # noqa: E402  (numpy; matplotlib only when a figure is drawn)
from . import impact  # noqa: E402  (light: numpy only)
from . import movie  # noqa: E402  (numpy; matplotlib only when drawing)
from . import waves  # noqa: E402  (light: numpy only)
from . import solver, structure, sweep  # noqa: E402  (light: numpy; petsc4py and the binding are loaded on first use)
from .solver import Solver  # noqa: E402
from .structure import Structure, TankMotion, register_structure  # noqa: E402
