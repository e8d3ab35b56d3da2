"""Shell meshes for ParaDyn: structured cylinders and flat plates, by formula (numpy); mesh files
are read by :mod:`paradyn.mesh.files` (gmsh or meshio).

Every mesh is a :class:`Mesh` of 4-node quadrilaterals with 0-based node indices, counter-clockwise
seen from the side the shell normal points to (the convention of ``docs/formats.md``); a triangle is
a row whose third node is repeated as the fourth (a degenerate quadrilateral, as LS-DYNA stores it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

Vector = Sequence[float]

# Surface cell types that meshio knows and that ParaDyn cannot use (higher order or other shapes).
_SURFACE_CELL_TYPES_REJECTED = ("triangle6", "triangle7", "quad8", "quad9", "polygon")
_VOLUME_CELL_TYPES = ("tetra", "tetra10", "hexahedron", "hexahedron20", "hexahedron27", "wedge",
                      "wedge15", "pyramid", "pyramid13")


class GeometryError(ValueError):
    """A geometry request or a mesh file that ParaDyn cannot turn into a shell mesh."""


@dataclass
class Mesh:
    """Shell mesh of quadrilaterals and triangles.

    coordinates: (n_nodes, 3) float64 node positions in metres.
    quads: (n_elements, 4) int64 node indices, 0-based, counter-clockwise around the normal; a
    triangle repeats its third node as the fourth.
    """

    coordinates: np.ndarray
    quads: np.ndarray
    node_ids: np.ndarray | None = None      # the mesh file's node ids (gmsh tags), when it has them
    element_ids: np.ndarray | None = None   # the mesh file's element ids
    part_id: int | None = None              # the physical group's tag the quads came from

    def __post_init__(self) -> None:
        self.coordinates = np.ascontiguousarray(self.coordinates, dtype=np.float64)
        self.quads = np.ascontiguousarray(self.quads, dtype=np.int64)
        if self.coordinates.ndim != 2 or self.coordinates.shape[1] != 3:
            raise GeometryError(f"Mesh.coordinates must have shape (n, 3), got {self.coordinates.shape}")
        if self.quads.ndim != 2 or self.quads.shape[1] != 4:
            raise GeometryError(f"Mesh.quads must have shape (n, 4), got {self.quads.shape}")

    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.quads.shape[0])

    @property
    def triangles(self) -> np.ndarray:
        """Whether each element is a triangle (its third node repeated as the fourth), (n_elements,) bool."""
        return self.quads[:, 2] == self.quads[:, 3]

    def normals(self) -> np.ndarray:
        """Unit normal of every quad (cross product of the diagonals), shape (n_elements, 3)."""
        return quad_normals(self.coordinates, self.quads)

    def edge_lengths(self) -> np.ndarray:
        """Length of the four edges of every quad, shape (n_elements, 4)."""
        corners = self.coordinates[self.quads]
        return np.linalg.norm(np.roll(corners, -1, axis=1) - corners, axis=2)


# ----------------------------------------------------------------------------------------------
# small vector helpers


def _unit(vector: Vector, name: str) -> np.ndarray:
    v = np.asarray(vector, dtype=np.float64)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise GeometryError(f"{name} must be three finite numbers [x, y, z], got {vector!r}")
    norm = float(np.linalg.norm(v))
    if norm == 0.0:
        raise GeometryError(f"{name} must not be the zero vector; give a direction such as [1, 0, 0]")
    return v / norm


def _point(point: Vector, name: str) -> np.ndarray:
    p = np.asarray(point, dtype=np.float64)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise GeometryError(f"{name} must be three finite numbers [x, y, z], got {point!r}")
    return p


def _positive(value: float, name: str) -> float:
    if not np.isfinite(value) or value <= 0.0:
        raise GeometryError(f"{name} must be a positive length in metres, got {value!r}")
    return float(value)


def _count(value: int, name: str, minimum: int = 1) -> int:
    if isinstance(value, bool) or int(value) != value or value < minimum:
        raise GeometryError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def cross_section_basis(axis: Vector) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Right-handed orthonormal frame (a, e1, e2) with a along ``axis``.

    e1 is the global z direction projected onto the cross-section (global x when the axis is along z),
    so a horizontal cylinder has nodes on its top and bottom lines.
    """
    a = _unit(axis, "axis")
    helper = np.array([0.0, 0.0, 1.0]) if abs(a[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = helper - np.dot(helper, a) * a
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    return a, e1, e2


def quad_normals(coordinates: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Unit normals of quads from the cross product of their diagonals."""
    c = coordinates[quads]
    n = np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0.0, length, 1.0)


# ----------------------------------------------------------------------------------------------
# cylinder


def cylinder(
    radius: float,
    length: float,
    axis: Vector = (1.0, 0.0, 0.0),
    center: Vector = (0.0, 0.0, 0.0),
    elements_around: int = 16,
    elements_along: int = 32,
) -> Mesh:
    """Structured quadrilateral mesh of the lateral surface of a cylinder (open ends).

    The cylinder is centred at ``center`` and spans ``length / 2`` each way along ``axis``.
    Normals point outward. Nodes are numbered ring by ring from the ``-axis`` end: node
    ``ring * elements_around + k`` lies at angle ``k * 2 pi / elements_around`` from the first
    in-plane direction (see :func:`cross_section_basis`), exactly on the circle; element
    ``ring * elements_around + k`` has the corners ``k`` and ``k + 1`` of rings ``ring`` and
    ``ring + 1``. ``elements_around`` is a multiple of 4, so that nodes lie on the four lines at
    0, 90, 180 and 270 degrees (a horizontal cylinder's top, bottom and sides).

    Examples
    --------
    >>> mesh = cylinder(0.08, 2.0, elements_around=16, elements_along=32)
    >>> mesh.n_nodes, mesh.n_elements
    (528, 512)
    """
    radius = _positive(radius, "radius")
    length = _positive(length, "length")
    n_around = _count(elements_around, "elements_around", minimum=4)
    n_along = _count(elements_along, "elements_along")
    if n_around % 4 != 0:
        raise GeometryError(
            f"elements_around = {n_around} must be a multiple of 4 (nodes on the top, bottom and "
            f"sides of the circle); use {4 * max(1, round(n_around / 4))} for example"
        )
    a, e1, e2 = cross_section_basis(axis)
    start = _point(center, "center") - 0.5 * length * a
    angle = np.arange(n_around) * (2.0 * np.pi / n_around)
    ring = radius * (np.outer(np.cos(angle), e1) + np.outer(np.sin(angle), e2))
    along = np.arange(n_along + 1) * (length / n_along)
    coordinates = (start + along[:, None, None] * a + ring[None, :, :]).reshape(-1, 3)
    k, layer = np.meshgrid(np.arange(n_around), np.arange(n_along))
    first = (layer * n_around + k).ravel()
    second = (layer * n_around + (k + 1) % n_around).ravel()
    quads = np.stack([first, second, second + n_around, first + n_around], axis=1)
    mesh = Mesh(coordinates=coordinates, quads=quads)
    _orient_outward(mesh, start, a)
    return mesh


def _orient_outward(mesh: Mesh, start: np.ndarray, a: np.ndarray) -> None:
    """Reverse quads whose normal points towards the axis."""
    centroid = mesh.coordinates[mesh.quads].mean(axis=1) - start
    radial = centroid - np.outer(centroid @ a, a)
    inward = np.einsum("ij,ij->i", mesh.normals(), radial) < 0.0
    mesh.quads[inward] = mesh.quads[inward][:, ::-1]


# ----------------------------------------------------------------------------------------------
# plate


def plate(
    size: tuple[float, float] = (1.0, 1.0),
    elements: tuple[int, int] = (10, 10),
    origin: Vector = (0.0, 0.0, 0.0),
    u_axis: Vector = (1.0, 0.0, 0.0),
    v_axis: Vector = (0.0, 1.0, 0.0),
) -> Mesh:
    """Flat rectangle ``origin + s * lx * u + r * ly * v`` for s, r in [0, 1], normal ``u x v``.

    ``u_axis`` and ``v_axis`` are normalised and must be perpendicular. Node ``j * (nx + 1) + i``
    sits at s = i / nx, r = j / ny; element ``j * nx + i`` has corners (i, j), (i+1, j), (i+1, j+1), (i, j+1).
    """
    if len(size) != 2 or len(elements) != 2:
        raise GeometryError(f"plate size and elements take two values each, got size={size!r}, "
                            f"elements={elements!r}")
    lx, ly = _positive(size[0], "plate size[0]"), _positive(size[1], "plate size[1]")
    nx, ny = _count(elements[0], "plate elements[0]"), _count(elements[1], "plate elements[1]")
    u, v = _unit(u_axis, "u_axis"), _unit(v_axis, "v_axis")
    if abs(float(np.dot(u, v))) > 1e-9:
        raise GeometryError(f"u_axis {list(u_axis)} and v_axis {list(v_axis)} must be perpendicular")
    o = _point(origin, "origin")
    s, r = np.meshgrid(np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 1.0, ny + 1))
    coordinates = o + np.outer(s.ravel() * lx, u) + np.outer(r.ravel() * ly, v)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    first = (j * (nx + 1) + i).ravel()
    quads = np.stack([first, first + 1, first + nx + 2, first + nx + 1], axis=1)
    return Mesh(coordinates=coordinates, quads=quads)


# ----------------------------------------------------------------------------------------------
# mesh files


def reject_other_cells(path: Path, counts: dict[str, int]) -> None:
    for cell_type in _SURFACE_CELL_TYPES_REJECTED + _VOLUME_CELL_TYPES:
        n = counts.get(cell_type, 0)
        if n:
            raise GeometryError(
                f"{path}: the file has {n} {cell_type} cells; ParaDyn needs 4-node quadrilaterals and "
                f"3-node triangles only (in gmsh: Mesh.ElementOrder = 1, a surface mesh)"
            )


def triangles_as_quads(triangles: np.ndarray) -> np.ndarray:
    """(n, 3) triangles -> (n, 4) rows with the third node repeated as the fourth (int64)."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    return np.concatenate([t, t[:, 2:3]], axis=1)


def shape_order(quads: np.ndarray, part: np.ndarray | None = None) -> np.ndarray:
    """The element order that puts the triangles of each run of consecutive elements of one part after
    its quadrilaterals, each shape in its own order (a stable sort): the engine groups elements of one
    part and one shape in the deck's order, so scattered triangles would cut its groups short. The
    identity for a mesh without triangles."""
    q = np.asarray(quads)
    runs = np.zeros(len(q), dtype=np.int64)
    if part is not None and len(q):
        runs[1:] = np.cumsum(np.asarray(part)[1:] != np.asarray(part)[:-1])
    return np.lexsort((q[:, 2] == q[:, 3], runs))


def shapes_in_runs(mesh: Mesh) -> Mesh:
    """``mesh`` with its triangles after its quadrilaterals (:func:`shape_order`), ids kept with them."""
    order = shape_order(mesh.quads)
    if np.array_equal(order, np.arange(mesh.n_elements)):
        return mesh
    return Mesh(mesh.coordinates, mesh.quads[order], node_ids=mesh.node_ids,
                element_ids=None if mesh.element_ids is None else mesh.element_ids[order], part_id=mesh.part_id)


def repeated_node_rows(quads: np.ndarray) -> np.ndarray:
    """Rows that name a node twice, other than a triangle's third node as its fourth."""
    q = np.asarray(quads)
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3)]
    return np.flatnonzero(np.any([q[:, a] == q[:, b] for a, b in pairs], axis=0))


def check_quads(path: Path, mesh: Mesh) -> None:
    if not np.all(np.isfinite(mesh.coordinates)):
        raise GeometryError(f"{path}: the file has non-finite node coordinates")
    repeated = repeated_node_rows(mesh.quads)
    if repeated.size:
        raise GeometryError(f"{path}: element {repeated[0]} (0-based, {repeated.size} in all) repeats a "
                            f"node; collapsed cells are not allowed, remesh without degenerate cells")


# ----------------------------------------------------------------------------------------------
# node selection


def nodes_in_box(coords: np.ndarray, lo: Vector, hi: Vector, tol: float = 0.0) -> np.ndarray:
    """Indices (int64, ascending) of the nodes with lo - tol <= x <= hi + tol in every coordinate."""
    lo_v, hi_v = _point(lo, "box lower corner"), _point(hi, "box upper corner")
    if np.any(lo_v > hi_v):
        raise GeometryError(f"box lower corner {list(lo)} must not exceed the upper corner {list(hi)} "
                            f"in any coordinate; write the box as [[xmin, ymin, zmin], [xmax, ymax, zmax]]")
    coords = np.asarray(coords, dtype=np.float64)
    inside = np.all((coords >= lo_v - tol) & (coords <= hi_v + tol), axis=1)
    return np.flatnonzero(inside).astype(np.int64)


def nearest_node(coords: np.ndarray, point: Vector) -> int:
    """Index of the node closest to ``point`` (the lowest index on ties)."""
    coords = np.asarray(coords, dtype=np.float64)
    if coords.shape[0] == 0:
        raise GeometryError("nearest_node needs at least one node")
    p = _point(point, "point")
    return int(np.argmin(np.einsum("ij,ij->i", coords - p, coords - p)))
