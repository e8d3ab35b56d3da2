"""The mesh of an LS-DYNA keyword deck and its node-level data (docs/keyword.md).

:func:`mesh_of` turns ``*NODE`` and ``*ELEMENT_SHELL`` records into 0-based arrays in SI, keeping
the deck's node, element and part ids beside them (:class:`KeywordMesh`); nodes used by no shell
are left out (with a warning). :func:`fixed_dofs` and :func:`initial_velocities` apply
``*NODE`` TC/RC, ``*BOUNDARY_SPC_*`` and ``*INITIAL_VELOCITY_*`` to its nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from paradyn import deck
from paradyn.mesh import geometry

from .cards import KeywordData, Record
from .reader import KeywordError
from .units import Units

# *NODE TC and RC: the constrained directions of each code
CONSTRAINT_CODES = {0: (), 1: (0,), 2: (1,), 3: (2,), 4: (0, 1), 5: (1, 2), 6: (2, 0), 7: (0, 1, 2)}


@dataclass(frozen=True)
class PartMeshGeometry:
    """The geometry of a part read from a keyword deck: its elements of the deck's mesh."""

    mesh_data: geometry.Mesh
    part_id: int

    def mesh(self) -> geometry.Mesh:
        return self.mesh_data


@dataclass
class KeywordMesh:
    """The deck's shells as 0-based arrays (SI), with the deck's ids of every row."""

    coordinates: np.ndarray            # (n_nodes, 3) m
    connectivity: np.ndarray           # (n_elements, 4) 0-based
    element_part: np.ndarray           # (n_elements,) 0-based part index
    node_ids: np.ndarray               # (n_nodes,) the deck's NID
    element_ids: np.ndarray            # (n_elements,) the deck's EID
    part_ids: np.ndarray               # (n_parts,) the deck's PID, in order of first appearance
    node_index: dict[int, int] = field(default_factory=dict)   # NID -> row
    added_mass: np.ndarray | None = None                       # (n_nodes,) kg: rigid solids' mass
    face_thickness: dict[int, float] = field(default_factory=dict)   # PID -> m, of a rigid solid's faces
    # per engine part (keyword/parts.py): thickness in the deck's units, name suffix ('' or _t<thickness>)
    part_thickness: list[float] = field(default_factory=list)
    part_suffix: list[str] = field(default_factory=list)

    def part_geometry(self, part: int) -> PartMeshGeometry:
        """The elements of engine part ``part`` (0-based; a PID split by thickness has several)."""
        quads = self.connectivity[self.element_part == part]
        used, inverse = np.unique(quads, return_inverse=True)
        return PartMeshGeometry(geometry.Mesh(self.coordinates[used], inverse.reshape(-1, 4)), int(self.part_ids[part]))

    def store_ids(self, model: deck.Model) -> None:
        """Give the model the deck's ids (written to the deck and to the outputs)."""
        model.node_ids = self.node_ids.astype(np.int64)
        model.element_ids = self.element_ids.astype(np.int64)
        model.part_ids = self.part_ids.astype(np.int64)


def mesh_of(data: KeywordData, unit: Units) -> KeywordMesh:
    """The shells of the deck; an element that names an unknown node, or repeats one, is an error."""
    if not data.elements and not data.beams:
        raise KeywordError("the deck has no *ELEMENT_SHELL (nor *ELEMENT_BEAM); ParaDyn needs a shell mesh")
    node_row: dict[int, int] = {}
    for row, record in enumerate(data.nodes):
        nid = int(record["NID"])
        if nid in node_row:
            raise KeywordError(f"{record.where}: *NODE {nid} is defined twice (first at "
                               f"{data.nodes[node_row[nid]].where}); give every node its own id")
        node_row[nid] = row
    part_order = _part_order(data)
    quads, parts, seen = [], [], {}
    for record in data.elements:
        quads.append(_element_rows(record, node_row))
        eid = int(record["EID"])
        if eid in seen:
            raise KeywordError(f"{record.where}: *ELEMENT_SHELL {eid} is defined twice (first at {seen[eid]})")
        seen[eid] = record.where
        parts.append(part_order[int(record["PID"])])
    largest = max(max(node_row), max(seen, default=0), max(part_order))
    if largest > np.iinfo(np.int32).max:
        raise KeywordError(f"id {largest} is larger than the deck format's ids ({np.iinfo(np.int32).max}); "
                           f"renumber the deck")
    # the triangles of each run of one part's elements after its quads (geometry.shape_order), ids with them
    order = geometry.shape_order(np.array(quads, dtype=np.int64), np.array(parts)) if quads else np.zeros(0, int)
    quads, parts = [quads[i] for i in order], [parts[i] for i in order]
    beam_ids = _beam_rows(data, node_row, part_order, quads, parts)   # trusses after the shells, by part
    used, inverse = np.unique(np.array(quads, dtype=np.int64), return_inverse=True)
    unused = len(data.nodes) - used.size
    if unused:
        data.warn(f"{unused} node(s) of *NODE belong to no shell or beam element and are left out")
    xyz = np.array([[float(data.nodes[r][c]) for c in "XYZ"] for r in used.tolist()]) * unit.length
    node_ids = np.array([int(data.nodes[r]["NID"]) for r in used.tolist()], dtype=np.int64)
    return KeywordMesh(coordinates=xyz, connectivity=inverse.reshape(-1, 4).astype(np.int32),
                       element_part=np.array(parts, dtype=np.int32),
                       node_ids=node_ids, element_ids=np.concatenate([np.array(list(seen), dtype=np.int64)[order],
                                                                      np.array(beam_ids, dtype=np.int64)]),
                       part_ids=np.array(list(part_order), dtype=np.int64),
                       node_index={int(n): i for i, n in enumerate(node_ids.tolist())})


