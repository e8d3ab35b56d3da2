"""Rigid bodies of a keyword deck (docs/keyword.md, "Rigid bodies"): ``*MAT_RIGID`` (MAT 20),
``*DEFORMABLE_TO_RIGID`` at the start, ``*ELEMENT_SOLID`` of rigid parts as geometry.

A part with a rigid material (or switched to rigid at the start) becomes one body of the deck's
/rigid_bodies, its constraints from MAT_RIGID's CMO, CON1, CON2. The solid elements of a rigid part
are geometry: their outer faces become the part's elements (a contact surface with no mass of its
own, /parts/surface_only), and their mass, lumped to their nodes, goes to /nodes/added_mass.
Solids of a deformable part are left out with a warning (ParaDyn has no deformable solids).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from paradyn import deck
from paradyn.deck.rigid_bodies import Weld, body_centres

from .cards import KeywordData, Record
from .mesh import KeywordMesh
from .reader import KeywordError
from .units import Units

# MAT_RIGID CON1 / CON2 (CMO = 1): the held directions of each code (as *NODE's TC and RC)
HELD_OF_CODE = {0: (), 1: (0,), 2: (1,), 3: (2,), 4: (0, 1), 5: (1, 2), 6: (2, 0), 7: (0, 1, 2)}
# the faces of an 8-node hexahedron (LS-DYNA's numbering: N1-N4 one end, N5-N8 the other), outward
HEX_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
# a solid part's faces are a contact surface this thick, as a fraction of their median edge: thin
# enough that the surface is where the solid's is, thick enough for the shell contact's search
FACE_THICKNESS = 0.01


def rigid_part_ids(data: KeywordData) -> set[int]:
    """The PIDs whose material is rigid or that *DEFORMABLE_TO_RIGID switches at the start."""
    rigid = {int(p["PID"]) for p in data.parts
             if data.materials.get(int(p["MID"] or 0), ("",))[0] == "rigid"}
    return rigid | {int(r["PID"]) for r in data.deformable_to_rigid}


def held_dofs(mid: int, cards: list[Record]) -> tuple[int, ...]:
    """The six held dofs of a rigid body from MAT_RIGID's CMO, CON1, CON2 (global axes)."""
    card = cards[1]
    cmo = float(card["CMO"] or 0.0)
    if cmo == 0.0:
        return (0,) * 6
    if cmo < 0.0:
        raise KeywordError(f"{card.where}: *MAT_RIGID {mid} CMO = {cmo:g} (constraints in a local system) is not "
                           f"read; give the constraints in global axes (CMO = 1)")
    codes = []
    for name in ("CON1", "CON2"):
        code = int(float(card[name] or 0.0))
        if code not in HELD_OF_CODE:
            raise KeywordError(f"{card.where}: *MAT_RIGID {mid} {name} = {code}; give 0 to 7 (CMO = 1)")
        codes.append(code)
    held = [0] * 6
    for offset, code in zip((0, 3), codes, strict=True):
        for axis in HELD_OF_CODE[code]:
            held[offset + axis] = 1
    return tuple(held)


@dataclass
class SolidGeometry:
    """The rigid solids of a deck as faces and nodal masses (deck ids, the deck's units)."""

    faces: list[tuple[int, int, tuple[int, int, int, int]]]   # (EID of the solid, PID, 4 NIDs)
    node_mass: dict[int, float]                                 # NID -> lumped mass of its solids


