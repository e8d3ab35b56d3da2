"""pyvista grids of a results mesh: quadrilaterals (VTK_QUAD) with one frame's fields on them.

Used by :meth:`paradyn.results.reading.Results.frame` and by the VTK export; the array names, units and
the ``TimeValue`` field are those of docs/outputs.md, "VTK time series". pyvista is imported only
when a grid is built: it is slow to import.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .layout import FrameArrays

VTK_QUAD = 9
MEMBRANE_COMPONENTS = ("sxx", "syy", "sxy")
STRAIN_COMPONENTS = ("exx", "eyy", "exy")
# layer_stress as one 15-component cell array: layer by layer (bottom, middle, top), 5 components each
LAYER_COMPONENTS = tuple(f"{layer}_{c}" for layer in ("bottom", "middle", "top")
                         for c in ("sxx", "syy", "sxy", "sxz", "syz"))
# surface_strain as one 6-component cell array: bottom, then top, 3 strain components each
SURFACE_COMPONENTS = tuple(f"{side}_{c}" for side in ("bottom", "top") for c in STRAIN_COMPONENTS)


@dataclass(frozen=True)
class FileIds:
    """The ids of the mesh file the model came from, one per node, element and part."""

    node: np.ndarray
    element: np.ndarray
    part: np.ndarray


@dataclass
class Topology:
    """A grid of some elements with its own compact node numbering."""

    grid: Any  # pyvista.UnstructuredGrid at the initial positions
    nodes: np.ndarray  # global node index of each local point
    elements: np.ndarray  # global element index of each cell


def topology(
    coordinates: np.ndarray, connectivity: np.ndarray, element_part: np.ndarray, elements: np.ndarray,
    ids: FileIds | None = None,
) -> Topology:
    """The grid of ``elements`` (global indices) at the initial positions, with ``node_id``,
    ``element_id`` and ``part``, and with ``ids`` the file's ``file_node_id``,
    ``file_element_id`` and ``file_part_id``."""
    import pyvista as pv

    conn = connectivity[elements]
    nodes, local = np.unique(conn, return_inverse=True)
    local = local.reshape(-1, 4)
    cells = np.hstack([np.full((local.shape[0], 1), 4, dtype=np.int64), local]).ravel()
    celltypes = np.full(local.shape[0], VTK_QUAD, dtype=np.uint8)
    grid = pv.UnstructuredGrid(cells, celltypes, coordinates[nodes].copy())
    grid.point_data["node_id"] = nodes.astype(np.int64)
    grid.cell_data["element_id"] = elements.astype(np.int64)
    grid.cell_data["part"] = element_part[elements].astype(np.int32)
    if ids is not None:
        grid.point_data["file_node_id"] = ids.node[nodes].astype(np.int64)
        grid.cell_data["file_element_id"] = ids.element[elements].astype(np.int64)
        grid.cell_data["file_part_id"] = ids.part[element_part[elements]].astype(np.int64)
    return Topology(grid=grid, nodes=nodes, elements=elements)


def fill_frame(
    grid: Any, topo: Topology, coordinates: np.ndarray, frame: FrameArrays, deformed: bool
) -> None:
    """Put ``frame``'s fields on ``grid`` (a copy of ``topo.grid`` or the grid itself), the points
    at the deformed position unless ``deformed`` is False."""
    disp = frame.displacement[topo.nodes]
    x0 = coordinates[topo.nodes]
    grid.points = x0 + disp if deformed else x0.copy()
    grid.point_data["displacement"] = disp
    grid.point_data["velocity"] = frame.velocity[topo.nodes]
    grid.cell_data["membrane_stress"] = frame.membrane_stress[topo.elements]
    grid.cell_data["von_mises"] = frame.von_mises[topo.elements]
    grid.cell_data["plastic_strain"] = frame.plastic_strain[topo.elements]
    grid.point_data["acceleration"] = frame.acceleration[topo.nodes]
    grid.point_data["nodal_contact_force"] = frame.nodal_contact_force[topo.nodes]
    grid.cell_data["layer_stress"] = frame.layer_stress[topo.elements].reshape(len(topo.elements), -1)
    grid.cell_data["membrane_strain"] = frame.membrane_strain[topo.elements]
    grid.cell_data["internal_energy_density"] = frame.internal_energy_density[topo.elements]
    grid.cell_data["surface_strain"] = frame.surface_strain[topo.elements].reshape(len(topo.elements), -1)
    grid.cell_data["thickness"] = frame.thickness[topo.elements]
    grid.field_data["TimeValue"] = np.array([frame.time])
    for array_name, names in (("membrane_stress", MEMBRANE_COMPONENTS), ("membrane_strain", STRAIN_COMPONENTS),
                              ("layer_stress", LAYER_COMPONENTS), ("surface_strain", SURFACE_COMPONENTS)):
        array = grid.GetCellData().GetArray(array_name)
        for c, name in enumerate(names):
            array.SetComponentName(c, name)
