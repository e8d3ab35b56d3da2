"""The rigid bodies of a deck model (/rigid_bodies, /nodes/rigid_body), completed from its parts.

A part whose material is rigid (a member with the trait ``rigid``) moves as one body, with the rigid
parts it shares nodes with or is merged with. The scene and the keyword reader give the bodies they
know about (their part and held dofs); :func:`complete_rigid_bodies` adds a free body for every
other rigid part, merges, and marks every node of a body's elements with its row, which is what the
engine reads (it never looks at the parts to find a body's nodes).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .model import Model, trait_codes


class RigidBodyError(ValueError):
    """A body that cannot be built: the message names the part and the fix."""


def rigid_parts(model: Model) -> np.ndarray:
    """The 0-based parts whose material is rigid."""
    rigid = np.isin(np.asarray(model.material_model), trait_codes("material_model", "rigid"))
    return np.flatnonzero(rigid[np.asarray(model.part_material)])


def complete_rigid_bodies(model: Model, merge: list[tuple[int, int]] | None = None) -> list[str]:
    """One /rigid_bodies row per rigid body and /nodes/rigid_body from the bodies' elements;
    nothing when the model has no rigid part and no row. A body is a rigid part, or rigid parts
    that share a node or that ``merge`` pairs (LS-DYNA *CONSTRAINED_RIGID_BODIES): the lowest part
    leads it, its held dofs are those of any of its parts. Returns a line for each pair of rigid
    parts merged because they share nodes (the caller warns with it)."""
    parts = [int(p) for p in rigid_parts(model)]
    given = [] if model.rigid_body_part is None else [int(p) for p in model.rigid_body_part]
    if not parts and not given:
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
    model.rigid_body_part = np.array(leads, dtype=np.int32)
    model.rigid_body_fixed_dofs = np.array([np.max([held[p] for p in parts if lead[p] == head], axis=0)
                                            for head in leads], dtype=np.int32).reshape(-1, 6)
    row_of = {head: row for row, head in enumerate(leads)}
    body = np.full(len(model.coordinates), -1, dtype=np.int32)
    connectivity, element_part = np.asarray(model.connectivity), np.asarray(model.element_part)
    for part in parts:
        body[np.unique(connectivity[element_part == part])] = row_of[lead[part]]
    model.node_rigid_body = body
    return notes


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
