"""A model check's message in the keyword deck's own ids (docs/keyword.md, "Messages").

The deck model's validation (:func:`paradyn.deck.validate_model`) names 0-based rows
(``/elements/connectivity[12] = [3, 4, 9, 8]``, ``node 7``); for a model read from a keyword deck,
:func:`in_deck_ids` rewrites them as the deck's ``*ELEMENT_SHELL`` EIDs and ``*NODE`` NIDs with the
file and line that define them, so the message points into the deck.
"""

from __future__ import annotations

import re

from .cards import KeywordData
from .mesh import KeywordMesh

_CONNECTIVITY = re.compile(r"/elements/connectivity\[(\d+)\] = \[([\d, ]+)\]")
_ELEMENT_WITH_PART = re.compile(r"\belement (\d+) \(part (\d+), nodes \[([\d, ]+)\]\)")
_ELEMENT = re.compile(r"\belement (\d+)\b")
_COORDINATES = re.compile(r"/nodes/coordinates\[(\d+)\]")
_NODE = re.compile(r"\bnode (\d+)\b")


class _Ids:
    def __init__(self, data: KeywordData, mesh: KeywordMesh) -> None:
        self.data, self.mesh = data, mesh
        self.node_where = {int(r["NID"]): r.where for r in data.nodes}

    def element(self, row: int) -> str:
        if not 0 <= row < len(self.mesh.element_ids):
            return f"element {row}"
        where = self.data.elements[row].where if row < len(self.data.elements) else "?"
        return f"*ELEMENT_SHELL {int(self.mesh.element_ids[row])} ({where})"

    def node(self, row: int) -> str:
        if not 0 <= row < len(self.mesh.node_ids):
            return f"node {row}"
        nid = int(self.mesh.node_ids[row])
        return f"*NODE {nid} ({self.node_where.get(nid, '?')})"

    def nids(self, rows: str) -> str:
        listed = [int(r) for r in rows.split(",") if r.strip()]
        return "[" + ", ".join(str(int(self.mesh.node_ids[r])) if 0 <= r < len(self.mesh.node_ids) else str(r)
                               for r in listed) + "]"

    def pid(self, part: int) -> str:
        return str(int(self.mesh.part_ids[part])) if 0 <= part < len(self.mesh.part_ids) else str(part)


def in_deck_ids(message: str, data: KeywordData, mesh: KeywordMesh) -> str:
    """``message`` with the model's element and node rows written as the deck's EIDs and NIDs."""
    ids = _Ids(data, mesh)
    message = _CONNECTIVITY.sub(lambda m: f"{ids.element(int(m[1]))} with nodes {ids.nids(m[2])}", message)
    message = _ELEMENT_WITH_PART.sub(lambda m: f"{ids.element(int(m[1]))} (part {ids.pid(int(m[2]))}, nodes "
                                               f"{ids.nids(m[3])})", message)
    message = _ELEMENT.sub(lambda m: ids.element(int(m[1])), message)
    message = _COORDINATES.sub(lambda m: ids.node(int(m[1])), message)
    return _NODE.sub(lambda m: ids.node(int(m[1])), message)
