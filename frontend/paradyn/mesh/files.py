"""Shell meshes (quadrilaterals and triangles) read from files, with their groups and ids (docs/scene.md,
``kind = "file"``). A triangle becomes a row whose third node is repeated as the fourth.

A gmsh ``.msh`` file is read with gmsh itself, which keeps the file's node and element tags and
the names of its physical groups; every other format (and a ``.msh`` file gmsh cannot open) with
meshio, which keeps named cell sets (gmsh physical groups, Abaqus ELSETs) but not the file's ids.
``group`` selects the cells of one physical group or cell set, so that a file's groups
become the scene's parts.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from .geometry import GeometryError, Mesh, check_quads, reject_other_cells, triangles_as_quads

# gmsh element type codes of the cells ParaDyn cannot use, by meshio's names (for the messages)
_GMSH_REJECTED = {9: "triangle6", 10: "quad9", 16: "quad8", 21: "triangle10"}
_GMSH_QUAD = 3
_GMSH_TRIANGLE = 2


@contextlib.contextmanager
def _gmsh_model(name: str) -> Iterator[object]:
    """A fresh gmsh model; initialises gmsh if needed and always cleans up, also after errors.
    gmsh is imported here, when a file is read: loading it costs about 12 ms."""
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


def read_gmsh(path: Path, group: str | None) -> Mesh:
    """The quadrilaterals and triangles of a gmsh file (of one physical group), with the file's tags as
    ids, in the file's order (each surface's elements by type, as gmsh stores them)."""
    with _gmsh_model("paradyn_file") as gmsh:
        try:
            gmsh.merge(str(path))
        except Exception as exc:  # gmsh raises a bare Exception naming the parse problem
            raise GeometryError(f"{path}: gmsh cannot read this file ({exc})") from exc
        model = gmsh.model
        if len(model.mesh.getElements(3)[0]):
            raise GeometryError(f"{path}: the file has volume cells; ParaDyn needs a surface mesh of 4-node "
                                f"quadrilaterals and 3-node triangles")
        entities, part_id = _entities(gmsh, path, group)
        node_tags, xyz, _ = model.mesh.getNodes()
        quads, element_tags = [], []
        for entity in entities:
            types, tags, nodes = model.mesh.getElements(2, entity)
            for kind, element, corner in zip(types, tags, nodes, strict=True):
                if kind in _GMSH_REJECTED:
                    reject_other_cells(path, {_GMSH_REJECTED[int(kind)]: len(element)})
                if kind == _GMSH_QUAD:
                    quads.append(np.asarray(corner, dtype=np.int64).reshape(-1, 4))
                    element_tags.append(np.asarray(element, dtype=np.int64))
                elif kind == _GMSH_TRIANGLE:
                    quads.append(triangles_as_quads(corner))
                    element_tags.append(np.asarray(element, dtype=np.int64))
    if not quads:
        raise GeometryError(f"{path}: no quadrilateral or triangle cells{f' in group {group!r}' if group else ''}; "
                            f"ParaDyn needs a surface mesh of 4-node quadrilaterals and 3-node triangles")
    tags = np.asarray(node_tags, dtype=np.int64)
    order = np.argsort(tags)
    corner_tags = np.concatenate(quads)
    used, inverse = np.unique(corner_tags, return_inverse=True)
    rows = order[np.searchsorted(tags[order], used)]
    mesh = Mesh(coordinates=np.asarray(xyz, dtype=np.float64).reshape(-1, 3)[rows], quads=inverse.reshape(-1, 4),
                node_ids=used, element_ids=np.concatenate(element_tags), part_id=part_id)
    check_quads(path, mesh)
    return mesh


def _entities(gmsh: object, path: Path, group: str | None) -> tuple[list[int], int | None]:
    """The surface entities to read: those of the physical group named ``group`` (and its tag), or all."""
    model = gmsh.model
    if group is None:
        return [tag for _, tag in model.getEntities(2)], None
    groups = {model.getPhysicalName(2, tag): tag for _, tag in model.getPhysicalGroups(2)}
    if group not in groups:
        raise GeometryError(f"{path}: no surface physical group named {group!r}; the file has "
                            f"{sorted(groups) or 'none'}")
    return [int(e) for e in model.getEntitiesForPhysicalGroup(2, groups[group])], groups[group]


def read_meshio(path: Path, group: str | None) -> Mesh:
    """The quadrilaterals and triangles of any file meshio reads (of one cell set); no file ids."""
    import meshio

    try:
        data = meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types, and exits on some unreadable files
        raise GeometryError(f"{path}: meshio cannot read this file ({exc}); export the mesh as "
                            f"gmsh .msh or VTK .vtu") from exc
    counts: dict[str, int] = {}
    blocks = []
    for index, block in enumerate(data.cells):
        rows = _rows_in_set(path, data, index, group)
        counts[block.type] = counts.get(block.type, 0) + len(rows)
        if block.type == "quad":
            blocks.append(np.asarray(block.data, dtype=np.int64)[rows])
        elif block.type == "triangle":
            blocks.append(triangles_as_quads(np.asarray(block.data, dtype=np.int64)[rows]))
    reject_other_cells(path, counts)
    if not blocks or sum(len(b) for b in blocks) == 0:
        found = ", ".join(f"{n} {t}" for t, n in counts.items()) or "no cells"
        raise GeometryError(f"{path}: the file has no quadrilateral or triangle cells ({found}); ParaDyn needs "
                            f"a surface mesh of 4-node quadrilaterals and 3-node triangles")
    quads = np.concatenate(blocks)
    points = np.asarray(data.points, dtype=np.float64)
    if points.shape[1] == 2:
        points = np.hstack([points, np.zeros((len(points), 1))])
    used, inverse = np.unique(quads, return_inverse=True)
    mesh = Mesh(coordinates=points[used], quads=inverse.reshape(-1, 4))
    check_quads(path, mesh)
    return mesh


def _rows_in_set(path: Path, data: object, block: int, group: str | None) -> np.ndarray:
    """The cells of block ``block`` in the cell set ``group`` (all of them without a group)."""
    size = len(data.cells[block].data)
    if group is None:
        return np.arange(size)
    sets = {name: rows for name, rows in data.cell_sets.items() if not name.startswith("gmsh:")}
    if group not in sets:
        raise GeometryError(f"{path}: no cell set named {group!r}; the file has {sorted(sets) or 'none'}")
    rows = sets[group][block]
    return np.asarray(rows if rows is not None else [], dtype=np.int64)


def load_mesh(path: str | Path, group: str | None = None) -> Mesh:
    """Read the quadrilaterals of a mesh file (``.msh`` with gmsh, any other format with meshio).

    Line and vertex cells are ignored; unused nodes are dropped and the rest renumbered from 0.
    A ``.msh`` file's node and element tags become the mesh's ``node_ids`` and ``element_ids`` and
    the group's physical tag its ``part_id``.
    """
    path = Path(path)
    if not path.is_file():
        raise GeometryError(f"{path}: mesh file not found; check the path (relative paths in a "
                            f"scene are relative to the scene file)")
    if path.suffix.lower() == ".msh":
        try:
            return read_gmsh(path, group)
        except GeometryError as exc:
            if "gmsh cannot read this file" not in str(exc):
                raise
    return read_meshio(path, group)
