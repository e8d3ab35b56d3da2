"""ParaDyn: parallel explicit finite elements for contact-impact of thin shells.

The frontend meshes scenes with gmsh, writes HDF5 decks, launches the Fortran engine and turns its
results into VTK, CSV, JSON and plots. ``paradyn.run(source, out)`` does all of it in one call;
``paradyn.read(path)`` opens a results file; ``paradyn.read_keyword(path)`` reads an LS-DYNA
keyword deck into a deck model (docs/keyword.md); ``paradyn.study(scene, out, knobs=...)`` shows
what accuracy costs in time (docs/accuracy-cost.md).
"""
from .builder import Cylinder, MeshFile, Plate, Scene
from .keyword_scene import read_keyword
from .reading import Results, read
from .study_sweep import study
from .workflow import BatchJob, run

__all__ = ["BatchJob", "Cylinder", "MeshFile", "Plate", "Results", "Scene", "read", "read_keyword", "run",
           "study"]
__version__ = "0.1.0"
