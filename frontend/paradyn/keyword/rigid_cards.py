"""The cards of rigid-body connections and given mass properties (docs/keyword.md, "Rigid
bodies"): *CONSTRAINED_NODAL_RIGID_BODY, *CONSTRAINED_SPOTWELD, *CONSTRAINED_GENERALIZED_WELD_SPOT
and *PART_INERTIA, read into cards.py's KeywordData (``welds``, ``parts``, ``part_inertia``); their
mapping to the model is keyword/rigid.py's.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .reader import Field, KeywordError, layout

# cards.py imports this module (its READERS take these), so its types are not imported back: a
# reader gets cards.py's _Reading
_Reading = Any

NODAL_RIGID_BODY = layout("int:PID int:CID int:NSID int:PNODE int:IPRT int:DRFLAG int:RRFLAG", pid=0, cid=0,
                          pnode=0, iprt=0, drflag=0, rrflag=0)
SPOTWELD = layout("int:N1 int:N2 SN SS N M TF EP", sn=0.0, ss=0.0, n=0.0, m=0.0, tf=1e20, ep=1e20)
WELD_SPOT = (layout("int:WID int:NSID int:CID int:FILTER int:WINDOW int:NPR int:NPRT", wid=0, cid=0, filter=0,
                    window=0, npr=0, nprt=0),
             layout("TFAIL EPSF SN SS N M", tfail=1e20, epsf=1e20, sn=0.0, ss=0.0, n=0.0, m=0.0))
# *PART_INERTIA: cards 3, 4, 5 after the part's two, and 5a where IRCS = 1
PART_INERTIA = (layout("XC YC ZC TM int:IRCS int:NODEID", xc=0.0, yc=0.0, zc=0.0, ircs=0, nodeid=0),
                layout("IXX IXY IXZ IYY IYZ IZZ", ixy=0.0, ixz=0.0, iyz=0.0),
                layout("VTX VTY VTZ VRX VRY VRZ", vtx=0.0, vty=0.0, vtz=0.0, vrx=0.0, vry=0.0, vrz=0.0),
                layout("XL YL ZL XLIP YLIP ZLIP int:CID", cid=0))


def _weld(kind: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        lines = [line for line in r.lines() if line.text.strip()]
        if kind == "SPOTWELD" and r.keyword.endswith("_ID"):
            lines = lines[1::2]   # each weld's ID card, then its card
        if kind == "GENERALIZED":
            for first, second in zip(lines[::2], lines[1::2], strict=False):
                record = r.card(first, WELD_SPOT[0])
                record.values.update(r.card(second, WELD_SPOT[1]).values)
                r.data.welds.append((kind, record))
            return
        card = NODAL_RIGID_BODY if kind == "NODAL" else SPOTWELD
        for line in lines:
            r.data.welds.append((kind, r.card(line, card)))
    return read


def part_inertia_reader(part: tuple[Field, ...]) -> Callable[[_Reading], None]:
    """The reader of *PART_INERTIA, whose first two cards are ``part``'s (*PART's)."""
    return lambda r: _part_inertia(r, part)


def _part_inertia(r: _Reading, part: tuple[Field, ...]) -> None:
    """*PART_INERTIA: the part's two cards (as *PART), then its mass properties (cards 3 to 5, and
    5a where IRCS = 1), group after group."""
    lines = r.lines()
    k = 0
    while k + 4 < len(lines):
        record = r.card(lines[k + 1], part, {"EOSID": 0, "GRAV": 0, "ADPOPT": 0, "TMID": 0})
        record.values["HEADING"] = lines[k].text.strip()
        r.data.parts.append(record)
        inertia = r.card(lines[k + 2], PART_INERTIA[0])
        for line, card in zip(lines[k + 3:k + 5], PART_INERTIA[1:3], strict=True):
            inertia.values.update(r.card(line, card).values)
        k += 5
        if int(inertia["IRCS"] or 0) == 1:
            if k >= len(lines):
                raise KeywordError(f"{inertia.where}: *PART_INERTIA part {record['PID']} has IRCS = 1 but no card 5a "
                                   f"(XL YL ZL XLIP YLIP ZLIP CID); give it, or the tensor in global axes (IRCS = 0)")
            inertia.values.update(r.card(lines[k], PART_INERTIA[3]).values)
            k += 1
        r.data.part_inertia[int(record["PID"])] = inertia
    if k != len(lines):
        raise KeywordError(f"{lines[k].where}: *PART_INERTIA ends with {len(lines) - k} card(s) of an incomplete "
                           f"part; give each part its 5 cards (6 with IRCS = 1)")


WELD_READERS: dict[str, Callable[[_Reading], None]] = {
    "CONSTRAINED_NODAL_RIGID_BODY": _weld("NODAL"),
    "CONSTRAINED_SPOTWELD": _weld("SPOTWELD"), "CONSTRAINED_SPOTWELD_ID": _weld("SPOTWELD"),
    "CONSTRAINED_GENERALIZED_WELD_SPOT": _weld("GENERALIZED"),
}