def _part_order(data: KeywordData) -> dict[int, int]:
    """PID -> part index, parts in order of their first element, the beams' parts after the shells'
    (parts without elements left out)."""
    defined = {int(p["PID"]): p for p in data.parts}
    order: dict[int, int] = {}
    for keyword, records in (("*ELEMENT_SHELL", data.elements), ("*ELEMENT_BEAM", data.beams)):
        for record in records:
            pid = int(record["PID"] or 0)
            if pid not in defined:
                raise KeywordError(f"{record.where}: {keyword} {record['EID']} names part {pid}, which no "
                                   f"*PART defines")
            order.setdefault(pid, len(order))
    shells = {int(record["PID"] or 0) for record in data.elements}
    both = sorted(shells & {int(record["PID"]) for record in data.beams})
    if both:
        raise KeywordError(f"{defined[both[0]].where}: *PART {both[0]} has both *ELEMENT_SHELL and *ELEMENT_BEAM "
                           f"elements; give the beams a part of their own")
    for pid, part in defined.items():
        if pid not in order:
            data.warn(f"{part.where}: *PART {pid} has no shell or beam elements and is left out")
    return order


def _beam_rows(data: KeywordData, node_row: dict[int, int], part_order: dict[int, int], quads: list[list[int]],
               parts: list[int]) -> list[int]:
    """Append the beams as trusses N1 N2 N2 N2 (the orientation node N3 is not needed) to ``quads``
    and ``parts``, grouped by part in the order of their first beam; their EIDs in that order."""
    seen: dict[int, str] = {}
    ordered = sorted(data.beams, key=lambda record: part_order[int(record["PID"])])   # stable: deck order kept
    for record in ordered:
        eid = int(record["EID"])
        if eid in seen:
            raise KeywordError(f"{record.where}: *ELEMENT_BEAM {eid} is defined twice (first at {seen[eid]})")
        seen[eid] = record.where
        ends = []
        for name in ("N1", "N2"):
            nid = int(record[name])
            if nid not in node_row:
                raise KeywordError(f"{record.where}: *ELEMENT_BEAM {eid} names node {nid}, which no *NODE defines")
            ends.append(node_row[nid])
        quads.append([ends[0], ends[1], ends[1], ends[1]])
        parts.append(part_order[int(record["PID"])])
    return list(seen)


def _element_rows(record: Record, node_row: dict[int, int]) -> list[int]:
    nids = [int(record[f"N{k}"] or 0) for k in range(1, 5)]
    if nids[3] == 0:   # a triangle: N4 = N3, or N4 left blank
        nids[3] = nids[2]
    for nid in nids:
        if nid not in node_row:
            raise KeywordError(f"{record.where}: *ELEMENT_SHELL {record['EID']} names node {nid}, which no "
                               f"*NODE defines")
    return [node_row[nid] for nid in nids]


def nodes_of_parts(mesh: KeywordMesh, pids: list[int]) -> np.ndarray:
    """Rows of the nodes of the elements of the parts ``pids`` (ids of parts without elements are skipped)."""
    parts = np.flatnonzero(np.isin(mesh.part_ids, pids))     # every engine part of each PID
    return np.unique(mesh.connectivity[np.isin(mesh.element_part, parts)])


def _node_rows(data: KeywordData, mesh: KeywordMesh, nids: list[int]) -> np.ndarray:
    """Rows of the nodes ``nids``; ids of nodes used by no shell are skipped."""
    return np.array([mesh.node_index[n] for n in nids if n in mesh.node_index], dtype=np.int64)


