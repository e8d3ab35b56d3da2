"""The relations between a part's options and its elements that the deck validator checks
(paradyn/deck/validation.py's _check_relations; the engine's model/deck_relations): a part that
updates its thickness is of one-point quadrilaterals."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from paradyn._schema import ENUMS
from paradyn.deck.model import trait_codes


class Checker(Protocol):
    """What the validator's checker offers: the model's arrays and a failure naming the problem."""

    def array(self, attribute: str) -> np.ndarray: ...

    def fail(self, message: str) -> None: ...


def check_thickness_updates(check: Checker, conn: np.ndarray, truss: np.ndarray) -> None:
    """thickness_update_elements (the engine's thickness_update_message): a part that updates its
    thickness is of one-point quadrilaterals, none a triangle, fully integrated, truss or rigid."""
    update = check.array("thickness_update")
    if not np.any(update):
        return
    part = check.array("element_part")
    rigid = np.isin(check.array("material_model")[check.array("part_material")], trait_codes("material_model", "rigid"))
    full = check.array("shell_element") == ENUMS["shell_element"]["full"]
    for row in np.flatnonzero(update[part] != 0):
        p = int(part[row])
        why = ("it is a truss part" if truss[row] else "its material is rigid" if rigid[p]
               else "its element is the fully integrated one (/parts/shell_element = 2)" if full[p]
               else f"its element {int(row)} is a triangle" if conn[row, 2] == conn[row, 3] else "")
        if why:
            check.fail(f"/parts/thickness_update[{p}] = 1, but {why}; the thickness update is the one-point "
                       f"quadrilateral's: set it to 0, or give the part one-point quadrilaterals only")
            return
