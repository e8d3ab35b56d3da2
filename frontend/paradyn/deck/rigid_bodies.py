"""The rigid bodies of a deck model (/rigid_bodies, /nodes/rigid_body), completed from its parts.

A part whose material is rigid (a member with the trait ``rigid``) moves as one body, with the rigid
parts it shares nodes with or is merged with. The scene and the keyword reader give the bodies they
know about (their part and held dofs); :func:`complete_rigid_bodies` adds a free body for every
other rigid part, merges, and marks every node of a body's elements with its row, which is what the
engine reads (it never looks at the parts to find a body's nodes).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from paradyn._schema import DATASETS

from .model import Model, trait_codes


class RigidBodyError(ValueError):
    """A body that cannot be built: the message names the part and the fix."""


@dataclass
class Weld:
    """A body of nodes alone (a spot weld, LS-DYNA *CONSTRAINED_SPOTWELD, or a nodal rigid body)
    with its failure (docs/theory.md, "Weld failure"): it lets its nodes go when the force its
    constraint applies to ``nodes[0]`` (N1) reaches (max(fn, 0) / SN)^N + (|fs| / SS)^M >= 1, fn along
    ``normal`` (N1 -> N2 when None and the first two nodes differ; else the zero vector: all shear),
    or at ``failure_time``, or when the largest effective plastic strain of the shells around its nodes
    reaches ``plastic_strain`` (LS-DYNA EP, EPSF). SN = SS = 0: no force failure; 0: no strain failure."""

    nodes: Sequence[int]
    strength: tuple[float, float] = (0.0, 0.0)        # SN, SS (N)
    exponent: tuple[float, float] = (2.0, 2.0)        # N, M
    failure_time: float = 1e20                        # s
    normal: tuple[float, float, float] | None = None
    plastic_strain: float = 0.0                       # EP

    def fails(self) -> bool:
        return max(self.strength) > 0.0 or self.failure_time < 1e20 or self.plastic_strain > 0.0

    def normal_at(self, coordinates: np.ndarray) -> np.ndarray:
        """The weld's normal at time 0: the one given, or N1 -> N2 (zero where they coincide)."""
        if self.normal is not None:
            return np.asarray(self.normal, dtype=float)
        if len(self.nodes) < 2:
            return np.zeros(3)
        d = np.asarray(coordinates[self.nodes[1]], dtype=float) - np.asarray(coordinates[self.nodes[0]], dtype=float)
        size = float(np.linalg.norm(d))
        return d / size if size > 1e-9 * max(float(np.abs(coordinates).max()), 1e-300) else np.zeros(3)


def rigid_parts(model: Model) -> np.ndarray:
    """The 0-based parts whose material is rigid."""
    rigid = np.isin(np.asarray(model.material_model), trait_codes("material_model", "rigid"))
    return np.flatnonzero(rigid[np.asarray(model.part_material)])