def rigid_solids(data: KeywordData, rigid: set[int]) -> SolidGeometry:
    """The outer faces of the solid elements of each rigid part and their mass lumped to the nodes
    (density of the part's material); solids of other parts are left out with a warning."""
    xyz = {int(n["NID"]): np.array([float(n[c]) for c in "XYZ"]) for n in data.nodes}
    density = {int(p["PID"]): float(data.materials[int(p["MID"] or 0)][1][0]["RO"] or 0.0) for p in data.parts
               if int(p["MID"] or 0) in data.materials}
    faces: list[tuple[int, int, tuple[int, int, int, int]]] = []
    node_mass: dict[int, float] = {}
    by_part: dict[int, list[Record]] = {}
    for record in data.solids:
        by_part.setdefault(int(record["PID"]), []).append(record)
    for pid, records in by_part.items():
        if pid not in rigid:
            data.warn(f"{records[0].where}: the {len(records)} *ELEMENT_SOLID of part {pid} are left out: ParaDyn "
                      f"reads solids only as the geometry of a rigid part (*MAT_RIGID)")
            continue
        count: dict[tuple[int, ...], int] = {}
        oriented: dict[tuple[int, ...], tuple[int, int, tuple[int, int, int, int]]] = {}
        for record in records:
            nids = [int(record[f"N{k}"]) for k in range(1, 9)]
            missing = [n for n in nids if n not in xyz]
            if missing:
                raise KeywordError(f"{record.where}: *ELEMENT_SOLID {record['EID']} names node {missing[0]}, which "
                                   f"no *NODE defines")
            for nid, mass in zip(nids, hexahedron_masses(np.array([xyz[n] for n in nids])) * density[pid],
                                 strict=True):
                node_mass[nid] = node_mass.get(nid, 0.0) + mass
            for face in HEX_FACES:
                quad = tuple(nids[k] for k in face)
                if len(set(quad)) < 3:
                    continue   # a face that a degenerate (6- or 4-node) solid collapses to an edge
                key = tuple(sorted(set(quad)))
                count[key] = count.get(key, 0) + 1
                oriented[key] = (int(record["EID"]), pid, _as_quad(quad))
        faces += [oriented[key] for key, n in count.items() if n == 1]
    return SolidGeometry(faces=faces, node_mass=node_mass)


def _as_quad(quad: tuple[int, ...]) -> tuple[int, int, int, int]:
    """A face of three distinct nodes as a triangle (N3 = N4), of four as it is."""
    distinct = list(dict.fromkeys(quad))
    if len(distinct) == 3:
        raise KeywordError("a rigid solid has a triangular face (a 6- or 4-node solid): ParaDyn's faces are "
                           "quadrilaterals until triangles are read; mesh the rigid solid with hexahedra")
    return (distinct[0], distinct[1], distinct[2], distinct[3])


def hexahedron_masses(x: np.ndarray) -> np.ndarray:
    """The volume of an 8-node hexahedron lumped to its nodes (row sums of the consistent mass
    with unit density: the integral of each shape function, 2 x 2 x 2 Gauss points)."""
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    g = 1.0 / np.sqrt(3.0)
    out = np.zeros(8)
    for point in signs * g:
        shape = np.prod(1.0 + signs * point, axis=1) / 8.0
        derivative = np.empty((3, 8))
        for axis in range(3):
            others = [a for a in range(3) if a != axis]
            derivative[axis] = signs[:, axis] * np.prod(1.0 + signs[:, others] * point[others], axis=1) / 8.0
        out += shape * abs(np.linalg.det(derivative @ x))
    return out


def face_thickness(faces: list[tuple[int, int, tuple[int, int, int, int]]], xyz: dict[int, np.ndarray]) -> float:
    """The contact thickness of a solid part's faces: FACE_THICKNESS of their median edge."""
    edges = [np.linalg.norm(xyz[q[(k + 1) % 4]] - xyz[q[k]]) for _, _, q in faces for k in range(4)]
    return FACE_THICKNESS * float(np.median(edges))


def add_solid_faces(data: KeywordData) -> SolidGeometry:
    """Append the outer faces of the rigid parts' solids to the deck's shells (ids after the deck's
    largest element id, so the outputs name them apart) and return the solids' geometry."""
    solids = rigid_solids(data, rigid_part_ids(data))
    first = max([int(e["EID"]) for e in data.elements] + [int(e["EID"]) for e in data.solids] + [0]) + 1
    for k, (eid, pid, quad) in enumerate(solids.faces):
        values = {"EID": first + k, "PID": pid, **{f"N{j + 1}": n for j, n in enumerate(quad)},
                  **{f"N{j}": 0 for j in range(5, 9)}}
        data.elements.append(Record(values, f"a face of *ELEMENT_SOLID {eid}"))
    return solids


def solid_face_thickness(data: KeywordData, solids: SolidGeometry) -> dict[int, float]:
    """PID -> the contact thickness of each rigid solid part's faces (the deck's length unit)."""
    xyz = {int(n["NID"]): np.array([float(n[c]) for c in "XYZ"]) for n in data.nodes}
    pids = {pid for _, pid, _ in solids.faces}
    return {pid: face_thickness([f for f in solids.faces if f[1] == pid], xyz) for pid in pids}


