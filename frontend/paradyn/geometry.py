"""Shell meshes for ParaDyn: structured cylinders (gmsh) and flat plates (numpy); mesh files are read by
:mod:`paradyn.mesh_files`.

Every mesh is a :class:`Mesh` of 4-node quadrilaterals with 0-based node indices, counter-clockwise
seen from the side the shell normal points to (the convention of ``docs/formats.md``).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

Vector = Sequence[float]

# Quadrilateral cell types that meshio knows and that ParaDyn cannot use (higher order or other shapes).
_SURFACE_CELL_TYPES_REJECTED = ("triangle", "triangle6", "triangle7", "quad8", "quad9", "polygon")
_VOLUME_CELL_TYPES = ("tetra", "tetra10", "hexahedron", "hexahedron20", "hexahedron27", "wedge",
                      "wedge15", "pyramid", "pyramid13")


class GeometryError(ValueError):
    """A geometry request or a mesh file that ParaDyn cannot turn into a quadrilateral shell mesh."""


@dataclass
class Mesh:
    """Quadrilateral shell mesh.

    coordinates: (n_nodes, 3) float64 node positions in metres.
    quads: (n_elements, 4) int64 node indices, 0-based, counter-clockwise around the normal.
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
# gmsh session handling


@contextlib.contextmanager
def _gmsh_model(name: str) -> Iterator[object]:
    """A fresh gmsh model; initialises gmsh if needed and always cleans up, also after errors."""
    try:
        import gmsh
    except ImportError as exc:  # pragma: no cover - gmsh is a declared dependency
        raise GeometryError("gmsh is not installed; install it with `pip install gmsh`") from exc
    owns_session = not gmsh.isInitialized()
    if owns_session:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        try:
            yield gmsh
        finally:
            if not owns_session:
                gmsh.model.remove()
    finally:
        if owns_session:
            gmsh.finalize()


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
    Normals point outward. Nodes are numbered ring by ring from the ``-axis`` end,
    node ``ring * elements_around + k`` lies at angle ``k * 2 pi / elements_around`` from the
    first in-plane direction (see :func:`cross_section_basis`).
    """
    radius = _positive(radius, "radius")
    length = _positive(length, "length")
    n_around = _count(elements_around, "elements_around", minimum=4)
    n_along = _count(elements_along, "elements_along")
    if n_around % 4 != 0:
        raise GeometryError(
            f"elements_around = {n_around} must be a multiple of 4 (the circle is meshed as four "
            f"quarter arcs); use {4 * max(1, round(n_around / 4))} for example"
        )
    a, e1, e2 = cross_section_basis(axis)
    c = _point(center, "center")
    start = c - 0.5 * length * a

    with _gmsh_model("paradyn_cylinder") as gmsh:
        geo = gmsh.model.geo
        centre_tag = geo.addPoint(*start)
        corner_tags = []
        for k in range(4):
            angle = 0.5 * np.pi * k
            corner_tags.append(geo.addPoint(*(start + radius * (np.cos(angle) * e1 + np.sin(angle) * e2))))
        arcs = [geo.addCircleArc(corner_tags[k], centre_tag, corner_tags[(k + 1) % 4]) for k in range(4)]
        for arc in arcs:
            geo.mesh.setTransfiniteCurve(arc, n_around // 4 + 1)
        extruded = geo.extrude([(1, arc) for arc in arcs], *(length * a),
                               numElements=[n_along], recombine=True)
        geo.synchronize()
        surfaces = [tag for dim, tag in extruded if dim == 2]
        group = gmsh.model.addPhysicalGroup(2, surfaces)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.removeDuplicateNodes()
        node_tags, node_xyz = gmsh.model.mesh.getNodesForPhysicalGroup(2, group)
        quad_tags_flat = np.concatenate(
            [gmsh.model.mesh.getElementsByType(3, tag)[1] for tag in surfaces]
        )
    mesh = _mesh_from_tags(np.asarray(node_tags), np.asarray(node_xyz), np.asarray(quad_tags_flat))
    mesh = _order_cylinder(mesh, start, a, e1, e2, length, n_around, n_along)
    _orient_outward(mesh, start, a)
    expected = (n_around * (n_along + 1), n_around * n_along)
    if (mesh.n_nodes, mesh.n_elements) != expected:  # pragma: no cover - guards a gmsh change
        raise GeometryError(
            f"gmsh produced {mesh.n_nodes} nodes and {mesh.n_elements} quads for the cylinder, "
            f"expected {expected[0]} and {expected[1]}; check the gmsh version"
        )
    return mesh


def _mesh_from_tags(node_tags: np.ndarray, node_xyz: np.ndarray, quad_tags_flat: np.ndarray) -> Mesh:
    """Turn gmsh node tags and element node tags into 0-based arrays."""
    order = np.argsort(node_tags)
    sorted_tags = node_tags[order]
    quad_tags = quad_tags_flat.reshape(-1, 4)
    position = np.searchsorted(sorted_tags, quad_tags)
    position = np.clip(position, 0, len(sorted_tags) - 1)
    if not np.all(sorted_tags[position] == quad_tags):  # pragma: no cover - guards a gmsh change
        raise GeometryError("gmsh returned quads that use nodes outside the meshed surface")
    coordinates = node_xyz.reshape(-1, 3)[order]
    return Mesh(coordinates=coordinates, quads=position)


def _order_cylinder(mesh: Mesh, start: np.ndarray, a: np.ndarray, e1: np.ndarray, e2: np.ndarray,
                    length: float, n_around: int, n_along: int) -> Mesh:
    """Renumber nodes ring by ring and elements in the same order, so results are reproducible."""
    rel = mesh.coordinates - start
    ring = np.rint(rel @ a / (length / n_along)).astype(np.int64)
    angle = np.mod(np.arctan2(rel @ e2, rel @ e1), 2.0 * np.pi)
    k = np.mod(np.rint(angle / (2.0 * np.pi / n_around)).astype(np.int64), n_around)
    new_index = ring * n_around + k
    if sorted(new_index.tolist()) != list(range(n_around * (n_along + 1))):
        raise GeometryError(  # pragma: no cover - guards a gmsh change
            "the cylinder mesh from gmsh is not the expected structured grid; check the gmsh version"
        )
    coordinates = np.empty_like(mesh.coordinates)
    coordinates[new_index] = mesh.coordinates
    quads = new_index[mesh.quads]
    # element order: by the lowest ring, then by the angle of the element's first corner in the ring
    element_ring = quads.min(axis=1) // n_around
    centre_angle = np.mod(np.arctan2((coordinates[quads].mean(axis=1) - start) @ e2,
                                     (coordinates[quads].mean(axis=1) - start) @ e1), 2.0 * np.pi)
    quads = quads[np.lexsort((centre_angle, element_ring))]
    return Mesh(coordinates=coordinates, quads=quads)


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
                f"{path}: the file has {n} {cell_type} cells; ParaDyn needs 4-node quadrilaterals "
                f"only (in gmsh: Mesh.RecombineAll = 1, Mesh.ElementOrder = 1, a surface mesh)"
            )


def check_quads(path: Path, mesh: Mesh) -> None:
    if not np.all(np.isfinite(mesh.coordinates)):
        raise GeometryError(f"{path}: the file has non-finite node coordinates")
    q = np.sort(mesh.quads, axis=1)
    repeated = np.flatnonzero(np.any(q[:, 1:] == q[:, :-1], axis=1))
    if repeated.size:
        raise GeometryError(f"{path}: quad {repeated[0]} (0-based, {repeated.size} in all) repeats a "
                            f"node; collapsed quads are not allowed, remesh without degenerate cells")


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