def complete_rigid_bodies(model: Model, merge: list[tuple[int, int]] | None = None,
                          extra: list[tuple[int, int]] | None = None,
                          nodal: Sequence[Sequence[int] | Weld] | None = None) -> list[str]:
    """One /rigid_bodies row per rigid body and /nodes/rigid_body from the bodies' elements;
    nothing when the model has no rigid part and no row. A body is a rigid part, or rigid parts
    that share a node or that ``merge`` pairs (LS-DYNA *CONSTRAINED_RIGID_BODIES): the lowest part
    leads it, its held dofs are those of any of its parts. ``extra``: (part, node) pairs, nodes that
    move with the part's body besides its elements' (LS-DYNA *CONSTRAINED_EXTRA_NODES); ``nodal``:
    bodies of nodes alone (part -1: LS-DYNA *CONSTRAINED_NODAL_RIGID_BODY, spot welds; a :class:`Weld`
    with its failure), after the parts' bodies. Returns a line for each pair of rigid parts merged
    because they share nodes (the caller warns with it)."""
    parts = [int(p) for p in rigid_parts(model)]
    given = [] if model.rigid_body_part is None else [int(p) for p in model.rigid_body_part if p >= 0]
    if not parts and not given and not nodal:
        return []
    name = _part_namer(model)
    held = {part: np.zeros(6, dtype=np.int32) for part in parts}
    fixed = np.zeros((0, 6)) if model.rigid_body_fixed_dofs is None else np.asarray(model.rigid_body_fixed_dofs)
    for row, part in enumerate(given):
        if part not in held:
            raise RigidBodyError(f"rigid body #{row + 1} names part {name(part)}, whose material is not rigid; give "
                                 f"the part a material with model = \"rigid\"")
        if given.count(part) > 1:
            raise RigidBodyError(f"part {name(part)} has {given.count(part)} rigid bodies; give each rigid part one")
        held[part] = np.asarray(fixed[row], dtype=np.int32)
    lead, notes = _group_parts(model, parts, merge or [], name)
    leads = sorted(set(lead.values()))
    _rows_of_leads(model, given, leads)
    model.rigid_body_part = np.array(leads, dtype=np.int32)
    model.rigid_body_fixed_dofs = np.array([np.max([held[p] for p in parts if lead[p] == head], axis=0)
                                            for head in leads], dtype=np.int32).reshape(-1, 6)
    row_of = {head: row for row, head in enumerate(leads)}
    body = np.full(len(model.coordinates), -1, dtype=np.int32)
    connectivity, element_part = np.asarray(model.connectivity), np.asarray(model.element_part)
    for part in parts:
        body[np.unique(connectivity[element_part == part])] = row_of[lead[part]]
    for part, node in extra or []:
        if part not in lead:
            raise RigidBodyError(f"extra node {node} names part {name(part)}, which is not rigid; give a rigid part")
        if body[node] >= 0 and body[node] != row_of[lead[part]]:
            raise RigidBodyError(f"extra node {node} of part {name(part)} is already on the rigid body of part "
                                 f"{name(int(model.rigid_body_part[body[node]]))}; merge the two bodies instead")
        body[node] = row_of[lead[part]]
    for entry in nodal or []:
        weld = entry if isinstance(entry, Weld) else Weld(list(entry))
        nodes = list(weld.nodes)
        row = len(model.rigid_body_part)
        taken = [int(n) for n in nodes if body[n] >= 0]
        if taken:
            raise RigidBodyError(f"node {taken[0]} of a nodal rigid body (a spot weld) is already on rigid body "
                                 f"{int(body[taken[0]])}; a node moves with one body (merge them instead)")
        body[np.asarray(nodes, dtype=int)] = row
        model.rigid_body_part = np.append(model.rigid_body_part, -1).astype(np.int32)
        model.rigid_body_fixed_dofs = np.vstack([model.rigid_body_fixed_dofs, np.zeros((1, 6), dtype=np.int32)])
        _pad_rows(model)
        if weld.fails():
            _set_failure(model, row, weld)
    model.node_rigid_body = body
    return notes


def _pad_rows(model: Model) -> None:
    """The other /rigid_bodies columns one row longer (the defaults), where they are given."""
    for spec in DATASETS:
        if spec.shape[0] != "n_rigid_bodies" or spec.python in ("rigid_body_part", "rigid_body_fixed_dofs"):
            continue
        values = getattr(model, spec.python)
        if values is not None:
            values = np.asarray(values)
            setattr(model, spec.python, np.concatenate([values, np.full((1, *values.shape[1:]), spec.default,
                                                                        dtype=values.dtype)]))


def _set_failure(model: Model, row: int, weld: Weld) -> None:
    """Row ``row`` of the /rigid_bodies failure columns from ``weld`` (the columns made, with their
    defaults, where absent)."""
    n = len(model.rigid_body_part)
    values = {"rigid_body_failure_force": weld.strength, "rigid_body_failure_exponent": weld.exponent,
              "rigid_body_failure_time": weld.failure_time, "rigid_body_failure_node": int(weld.nodes[0]),
              "rigid_body_failure_normal": weld.normal_at(np.asarray(model.coordinates, dtype=float)),
              "rigid_body_failure_plastic_strain": weld.plastic_strain}
    for spec in DATASETS:
        if spec.python not in values:
            continue
        column = getattr(model, spec.python)
        if column is None:
            dtype = np.int32 if spec.type == "int" else float
            column = np.full((n, *[int(k) for k in spec.shape[1:]]), spec.default, dtype=dtype)
        column[row] = values[spec.python]
        setattr(model, spec.python, column)


