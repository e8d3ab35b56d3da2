"""Results: read ParaDyn results files and turn them into files other tools read.

The work is split by job, and each job has its module:

* :mod:`paradyn.results.reading`: :func:`read` and the :class:`Results` object (frames read on demand);
* :mod:`paradyn.results.layout`: the layout of ``results.h5`` and the checks made when opening one;
* :mod:`paradyn.results.names`: the run's names, title and effects (from ``results.h5``, else the deck);
* :mod:`paradyn.results.grids`: a frame as a pyvista grid;
* :mod:`paradyn.results.vtkhdf_export` and :mod:`paradyn.results.vtk_export`: ``results.vtkhdf``
  and the ParaView/pyvista time series per part (``<part>.pvd`` + ``vtk/<part>_<k:05d>.vtu``);
* :mod:`paradyn.results.reports`: the history as CSV, the energy report and ``summary.json``;
* :mod:`paradyn.results.figures`, :mod:`paradyn.results.rendering` and :mod:`paradyn.results.plots`:
  the figures ``Results.plot`` returns, the off-screen pyvista drawing, the PNG files;
* :mod:`paradyn.results.postprocess`: what ``paradyn-run`` writes after a run.

The results read the deck beside them (names, thicknesses) but nothing of the scene, the keyword
reader or the runs. docs/outputs.md describes every output file, its columns, keys and units.

The names below (the former ``paradyn.results`` module's) are imported when first used, so that
importing one module of the package loads only what it needs.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .layout import ENERGY_NAMES as ENERGY_NAMES
    from .layout import SUPPORTED_RESULTS_VERSIONS as SUPPORTED_RESULTS_VERSIONS
    from .layout import TRACKED_COMPONENTS as TRACKED_COMPONENTS
    from .layout import IncompleteResultsError as IncompleteResultsError
    from .layout import ResultsError as ResultsError
    from .names import DECK_FILE_NAME as DECK_FILE_NAME
    from .reading import FrameArrays as FrameArrays
    from .reading import FrameField as FrameField
    from .reading import Results as Results
    from .reading import read as read
    from .reports import CONTACT_PHASE_NAMES as CONTACT_PHASE_NAMES
    from .reports import PHASE_NAMES as PHASE_NAMES
    from .reports import energy_report as energy_report
    from .reports import write_history_csv as write_history_csv
    from .reports import write_summary as write_summary
    from .vtk_export import write_vtk_series as write_vtk_series

# name -> the module that defines it
_EXPORTS = {
    "CONTACT_PHASE_NAMES": "reports", "DECK_FILE_NAME": "names", "ENERGY_NAMES": "layout", "PHASE_NAMES": "reports",
    "SUPPORTED_RESULTS_VERSIONS": "layout", "TRACKED_COMPONENTS": "layout", "FrameArrays": "reading",
    "FrameField": "reading", "IncompleteResultsError": "layout", "Results": "reading", "ResultsError": "layout",
    "energy_report": "reports", "read": "reading", "write_history_csv": "reports", "write_summary": "reports",
    "write_vtk_series": "vtk_export",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        value = getattr(import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value   # found once
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
