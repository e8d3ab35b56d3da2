"""*MAT_ADD_EROSION (docs/keyword.md): a material's failure by effective plastic strain (EFFEPS)
and the number of failed points that erodes an element (NUMFIP).

Card 1 is MID, EXCL, MXPRES, MNEPS, EFFEPS, VOLEPS, NUMFIP, NCS; card 2 MNPRES, SIGP1, SIGVM,
MXEPS, EPSSH, SIGTH, IMPULSE, FAILTM; later cards (damage models: IDAM, GISSMO, ...) are not read.
ParaDyn models the effective plastic strain criterion only: |EFFEPS| becomes the material's
failure_strain (with its own FAIL or FS, the smaller one), NUMFIP its failure_points; every other
active criterion (not blank, 0 or EXCL) is named in a warning and not applied.

:data:`EROSION_READERS` maps the keyword to its reader (registered in
:data:`paradyn.keyword.cards.READERS`); :func:`apply_erosion` puts what it read on a material
(called from :func:`paradyn.keyword.materials.material_of`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from .reader import KeywordError, Line, layout

if TYPE_CHECKING:
    from paradyn.scene.specs import MaterialSpec

# cards.py imports this module (its READERS take EROSION_READERS), so its types are not imported
# back: a reader gets cards.py's _Reading, the data is its KeywordData, a card its Record
_Reading = Any
KeywordData = Any
Record = Any

CARD_1 = layout("int:MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS", excl=0.0, mxpres=0.0, mneps=0.0, effeps=0.0,
                voleps=0.0, numfip=1.0, ncs=1.0)
CARD_2 = layout("MNPRES SIGP1 SIGVM MXEPS EPSSH SIGTH IMPULSE FAILTM", mnpres=0.0, sigp1=0.0, sigvm=0.0, mxeps=0.0,
                epssh=0.0, sigth=0.0, impulse=0.0, failtm=0.0)
# the criteria ParaDyn does not model, with what each one means in LS-DYNA
UNMODELLED = {"MXPRES": "maximum pressure", "MNEPS": "minimum principal strain", "VOLEPS": "volumetric strain",
              "MNPRES": "minimum pressure", "SIGP1": "maximum principal stress", "SIGVM": "equivalent stress",
              "MXEPS": "maximum principal strain", "EPSSH": "shear strain", "SIGTH": "threshold stress (Tuler-Butcher)",
              "IMPULSE": "stress impulse (Tuler-Butcher)", "FAILTM": "failure time"}


def read_erosions(data: KeywordData) -> dict[int, list[Record]]:
    """The *MAT_ADD_EROSION cards read so far, by MID (kept on the deck's KeywordData)."""
    erosions: dict[int, list[Record]] = data.__dict__.setdefault("erosions", {})
    return erosions


def _add_erosion(r: _Reading) -> None:
    titled = r.keyword.endswith("_TITLE")
    lines = r.head_and_rest(titled)
    first = r.card(lines[0], CARD_1)
    second = r.card(lines[1] if len(lines) > 1 else Line("", lines[0].path, lines[0].number + 1), CARD_2)
    if any(line.text.strip() for line in lines[2:]):
        r.data.warn(f"{lines[2].where}: *{r.keyword} {first['MID']}: the cards after the second (damage models: "
                    f"IDAM, GISSMO, DIEM, ...) are not read; only the effective plastic strain EFFEPS fails a point")
    if first["MID"] is None:
        raise KeywordError(f"{lines[0].where}: *{r.keyword} MID is blank; give the material it applies to")
    mid = int(first["MID"])
    erosions = read_erosions(r.data)
    if mid in erosions:
        raise KeywordError(f"{lines[0].where}: *{r.keyword} for material {mid} is given twice; keep one")
    erosions[mid] = [first, second]


def apply_erosion(mid: int, data: KeywordData, spec: MaterialSpec) -> None:
    """Material ``mid``'s *MAT_ADD_EROSION, if any, on ``spec``: |EFFEPS| (> 0) the failure plastic
    strain (the smaller of it and the material's own FAIL or FS), NUMFIP its failure_points; a
    warning for each active criterion that is not modelled, for a positive EFFEPS (LS-DYNA's
    effective total strain, read as the plastic one), for NCS > 1 and for a material without
    plastic strain."""
    cards = read_erosions(data).get(mid)
    if cards is None:
        return
    first, second = cards
    name = f"*MAT_ADD_EROSION {mid}"
    excl = float(first["EXCL"] or 0.0)

    def active(card: Record, field: str) -> float | None:
        value = card[field]
        return None if value is None or float(value) in (0.0, excl) else float(value)

    for card in (first, second):
        for field, meaning in UNMODELLED.items():
            if field in card.values and active(card, field) is not None:
                data.warn(f"{card.where}: {name} {field} = {card[field]} ({meaning} at failure) is not modelled and "
                          f"ignored: material {mid} fails only by its effective plastic strain (EFFEPS, FAIL, FS)")
    effeps = active(first, "EFFEPS")
    numfip = float(first["NUMFIP"] if first["NUMFIP"] is not None else 1.0)
    if numfip == excl and excl != 0.0:
        numfip = 1.0
    if effeps is None and "failure_strain" not in spec.extra:
        data.warn(f"{first.where}: {name} sets no EFFEPS and material {mid} has no failure strain of its own: "
                  f"nothing fails it (NUMFIP = {numfip:g} has no effect)")
        return
    if spec.model in ("elastic", "rigid"):
        data.warn(f"{first.where}: {name}: material {mid} is {spec.model}, it has no plastic strain, so EFFEPS "
                  f"never fails it")
        return
    if effeps is not None:
        if effeps > 0.0:
            data.warn(f"{first.where}: {name} EFFEPS = {effeps:g} is LS-DYNA's effective total strain at failure; "
                      f"ParaDyn fails a point when its effective plastic strain reaches {effeps:g} (later by about "
                      f"the elastic strain, yield stress / E); a negative EFFEPS says the plastic strain exactly")
        strain = abs(effeps)
        own = spec.extra.get("failure_strain")
        spec.extra["failure_strain"] = strain if own is None else min(strain, float(own))
    ncs = float(first["NCS"] or 1.0)
    if ncs > 1.0:
        data.warn(f"{first.where}: {name} NCS = {ncs:g}: ParaDyn models one criterion (the effective plastic "
                  f"strain), which fails a point alone")
    spec.extra["failure_points"] = numfip


def warn_unused_erosions(data: KeywordData, used: set[int]) -> None:
    """A warning for each *MAT_ADD_EROSION whose MID no *MAT defines, or no part uses: it acts on
    nothing."""
    for mid, (first, _) in sorted(read_erosions(data).items()):
        if mid not in data.materials:
            data.warn(f"{first.where}: *MAT_ADD_EROSION names material {mid}, which no *MAT defines; it is ignored")
        elif mid not in used:
            data.warn(f"{first.where}: *MAT_ADD_EROSION {mid}: no part uses material {mid}; it acts on nothing")


EROSION_READERS: dict[str, Callable[[_Reading], None]] = {
    "MAT_ADD_EROSION": _add_erosion, "MAT_ADD_EROSION_TITLE": _add_erosion,
}

__all__ = ["EROSION_READERS", "apply_erosion", "read_erosions", "warn_unused_erosions"]
