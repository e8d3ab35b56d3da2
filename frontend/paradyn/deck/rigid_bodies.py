"""The rigid bodies of a deck model (/rigid_bodies, /nodes/rigid_body), completed from its parts.

A part whose material is rigid (a member with the trait ``rigid``) moves as one body. The scene and
the keyword reader give the bodies they know about (their part and held dofs); :func:`complete_rigid_bodies`
adds a free body for every other rigid part and marks every node of a body's elements with its
row, which is what the engine reads (it never looks at the parts to find a body's nodes).
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


def complete_rigid_bodies(model: Model) -> None:
    """One /rigid_bodies row per rigid part (a free one where none is given) and /nodes/rigid_body
    from the bodies' elements; nothing when the model has no rigid part and no row."""
    parts = rigid_parts(model)
    given = [] if model.rigid_body_part is None else [int(p) for p in model.rigid_body_part]
    if not parts.size and not given:
        return
    name = _part_namer(model)
    for row, part in enumerate(given):
        if part not in parts:
            raise RigidBodyError(f"rigid body #{row + 1} names part {name(part)}, whose material is not rigid; give "
                                 f"the part a material with model = \"rigid\"")
        if given.count(part) > 1:
            raise RigidBodyError(f"part {name(part)} has {given.count(part)} rigid bodies; give each rigid part one")
    fixed = np.zeros((0, 6), dtype=np.int32) if model.rigid_body_fixed_dofs is None else model.rigid_body_fixed_dofs
    missing = [int(p) for p in parts if int(p) not in given]
    model.rigid_body_part = np.array(given + missing, dtype=np.int32)
    model.rigid_body_fixed_dofs = np.concatenate([np.asarray(fixed, dtype=np.int32).reshape(-1, 6),
                                                  np.zeros((len(missing), 6), dtype=np.int32)])
    model.node_rigid_body = node_bodies(model, name)


def node_bodies(model: Model, name: Callable[[int], str] = str) -> np.ndarray:
    """-1, or the row of /rigid_bodies whose part has an element on the node; a node on two
    bodies' elements is refused (the bodies would have to be one)."""
    n_nodes = len(model.coordinates)
    body = np.full(n_nodes, -1, dtype=np.int32)
    connectivity, element_part = np.asarray(model.connectivity), np.asarray(model.element_part)
    for row, part in enumerate(model.rigid_body_part):
        nodes = np.unique(connectivity[element_part == part])
        taken = nodes[(body[nodes] >= 0) & (body[nodes] != row)]
        if taken.size:
            other = int(model.rigid_body_part[body[taken[0]]])
            raise RigidBodyError(f"node {int(taken[0])} belongs to the rigid parts {name(other)} and {name(int(part))}; "
                                 f"two rigid bodies cannot share a node: merge them into one part, or separate "
                                 f"them (LS-DYNA *CONSTRAINED_RIGID_BODIES merges two bodies)")
        body[nodes] = row
    return body


def _part_namer(model: Model) -> Callable[[int], str]:
    names = list(model.part_names or [])

    def name(part: int) -> str:
        return f"{part} ('{names[part]}')" if part < len(names) else str(part)
    return name
