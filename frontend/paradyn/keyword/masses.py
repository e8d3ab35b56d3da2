"""Added masses of a keyword deck (docs/keyword.md): ``*ELEMENT_MASS`` on a node, ``_NODE_SET``
spread equally over a set's nodes, ``*ELEMENT_MASS_PART`` (``_SET``) over a part's nodes in
proportion to their own mass (ADDMASS added, or FINMASS the part's final mass). All of them go to
``/nodes/added_mass``, which the engine adds to the nodes' lumped masses (a rigid body's included).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from paradyn import deck

from .cards import KeywordData, _Reading
from .loads import node_rows
from .mesh import KeywordMesh
from .reader import Field, KeywordError, layout
from .units import Units

ELEMENT_MASS = (Field("EID", "int", 0, 8), Field("ID", "int", None, 8), Field("MASS", "float", 0.0, 16),
                Field("PID", "int", 0, 8))
MASS_PART = layout("int:ID ADDMASS FINMASS int:LCID", addmass=0.0, finmass=0.0, lcid=0)


def _element_mass(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        for line in r.lines():
            r.data.added_masses.append((target, r.card(line, ELEMENT_MASS, {"PID": 0})))
    return read


def _part_mass(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        for line in r.lines():
            r.data.added_masses.append((target, r.card(line, MASS_PART, {"LCID": 0})))
    return read


READERS: dict[str, Callable[[_Reading], None]] = {
    "ELEMENT_MASS": _element_mass("NODE"), "ELEMENT_MASS_NODE_SET": _element_mass("SET"),
    "ELEMENT_MASS_PART": _part_mass("PART"), "ELEMENT_MASS_PART_SET": _part_mass("PART_SET"),
}


def apply_masses(data: KeywordData, mesh: KeywordMesh, unit: Units, model: deck.Model) -> None:
    """The deck's added masses (kg) onto ``model.added_mass``."""
    if not data.added_masses:
        return
    added = np.zeros(len(mesh.node_ids)) if model.added_mass is None else np.asarray(model.added_mass, float).copy()
    own = _own_masses(model)
    for target, record in data.added_masses:
        what = f"*ELEMENT_MASS{'' if target == 'NODE' else '_' + target}"
        if target in ("NODE", "SET"):
            rows = node_rows(data, mesh, target, int(record["ID"]), record.where, what)
            added[rows] += float(record["MASS"]) * unit.mass / len(rows)
            continue
        pids = [int(record["ID"])] if target == "PART" else data.part_sets.get(int(record["ID"]), [])
        nodes = np.unique(np.asarray(model.connectivity)[np.isin(mesh.part_ids[np.asarray(model.element_part)], pids)])
        if not nodes.size:
            kind = target.lower().replace("_", " ")
            raise KeywordError(f"{record.where}: {what} names {kind} {record['ID']}, which has no elements; name a "
                               f"part with shells")
        final, extra = float(record["FINMASS"]) * unit.mass, float(record["ADDMASS"]) * unit.mass
        share = own[nodes] / own[nodes].sum()
        added[nodes] += share * (final - (own[nodes] + added[nodes]).sum() if final > 0 else extra)
    if np.any(added < 0):
        raise KeywordError("*ELEMENT_MASS_PART FINMASS is below a part's own mass; give a final mass above it")
    model.added_mass = added


def _own_masses(model: deck.Model) -> np.ndarray:
    """Each node's lumped shell mass (a quarter of rho t A of each quadrilateral, a third of a triangle's)."""
    x = np.asarray(model.coordinates, float)[np.asarray(model.connectivity)]
    area = 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)
    part = np.asarray(model.element_part)
    mass = (np.asarray(model.density)[np.asarray(model.part_material)] * np.asarray(model.thickness))[part] * area
    conn = np.asarray(model.connectivity)
    triangle = conn[:, 2] == conn[:, 3]
    out = np.zeros(len(model.coordinates))
    for k in range(4):
        np.add.at(out, conn[:, k], mass * np.where(triangle, 1.0 / 3.0 if k < 3 else 0.0, 0.25))
    return out


__all__ = ["READERS", "apply_masses"]
