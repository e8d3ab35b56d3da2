"""ParaDyn: parallel explicit finite elements for contact-impact of thin shells.

The frontend meshes scenes (or reads gmsh and other mesh files), writes HDF5 decks, launches the
Fortran engine and turns its results into VTK, CSV, JSON and plots. ``paradyn.run(source, out)``
does all of it in one call; ``paradyn.read(path)`` opens a results file; ``paradyn.read_keyword(path)`` reads an LS-DYNA
keyword deck into a deck model (docs/keyword.md); ``paradyn.study(scene, out, knobs=...)`` shows
what accuracy costs in time (docs/accuracy-cost.md).

The names below are imported when first used, so that ``import paradyn.cli`` loads only what a
command needs and the commands can settle their environment before numpy loads
(:mod:`paradyn.commands`).
"""
from __future__ import annotations

from importlib import import_module
from importlib.util import find_spec
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .arguments import ArgumentError as ArgumentError
    from .keyword.scene import read_keyword as read_keyword
    from .results.reading import Results as Results
    from .results.reading import read as read
    from .running.run_warnings import EngineWarning as EngineWarning
    from .running.run_warnings import KeywordWarning as KeywordWarning
    from .running.run_warnings import ModelWarning as ModelWarning
    from .running.run_warnings import ParaDynWarning as ParaDynWarning
    from .running.workflow import BatchJob as BatchJob
    from .running.workflow import run as run
    from .scene.builder import Cylinder as Cylinder
    from .scene.builder import MeshFile as MeshFile
    from .scene.builder import Plate as Plate
    from .scene.builder import Scene as Scene
    from .studies.sweep import study as study

# name -> the module that defines it
_EXPORTS = {
    "ArgumentError": "arguments", "BatchJob": "running.workflow", "Cylinder": "scene.builder",
    "EngineWarning": "running.run_warnings", "KeywordWarning": "running.run_warnings",
    "MeshFile": "scene.builder", "ModelWarning": "running.run_warnings",
    "ParaDynWarning": "running.run_warnings", "Plate": "scene.builder", "Results": "results.reading",
    "Scene": "scene.builder", "read": "results.reading", "read_keyword": "keyword.scene", "run": "running.workflow",
    "study": "studies.sweep",
}
__all__ = sorted(_EXPORTS)
__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        value = getattr(import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value   # found once
        return value
    if not name.startswith("_") and find_spec(f"{__name__}.{name}") is not None:
        return import_module(f".{name}", __name__)   # paradyn.scene, paradyn.deck ... as before
    raise AttributeError(f"module 'paradyn' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
