"""Read ParaDyn results files and turn them into files other tools read: one import for all of it.

The work is split by job, and each job has its module:

* :mod:`paradyn.reading`: :func:`read` and the :class:`Results` object (frames read on demand);
* :mod:`paradyn.vtk_export`: the ParaView/pyvista time series per part (``<part>.pvd`` +
  ``vtk/<part>_<k:05d>.vtu``);
* :mod:`paradyn.reports`: the history as CSV, the energy report and ``summary.json``;
* :mod:`paradyn.atomic_write`: the write-to-temporary-then-rename every writer uses.

docs/outputs.md describes every output file, its columns, keys and units.
"""

from __future__ import annotations

from .reading import FrameArrays, FrameField, Results, read
from .reports import CONTACT_PHASE_NAMES, PHASE_NAMES, energy_report, write_history_csv, write_summary
from .results_file import (
    ENERGY_NAMES,
    SUPPORTED_RESULTS_VERSIONS,
    TRACKED_COMPONENTS,
    IncompleteResultsError,
    ResultsError,
)
from .run_names import DECK_FILE_NAME
from .vtk_export import write_vtk_series

__all__ = [
    "CONTACT_PHASE_NAMES",
    "DECK_FILE_NAME",
    "ENERGY_NAMES",
    "PHASE_NAMES",
    "SUPPORTED_RESULTS_VERSIONS",
    "TRACKED_COMPONENTS",
    "FrameArrays",
    "FrameField",
    "IncompleteResultsError",
    "Results",
    "ResultsError",
    "energy_report",
    "read",
    "write_history_csv",
    "write_summary",
    "write_vtk_series",
]
