"""The whole run in one file that ParaView and VTK read with its time steps: ``results.vtkhdf``.

VTKHDF (the VTK project's HDF5 layout, version 2, "Temporal Data"): one ``UnstructuredGrid`` of
every part's quadrilaterals, whose points (at the deformed position) and fields are appended frame
after frame, while the topology and the ``part``, ``element_id`` and ``node_id`` arrays (and the
mesh file's ``file_*_id``) are written once and shared by every step (their offsets stay 0). The
arrays are those of the ``.vtu`` files (docs/outputs.md, "VTK time series"); the top-level group
``/ParaDyn`` holds the part names.
Written with h5py, a block of frames at a time, through a temporary file renamed at the end.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from paradyn.atomic_write import replacing

from . import grids
from .layout import FRAME_DATASETS, LATER_FRAME_FIELDS, frame_tails, open_results, read_frame_rows
from .reading import Results, ResultsError

if TYPE_CHECKING:
    import h5py
    import pyvista

VTKHDF_VERSION = (2, 1)
_BLOCK_BYTES = 64 * 2**20   # frames copied per read: bounded memory on long runs
# (name, on points?, components) of the fields written every frame, as in the .vtu files (grids.py);
# layer_stress is one 15-component cell array (bottom, middle, top; sxx syy sxy sxz syz each),
# surface_strain one 6-component cell array (bottom, top; exx eyy exy each)
_FRAME_ARRAYS = (("displacement", True, 3), ("velocity", True, 3), ("membrane_stress", False, 3),
                 ("von_mises", False, 1), ("plastic_strain", False, 1), ("acceleration", True, 3),
                 ("nodal_contact_force", True, 3), ("layer_stress", False, 15), ("membrane_strain", False, 3),
                 ("internal_energy_density", False, 1), ("surface_strain", False, 6), ("thickness", False, 1))


def write_vtkhdf(results: Results, path: str | Path) -> Path:
    """Write every frame of ``results`` into one transient VTKHDF file at ``path``; return the path.

    ParaView opens it with its time steps; from Python, ``pyvista.get_reader(path)`` has them too
    (:class:`paradyn.results.vtkhdf_reader.VTKHDFReader`), and :func:`read_step` reads step ``k``.
    """
    import h5py  # where a file is opened (layout.open_results)

    path = Path(path)
    if results.n_frames == 0:
        raise ResultsError(f"{results.path} holds no field frames; there is nothing to write")
    with replacing(path) as temporary, h5py.File(temporary, "w") as h5:
        root = h5.create_group("VTKHDF")
        root.attrs["Version"] = np.array(VTKHDF_VERSION, dtype=np.int64)
        root.attrs.create("Type", np.bytes_("UnstructuredGrid"))
        _write_topology(root, results)
        _write_steps(root, results)
        names = h5.create_group("ParaDyn")
        names.attrs["part_names"] = [name.encode() for name in results.part_names]
        names.attrs["title"] = results.title
    return path


def read_step(path: str | Path, k: int) -> pyvista.UnstructuredGrid:
    """Step ``k`` of a VTKHDF file as a pyvista grid, through VTK's ``vtkHDFReader`` (its field
    data ``Time`` holds the step's time)."""
    import pyvista as pv
    from vtkmodules.vtkIOHDF import vtkHDFReader

    reader = vtkHDFReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    if not 0 <= k < reader.GetNumberOfSteps():
        raise IndexError(f"step {k} does not exist: {path} holds {reader.GetNumberOfSteps()} steps")
    reader.SetStep(k)
    reader.Update()
    return pv.wrap(reader.GetOutput())


