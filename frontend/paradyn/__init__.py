"""ParaDyn: parallel explicit finite elements for contact-impact of thin shells.

The frontend meshes scenes with gmsh, writes HDF5 decks, launches the Fortran engine and turns its
results into VTK, CSV, JSON and plots. ``paradyn.read(path)`` opens a results file.
"""
from .results import Results, read

__all__ = ["Results", "read"]
__version__ = "0.1.0"