def rigid_material_key(data: KeywordData, pid: int, mid: int) -> tuple[str, int]:
    """The material a part runs with: its own, or for a part *DEFORMABLE_TO_RIGID switches at the
    start a rigid one with its density and elastic constants ("rigid", MID)."""
    switched = {int(r["PID"]): r for r in data.deformable_to_rigid}
    if pid not in switched:
        return ("", mid)
    return ("rigid", mid)


def merged_pairs(data: KeywordData) -> list[tuple[int, int]]:
    """PID pairs whose bodies are one: *CONSTRAINED_RIGID_BODIES (PIDL, PIDC) and a
    *DEFORMABLE_TO_RIGID part's MRB."""
    pairs = [(int(r["PIDL"]), int(r["PIDC"])) for r in data.merged_bodies]
    return pairs + [(int(r["MRB"]), int(r["PID"])) for r in data.deformable_to_rigid if int(r["MRB"] or 0)]


def rigid_body_rows(data: KeywordData, part_ids: np.ndarray,
                    part_material_ids: list[int]) -> tuple[list[int], list[tuple[int, ...]]]:
    """The /rigid_bodies rows of the rigid parts (0-based parts, held dofs from MAT_RIGID's CMO,
    CON1, CON2; a switched part's body is free)."""
    rigid = rigid_part_ids(data)
    parts, held = [], []
    for row, pid in enumerate(part_ids.tolist()):
        if pid not in rigid:
            continue
        mid = part_material_ids[row]
        model, cards = data.materials[mid]
        parts.append(row)
        held.append(held_dofs(mid, cards) if model == "rigid" else (0,) * 6)
    return parts, held


def extra_nodes(data: KeywordData, mesh: KeywordMesh, row: dict[int, int]) -> list[tuple[int, int]]:
    """(engine part, node row) of every *CONSTRAINED_EXTRA_NODES_NODE / _SET node."""
    pairs = []
    for target, record in data.extra_nodes:
        pid, ident = int(record["PID"]), int(record["ID"])
        what = f"{record.where}: *CONSTRAINED_EXTRA_NODES_{target}"
        if pid not in row:
            raise KeywordError(f"{what} names part {pid}, which has no elements; name a rigid part")
        if target == "SET" and ident not in data.node_sets:
            raise KeywordError(f"{what} names node set {ident}, which no *SET_NODE defines")
        for nid in [ident] if target == "NODE" else data.node_sets[ident]:
            if nid not in mesh.node_index:
                raise KeywordError(f"{what} names node {nid}, which no element uses; ParaDyn's nodes belong to "
                                   f"elements (a node alone has no mass)")
            pairs.append((row[pid], mesh.node_index[nid]))
    return pairs


def body_velocities(data: KeywordData, mesh: KeywordMesh, row: dict[int, int], unit: Units,
                    model: deck.Model) -> None:
    """*INITIAL_VELOCITY_RIGID_BODY: the nodes of the part's body start with V + omega x (x - centre)
    and omega (the body then takes exactly that motion, docs/theory.md)."""
    if not data.body_velocities:
        return
    centres = body_centres(model)
    if model.rigid_body_given_mass is not None:   # *PART_INERTIA: the given centre
        given = np.asarray(model.rigid_body_given_mass) > 0.0
        centres[given] = np.asarray(model.rigid_body_given_centre)[given]
    for record in data.body_velocities:
        body = _body_of_part(model, row, int(record["PID"]), f"{record.where}: *INITIAL_VELOCITY_RIGID_BODY")
        nodes = np.flatnonzero(model.node_rigid_body == body)
        velocity = np.array([float(record[k]) for k in ("VX", "VY", "VZ")]) * unit.velocity
        omega = np.array([float(record[k]) for k in ("VXR", "VYR", "VZR")]) / unit.time
        r = np.asarray(model.coordinates)[nodes] - centres[body]
        model.initial_velocity[nodes] = velocity + np.cross(omega, r)
        model.initial_angular_velocity[nodes] = omega


