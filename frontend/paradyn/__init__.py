"""ParaDyn: parallel explicit finite elements for contact-impact of thin shells.

The frontend meshes scenes with gmsh, writes HDF5 decks, launches the Fortran engine and turns its
results into VTK, CSV, JSON and plots. ``paradyn.run(source, out)`` does all of it in one call;
``paradyn.read(path)`` opens a results file; ``paradyn.read_keyword(path)`` reads an LS-DYNA
keyword deck into a deck model (docs/keyword.md); ``paradyn.study(scene, out, knobs=...)`` shows
what accuracy costs in time (docs/accuracy-cost.md).
"""
from typing import Any

from .builder import Cylinder, MeshFile, Plate, Scene
from .reading import Results, read
from .workflow import BatchJob, run

__all__ = ["BatchJob", "Cylinder", "MeshFile", "Plate", "Results", "Scene", "read", "read_keyword", "run",
           "study"]
__version__ = "0.1.0"
# imported when first used: a paradyn-run needs neither, and the study's imports cost it 60 ms
_LAZY = {"read_keyword": "keyword_scene", "study": "study_sweep"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from importlib import import_module

        return getattr(import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'paradyn' has no attribute {name!r}")