def body_centres(model: Model) -> np.ndarray:
    """The centre of mass of each body of /rigid_bodies, from its nodes' lumped masses (a quarter, or
    a third for a triangle, of each element's rho t A, and /nodes/added_mass), as the engine takes it."""
    x = np.asarray(model.coordinates, dtype=float)
    conn, part = np.asarray(model.connectivity), np.asarray(model.element_part)
    corners = x[conn]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1]), axis=1)
    rho_t = (np.asarray(model.density)[np.asarray(model.part_material)] * np.asarray(model.thickness))[part]
    surface = np.zeros(len(np.asarray(model.thickness)), dtype=bool)
    if model.surface_only is not None:
        surface = np.asarray(model.surface_only) == 1
    element_mass = np.where(surface[part], 0.0, rho_t * area)
    triangle = conn[:, 2] == conn[:, 3]
    mass = np.zeros(len(x))
    for k in range(4):   # a triangle's fourth corner is its third node again: no second share
        share = np.where(triangle, 1.0 / 3.0 if k < 3 else 0.0, 0.25)
        np.add.at(mass, conn[:, k], share * element_mass)
    if model.added_mass is not None:
        mass += np.asarray(model.added_mass)
    body = np.asarray(model.node_rigid_body)
    return np.array([mass[body == b] @ x[body == b] / mass[body == b].sum() for b in range(len(model.rigid_body_part))])


def _rows_of_leads(model: Model, given: list[int], leads: list[int]) -> None:
    """The other /rigid_bodies columns (prescribed motion, ...) row by row of the new bodies: a body
    whose lead part had a row keeps that row's values, the others take the defaults."""
    for spec in DATASETS:
        if spec.shape[0] != "n_rigid_bodies" or spec.python in ("rigid_body_part", "rigid_body_fixed_dofs"):
            continue
        values = getattr(model, spec.python)
        if values is None or len(values) != len(given) or not given:
            setattr(model, spec.python, None)
            continue
        values = np.asarray(values)
        default = np.full(values.shape[1:], spec.default, dtype=values.dtype)
        setattr(model, spec.python, np.array([values[given.index(p)] if p in given else default for p in leads]))


def _group_parts(model: Model, parts: list[int], merge: list[tuple[int, int]],
                 name: Callable[[int], str]) -> tuple[dict[int, int], list[str]]:
    """The lead part (the lowest) of every rigid part's body: parts joined by ``merge`` or by
    shared nodes; and a line for each join by shared nodes."""
    lead = {part: part for part in parts}

    def head(part: int) -> int:
        while lead[part] != part:
            part = lead[part]
        return part

    def join(a: int, b: int) -> None:
        ha, hb = head(a), head(b)
        lead[max(ha, hb)] = min(ha, hb)

    for a, b in merge:
        for part in (a, b):
            if part not in lead:
                raise RigidBodyError(f"merging rigid bodies: part {name(part)} is not rigid; give it a rigid material")
        join(a, b)
    owner = np.full(len(model.coordinates), -1)
    connectivity, element_part = np.asarray(model.connectivity), np.asarray(model.element_part)
    notes = []
    for part in parts:
        nodes = np.unique(connectivity[element_part == part])
        shared = owner[nodes][owner[nodes] >= 0]
        for other in sorted({int(o) for o in shared}):
            if head(other) != head(part):
                notes.append(f"rigid parts {name(other)} and {name(part)} share "
                             f"{int(np.count_nonzero(shared == other))} node(s): they move as one rigid body "
                             f"(as *CONSTRAINED_RIGID_BODIES would merge them)")
                join(other, part)
        owner[nodes] = part
    return {part: head(part) for part in parts}, notes


def _part_namer(model: Model) -> Callable[[int], str]:
    names = list(model.part_names or [])

    def name(part: int) -> str:
        return f"{part} ('{names[part]}')" if part < len(names) else str(part)
    return name