def part_inertia(data: KeywordData, mesh: KeywordMesh, row: dict[int, int], unit: Units,
                 model: deck.Model) -> None:
    """*PART_INERTIA: the mass TM, centre (XC, YC, ZC, or node NODEID's place) and inertia tensor of
    the part's body as given (global axes with IRCS = 0; IRCS = 1: the principal tensor in the axes
    of card 5a, XL and the plane of XL, XLIP), and where VTX .. VRZ are not all zero the body's
    initial velocity, V + omega x (x - centre) on its nodes."""
    if not data.part_inertia:
        return
    n = len(model.rigid_body_part)
    mass, centre, inertia = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 6))
    x = np.asarray(model.coordinates, dtype=float)
    for pid, record in data.part_inertia.items():
        where = f"{record.where}: *PART_INERTIA part {pid}"
        body = _body_of_part(model, row, pid, where)
        if mass[body] > 0.0:
            raise KeywordError(f"{where}: its body already has a *PART_INERTIA (merged parts); give the merged "
                               f"body one")
        mass[body] = float(record["TM"] or 0.0) * unit.mass
        if not mass[body] > 0.0:
            raise KeywordError(f"{where}: TM = {record['TM']}; give the body's mass (> 0)")
        node = int(record["NODEID"] or 0)
        if node and node not in mesh.node_index:
            raise KeywordError(f"{where}: NODEID {node} is no node of an element; give a node or XC, YC, ZC")
        centre[body] = x[mesh.node_index[node]] if node else np.array([float(record[k] or 0.0) for k in
                                                                       ("XC", "YC", "ZC")]) * unit.length
        tensor = _inertia_tensor(record, where) * unit.mass * unit.length**2
        if np.any(np.linalg.eigvalsh(tensor) <= 0.0):
            raise KeywordError(f"{where}: the inertia tensor is not positive definite; give IXX .. IZZ about the "
                               f"centre of mass")
        inertia[body] = tensor[[0, 1, 2, 0, 1, 2], [0, 1, 2, 1, 2, 0]]
        velocity = np.array([float(record[k] or 0.0) for k in ("VTX", "VTY", "VTZ")]) * unit.velocity
        omega = np.array([float(record[k] or 0.0) for k in ("VRX", "VRY", "VRZ")]) / unit.time
        if velocity.any() or omega.any():
            nodes = np.flatnonzero(np.asarray(model.node_rigid_body) == body)
            model.initial_velocity[nodes] = velocity + np.cross(omega, x[nodes] - centre[body])
            model.initial_angular_velocity[nodes] = omega
    model.rigid_body_given_mass, model.rigid_body_given_centre, model.rigid_body_given_inertia = mass, centre, inertia


def _inertia_tensor(record: Record, where: str) -> np.ndarray:
    """The tensor of *PART_INERTIA's card 4 in global axes (IRCS = 1: turned from card 5a's axes)."""
    v = {k: float(record[k] or 0.0) for k in ("IXX", "IXY", "IXZ", "IYY", "IYZ", "IZZ")}
    tensor = np.array([[v["IXX"], v["IXY"], v["IXZ"]], [v["IXY"], v["IYY"], v["IYZ"]], [v["IXZ"], v["IYZ"], v["IZZ"]]])
    if int(record["IRCS"] or 0) != 1:
        return tensor
    if int(record["CID"] or 0):
        raise KeywordError(f"{where}: IRCS = 1 with CID {record['CID']} is not read; give the axes by XL .. ZLIP")
    e1 = np.array([float(record[k] or 0.0) for k in ("XL", "YL", "ZL")])
    in_plane = np.array([float(record[k] or 0.0) for k in ("XLIP", "YLIP", "ZLIP")])
    e3 = np.cross(e1, in_plane)
    if np.linalg.norm(e1) == 0.0 or np.linalg.norm(e3) == 0.0:
        raise KeywordError(f"{where}: IRCS = 1 needs XL, YL, ZL and a vector XLIP, YLIP, ZLIP not along it")
    e1, e3 = e1 / np.linalg.norm(e1), e3 / np.linalg.norm(e3)
    axes = np.column_stack([e1, np.cross(e3, e1), e3])
    return axes @ tensor @ axes.T