def _write_topology(root: h5py.Group, results: Results) -> None:
    """Cells, their static arrays and the per-step sizes (one piece per step)."""
    steps, n_nodes, n_cells = results.n_frames, results.n_nodes, results.n_elements
    root["Connectivity"] = results.connectivity.reshape(-1).astype(np.int64)
    root["Offsets"] = np.arange(0, 4 * n_cells + 1, 4, dtype=np.int64)
    root["Types"] = np.full(n_cells, grids.VTK_QUAD, dtype=np.uint8)
    root["NumberOfPoints"] = np.full(steps, n_nodes, dtype=np.int64)
    root["NumberOfCells"] = np.full(steps, n_cells, dtype=np.int64)
    root["NumberOfConnectivityIds"] = np.full(steps, 4 * n_cells, dtype=np.int64)
    ids = results.ids()
    points = root.create_group("PointData")
    points["node_id"] = np.arange(n_nodes, dtype=np.int64)
    points["file_node_id"] = ids.node.astype(np.int64)
    cells = root.create_group("CellData")
    cells["part"] = results.element_part.astype(np.int32)
    cells["element_id"] = np.arange(n_cells, dtype=np.int64)
    cells["file_element_id"] = ids.element.astype(np.int64)
    cells["file_part_id"] = ids.part[results.element_part].astype(np.int64)


def _arrays_in(h5: h5py.File) -> list[tuple[str, bool, int]]:
    """The frame arrays of ``h5``: every one of ``_FRAME_ARRAYS`` but the later fields a file
    written before them lacks (layout.LATER_FRAME_FIELDS)."""
    return [a for a in _FRAME_ARRAYS if a[0] not in LATER_FRAME_FIELDS or FRAME_DATASETS[a[0]] in h5]


def _write_steps(root: h5py.Group, results: Results) -> None:
    """The deformed points and the fields of every frame, and the ``Steps`` offsets into them."""
    steps, n_nodes, n_cells = results.n_frames, results.n_nodes, results.n_elements
    points = root.create_dataset("Points", (steps * n_nodes, 3), dtype=np.float64)
    with open_results(results.path) as h5:
        arrays = _arrays_in(h5)
    data = {}
    for name, on_points, components in arrays:
        rows = steps * (n_nodes if on_points else n_cells)
        shape = (rows, components) if components > 1 else (rows,)
        data[name] = root["PointData" if on_points else "CellData"].create_dataset(name, shape, dtype=np.float64)
    # whole blocks of frames per read and write: one h5py call per block, not per frame and field
    per_frame = 8 * sum(c * (n_nodes if p else n_cells) for _, p, c in arrays) + 24 * n_nodes
    block = max(1, _BLOCK_BYTES // max(per_frame, 1))
    tails = frame_tails(n_nodes, n_elements=n_cells)
    with open_results(results.path) as h5:
        for first in range(0, steps, block):
            last = min(first + block, steps)
            for name, on_points, components in arrays:
                size = n_nodes if on_points else n_cells
                rows = slice(first * size, last * size)
                values = read_frame_rows(h5, name, first, last, tails[name])
                data[name][rows] = values.reshape((-1, components) if components > 1 else (-1,))
                if name == "displacement":
                    points[rows] = (values + results.coordinates).reshape(-1, 3)
    step = root.create_group("Steps")
    step.attrs["NSteps"] = steps
    step["Values"] = results.time_values.astype(np.float64)
    zeros, k = np.zeros(steps, dtype=np.int64), np.arange(steps, dtype=np.int64)
    step["PartOffsets"] = zeros
    step["NumberOfParts"] = np.ones(steps, dtype=np.int64)
    step["PointOffsets"] = k * n_nodes
    step["CellOffsets"] = zeros
    step["ConnectivityIdOffsets"] = zeros
    point_offsets, cell_offsets = step.create_group("PointDataOffsets"), step.create_group("CellDataOffsets")
    for name in ("node_id", "file_node_id"):
        point_offsets[name] = zeros
    for name in ("part", "element_id", "file_element_id", "file_part_id"):
        cell_offsets[name] = zeros
    for name, on_points, _ in arrays:
        (point_offsets if on_points else cell_offsets)[name] = k * (n_nodes if on_points else n_cells)