def _node_set(data: KeywordData, sid: int, where: str) -> list[int]:
    if sid not in data.node_sets:
        raise KeywordError(f"{where}: node set {sid} is not defined; define it with *SET_NODE_LIST")
    return data.node_sets[sid]


def _part_set(data: KeywordData, sid: int, where: str) -> list[int]:
    if sid not in data.part_sets:
        raise KeywordError(f"{where}: part set {sid} is not defined; define it with *SET_PART_LIST")
    return data.part_sets[sid]


def fixed_dofs(data: KeywordData, mesh: KeywordMesh) -> np.ndarray:
    """The fixed dofs (n_nodes, 6) of *NODE TC/RC and *BOUNDARY_SPC_NODE / _SET."""
    fixed = np.zeros((len(mesh.coordinates), 6), dtype=np.int32)
    for record in data.nodes:
        if not (record["TC"] or record["RC"]):
            continue
        row = mesh.node_index.get(int(record["NID"]))
        for column, offset in (("TC", 0), ("RC", 3)):
            code = int(record[column] or 0)
            if code not in CONSTRAINT_CODES:
                raise KeywordError(f"{record.where}: *NODE {column} = {code}; use 0 to 7")
            if row is not None:
                fixed[row, [offset + d for d in CONSTRAINT_CODES[code]]] = 1
    names = ("DOFX", "DOFY", "DOFZ", "DOFRX", "DOFRY", "DOFRZ")
    for target, record in data.spcs:
        if int(record["CID"] or 0) != 0:
            raise KeywordError(f"{record.where}: *BOUNDARY_SPC_{target} CID = {record['CID']}: local coordinate "
                               f"systems are not read; give the constraints in global axes (CID 0)")
        ident = int(record["ID"])
        nids = [ident] if target == "NODE" else _node_set(data, ident, record.where)
        rows = _node_rows(data, mesh, nids)
        for column, name in enumerate(names):
            if int(record[name] or 0) not in (0, 1):
                raise KeywordError(f"{record.where}: *BOUNDARY_SPC_{target} {name} = {record[name]}; use 0 or 1")
            if int(record[name] or 0) == 1:
                fixed[rows, column] = 1
    return fixed


def initial_velocities(data: KeywordData, mesh: KeywordMesh, unit: Units,
                       start: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Velocities and angular velocities (SI) of *INITIAL_VELOCITY_GENERATION, then *INITIAL_VELOCITY_NODE,
    over ``start`` (those of *INITIAL_VELOCITY, keyword/loads.py) where given."""
    n = len(mesh.coordinates)
    velocity, angular = (np.zeros((n, 3)), np.zeros((n, 3))) if start is None else start
    for first, second in data.velocity_generation:
        rows = _generation_rows(data, mesh, first)
        v = np.array([float(first[k]) for k in ("VX", "VY", "VZ")]) * unit.velocity
        omega = float(first["OMEGA"]) / unit.time
        velocity[rows] = v
        angular[rows] = 0.0
        if omega != 0.0:
            axis = np.array([float(second[k]) for k in ("NX", "NY", "NZ")])
            if not np.linalg.norm(axis) > 0.0:
                raise KeywordError(f"{second.where}: *INITIAL_VELOCITY_GENERATION OMEGA is not 0 but the axis "
                                   f"NX NY NZ is zero; give the axis of rotation")
            axis = axis / np.linalg.norm(axis)
            centre = np.array([float(second[k]) for k in ("XC", "YC", "ZC")]) * unit.length
            velocity[rows] += omega * np.cross(axis, mesh.coordinates[rows] - centre)
            angular[rows] = omega * axis
    for record in data.node_velocities:
        row = mesh.node_index.get(int(record["NID"]))
        if row is not None:
            velocity[row] = [float(record[k]) * unit.velocity for k in ("VX", "VY", "VZ")]
            angular[row] = [float(record[k]) / unit.time for k in ("VXR", "VYR", "VZR")]
    return velocity, angular


def _generation_rows(data: KeywordData, mesh: KeywordMesh, first: Record) -> np.ndarray:
    ident, styp = int(first["ID"]), int(first["STYP"])
    if ident == 0:
        return np.arange(len(mesh.coordinates))
    if styp == 1:
        return nodes_of_parts(mesh, _part_set(data, ident, first.where))
    if styp == 2:
        if ident not in mesh.part_ids:
            raise KeywordError(f"{first.where}: *INITIAL_VELOCITY_GENERATION names part {ident}, which has no "
                               f"shell elements")
        return nodes_of_parts(mesh, [ident])
    if styp == 3:
        return _node_rows(data, mesh, _node_set(data, ident, first.where))
    raise KeywordError(f"{first.where}: *INITIAL_VELOCITY_GENERATION STYP = {styp}; use 1 (part set), 2 (part) "
                       f"or 3 (node set)")