def body_motions(data: KeywordData, row: dict[int, int], model: deck.Model) -> None:
    """*BOUNDARY_PRESCRIBED_MOTION_RIGID rows on their bodies: the dof prescribed, its SF (SI) and the
    body's one velocity curve (dofs of one body with two different curves are refused)."""
    if not data.rigid_motions:
        return
    n = len(model.rigid_body_part)
    prescribed, velocity = np.zeros((n, 6), dtype=np.int32), np.zeros((n, 6))
    curve = np.full(n, -1, dtype=np.int32)
    for pid, dof, scale, index, where in data.rigid_motions:
        body = _body_of_part(model, row, pid, where)
        if curve[body] not in (-1, index):
            raise KeywordError(f"{where}: *BOUNDARY_PRESCRIBED_MOTION_RIGID part {pid}: a body's prescribed dofs "
                               f"share one curve in ParaDyn, and this one's differs from the body's others; give them "
                               f"the same LCID (scale them by SF)")
        prescribed[body, dof - 1], velocity[body, dof - 1], curve[body] = 1, scale, index
    model.rigid_body_prescribed, model.rigid_body_velocity, model.rigid_body_curve = prescribed, velocity, curve


def _body_of_part(model: deck.Model, row: dict[int, int], pid: int, where: str) -> int:
    part = row.get(pid)
    nodes = [] if part is None else np.asarray(model.connectivity)[np.asarray(model.element_part) == part].ravel()
    bodies = set() if model.node_rigid_body is None else {int(b) for b in np.asarray(model.node_rigid_body)[nodes]}
    if len(bodies) != 1 or -1 in bodies:
        raise KeywordError(f"{where}: part {pid} is not a rigid part with elements; prescribe a rigid part's motion")
    return bodies.pop()


def nodal_bodies(data: KeywordData, mesh: KeywordMesh, unit: Units) -> list[Weld]:
    """The bodies of nodes alone: *CONSTRAINED_NODAL_RIGID_BODY (its NSID), *CONSTRAINED_SPOTWELD
    (N1, N2) and *CONSTRAINED_GENERALIZED_WELD_SPOT (its NSID), with a weld's failure: SN, SS, N, M
    (a zero exponent is read as 2) and its failure time TF / TFAIL; the force is the one on N1 (the
    set's first node), its normal N1 -> N2; EP / EPSF, the failure plastic strain of the shells
    around its nodes (docs/theory.md, "Weld failure")."""
    bodies = []
    for kind, record in data.welds:
        what = {"NODAL": "*CONSTRAINED_NODAL_RIGID_BODY", "SPOTWELD": "*CONSTRAINED_SPOTWELD",
                "GENERALIZED": "*CONSTRAINED_GENERALIZED_WELD_SPOT"}[kind]
        if kind == "SPOTWELD":
            nids = [int(record["N1"]), int(record["N2"])]
        else:
            if int(record["NSID"]) not in data.node_sets:
                raise KeywordError(f"{record.where}: {what} names node set {record['NSID']}, which no *SET_NODE "
                                   f"defines")
            nids = data.node_sets[int(record["NSID"])]
        missing = [n for n in nids if n not in mesh.node_index]
        if missing:
            raise KeywordError(f"{record.where}: {what} names node {missing[0]}, which no element uses; a weld joins "
                               f"nodes of elements")
        rows = list(dict.fromkeys(mesh.node_index[n] for n in nids))
        bodies.append(Weld(rows, *_weld_failure(record, unit), plastic_strain=_weld_plastic_strain(record)))
    return bodies


def _weld_plastic_strain(record: Record) -> float:
    """EP (*CONSTRAINED_SPOTWELD) or EPSF (*CONSTRAINED_GENERALIZED_WELD_SPOT): the failure plastic
    strain of the shells at the weld's nodes; 0 (none) where absent, 0 or 1e20 and above."""
    for key in ("EP", "EPSF"):
        value = record.values.get(key)
        if value not in (None, "") and 0.0 < float(value) < 1e20:
            return float(value)
    return 0.0


def _weld_failure(record: Record, unit: Units) -> tuple[tuple[float, float], tuple[float, float], float]:
    """(SN, SS) in N, the exponents (N, M; 0 read as 2) and the failure time (TF or TFAIL) in s of a
    weld's card; (0, 0) and 1e20 where the card gives none."""
    def number(key: str, default: float) -> float:
        value = record.values.get(key)
        return default if value in (None, "") else float(value)
    strength = (max(number("SN", 0.0), 0.0) * unit.force, max(number("SS", 0.0), 0.0) * unit.force)
    exponent = tuple(e if e > 0.0 else 2.0 for e in (number("N", 0.0), number("M", 0.0)))
    time = min(number("TF", 1e20), number("TFAIL", 1e20))
    return strength, (exponent[0], exponent[1]), (time * unit.time if time < 1e20 else 1e20)
